//! What a run keeps: the saved modal history, and what a failed run keeps of it.

use crate::error::CoreError;

/// The saved state coordinates: which ones depends on the background propagator.
#[derive(Debug, Clone, PartialEq)]
pub enum Coordinates {
    /// Modal coordinates and velocities of the uncoupled oscillators, `n_saved x n_modes`
    /// each, time-major.
    Modal { q: Vec<f64>, v: Vec<f64> },
    /// First-order (complex) modal coordinates of a coupled run, `n_saved x 2 r`: the real
    /// parts then the imaginary parts of each row (see [`crate::background::first_order`]).
    FirstOrder { eta: Vec<f64>, width: usize },
}

impl Default for Coordinates {
    fn default() -> Self {
        Coordinates::Modal {
            q: Vec::new(),
            v: Vec::new(),
        }
    }
}

/// Saved modal history. Arrays are time-major: entry `(s, j)` at `s * width + j`.
///
/// Modal accelerations are not stored: they follow exactly from the equation of motion,
/// `a = p - c v - k q + pseudo`, with the modal load `p = sum_l pattern_l load_values[s, l] +
/// forcing`; recovering them afterwards for the wanted degrees of freedom only keeps the time
/// loop within the machine's memory bandwidth.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct History {
    /// Number of (real) modes.
    pub n_modes: usize,
    /// Number of built-in loads.
    pub n_loads: usize,
    /// Number of mapped outputs.
    pub n_outputs: usize,
    /// Saved times.
    pub t: Vec<f64>,
    /// The saved state.
    pub coordinates: Coordinates,
    /// Value of each built-in load's time function at the saved times (the value just after
    /// each saved time), `n_saved x n_loads`.
    pub load_values: Vec<f64>,
    /// Modal external forcing at the saved times, `n_saved x n_modes`, if there is any.
    pub forcing: Option<Vec<f64>>,
    /// Modal pseudo-force (everything not in the background) at the saved states,
    /// `n_saved x n_modes`, for routes with a corrector.
    pub pseudo: Option<Vec<f64>>,
    /// Outputs mapped from the coordinates during the run, `n_saved x n_cols`, if asked for.
    pub outputs: Option<Vec<f64>>,
    /// The elements' local states and restoring forces at the saved instants, for routes
    /// that evaluate elements.
    pub elements: Option<ElementRows>,
    /// The energy integrals accumulated during the run at the saved instants, when asked for
    /// ([`crate::energy`]).
    pub energy: Option<crate::energy::EnergyRows>,
    /// The elements' committed internal variables at the end of the run (hysteretic
    /// elements; what a continued run starts from).
    pub element_state: Option<Vec<f64>>,
    /// The growth guard's accumulated bounds at the end of the run
    /// ([`crate::pseudo::GrowthGuard::state`]; what a continued run starts from), if guarded.
    pub guard_state: Option<Vec<f64>>,
}

/// The elements' local displacements, velocities and restoring forces at the saved
/// instants, each `n_saved x width` (`width` the sum of the elements' local dofs, the
/// elements in order). A hysteretic element's force is its committed one: the force of the
/// path the run followed.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ElementRows {
    pub width: usize,
    /// Local dofs of each element (they sum to `width`).
    pub widths: Vec<usize>,
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub r: Vec<f64>,
}

impl History {
    /// Number of saved instants.
    pub fn n_saved(&self) -> usize {
        self.t.len()
    }

    /// Modal coordinates (empty for a first-order history).
    pub fn q(&self) -> &[f64] {
        match &self.coordinates {
            Coordinates::Modal { q, .. } => q,
            Coordinates::FirstOrder { .. } => &[],
        }
    }

    /// Modal velocities (empty for a first-order history).
    pub fn v(&self) -> &[f64] {
        match &self.coordinates {
            Coordinates::Modal { v, .. } => v,
            Coordinates::FirstOrder { .. } => &[],
        }
    }

    /// Keeps the first `keep` saved instants.
    pub(crate) fn truncate(&mut self, keep: usize) {
        let rows = self.t.len().max(1);
        let cut = |v: &mut Vec<f64>| {
            let width = v.len() / rows;
            v.truncate(keep * width);
        };
        match &mut self.coordinates {
            Coordinates::Modal { q, v } => {
                cut(q);
                cut(v);
            }
            Coordinates::FirstOrder { eta, .. } => cut(eta),
        }
        cut(&mut self.load_values);
        for v in [&mut self.forcing, &mut self.pseudo, &mut self.outputs]
            .into_iter()
            .flatten()
        {
            cut(v);
        }
        if let Some(e) = &mut self.energy {
            e.values.truncate(keep * e.n_cols);
        }
        if let Some(e) = &mut self.elements {
            for v in [&mut e.x, &mut e.v, &mut e.r] {
                v.truncate(keep * e.width);
            }
        }
        self.t.truncate(keep);
    }
}

/// A run that stopped early: the reason and everything computed before it (a modal
/// [`History`], or another integrator's history type).
#[derive(Debug, Clone)]
pub struct Failure<H = History> {
    /// Why the run stopped.
    pub error: CoreError,
    /// The history up to the last good saved instant.
    pub partial: H,
    /// The run's statistics up to the failure (Newton iterations, the steps retried in
    /// halves), when the route counts them.
    pub stats: Stats,
}

impl<H: Default> From<CoreError> for Failure<H> {
    fn from(error: CoreError) -> Self {
        Failure {
            error,
            partial: H::default(),
            stats: Stats::default(),
        }
    }
}

/// A zeroed buffer of `len` values, or a clean error naming what to change when the memory
/// cannot be had (instead of an abort). `what` says what the buffer holds, for the message.
///
/// The buffer comes from `alloc_zeroed` (fresh, lazily zeroed pages for large sizes, no
/// memset) and is advised to use transparent huge pages: a history of a few hundred MB would
/// otherwise cost one page fault per 4 KiB written inside the time loop.
pub fn zeroed(len: usize, what: &str) -> Result<Vec<f64>, CoreError> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let too_big = || CoreError::InvalidInput {
        name: "save_every",
        problem: format!(
            "is too small for this run: {what} needs {:.3} GiB that cannot be allocated; save \
             fewer steps (a larger `save_every` or a shorter `t_end`), fewer `dofs` or fewer modes",
            len as f64 * 8.0 / (1u64 << 30) as f64
        ),
    };
    let layout = std::alloc::Layout::array::<f64>(len).map_err(|_| too_big())?;
    // SAFETY: `layout` has a non-zero size (len > 0).
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f64>();
    if ptr.is_null() {
        return Err(too_big());
    }
    advise_huge_pages(ptr, len);
    // SAFETY: `ptr` was allocated by the global allocator with the layout of `[f64; len]`
    // (capacity `len`, alignment of f64), as `Vec` requires; its bytes are all zero, a valid
    // `0.0_f64` for each of the `len` elements, so the length `len` is initialised.
    Ok(unsafe { Vec::from_raw_parts(ptr, len, len) })
}

/// Checks that a run's saved history — `values` numbers in all, over its buffers — fits in
/// the machine's memory, before any of it is allocated; refuses it otherwise with what it
/// needs and what to change. (An allocation that passes this and still fails is refused by
/// [`zeroed`].)
pub fn reserve(values: usize) -> Result<(), CoreError> {
    let bytes = values as f64 * 8.0;
    let available = physical_memory();
    if bytes > available {
        let gib = |b: f64| b / (1u64 << 30) as f64;
        return Err(CoreError::InvalidInput {
            name: "save_every",
            problem: format!(
                "is too small for this run: its saved history needs {:.3} GiB, more than the \
                 machine's {:.1} GiB of memory; save fewer steps (a larger `save_every` or a \
                 shorter `t_end`), fewer `dofs` or fewer modes",
                gib(bytes),
                gib(available)
            ),
        });
    }
    Ok(())
}

/// Refuses working buffers of `values` numbers (the dense matrices of a solver, sized by the
/// number of modes) that the machine's memory cannot hold, before they are allocated: an
/// allocation failure aborts the process, an error does not.
pub fn working(values: f64, what: &str) -> Result<(), CoreError> {
    let bytes = values * 8.0;
    let available = physical_memory();
    if bytes > available {
        let gib = |b: f64| b / (1u64 << 30) as f64;
        return Err(CoreError::InvalidInput {
            name: "modes",
            problem: format!(
                "is too large for {what}: its dense matrices need {:.3} GiB, more than the \
                 machine's {:.1} GiB of memory; keep fewer modes",
                gib(bytes),
                gib(available)
            ),
        });
    }
    Ok(())
}

/// The machine's physical memory in bytes (unbounded where it cannot be read), read once
/// per process (glibc answers `_SC_PHYS_PAGES` with a `sysinfo` system call: 3 % of a short
/// run's call when it was asked on every run).
#[cfg(target_os = "linux")]
fn physical_memory() -> f64 {
    static MEMORY: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *MEMORY.get_or_init(|| {
        // SAFETY: sysconf only reads system configuration; it has no preconditions.
        let (pages, size) = unsafe {
            (
                libc::sysconf(libc::_SC_PHYS_PAGES),
                libc::sysconf(libc::_SC_PAGESIZE),
            )
        };
        if pages > 0 && size > 0 {
            pages as f64 * size as f64
        } else {
            f64::INFINITY
        }
    })
}

#[cfg(not(target_os = "linux"))]
fn physical_memory() -> f64 {
    f64::INFINITY
}

/// `rows * cols` without overflow, or the error of [`zeroed`] for a buffer too large.
pub fn size(rows: usize, cols: usize, what: &str) -> Result<usize, CoreError> {
    rows.checked_mul(cols)
        .filter(|&n| n <= isize::MAX as usize / 8)
        .ok_or_else(|| CoreError::InvalidInput {
            name: "save_every",
            problem: format!(
                "is too small for this run: {what} needs {rows} x {cols} values, more than can \
                 be addressed; save fewer steps (a larger `save_every` or a shorter `t_end`)"
            ),
        })
}

/// Asks Linux to back the 2 MiB-aligned interior of a buffer with transparent huge pages.
#[cfg(target_os = "linux")]
fn advise_huge_pages(ptr: *mut f64, len: usize) {
    const HUGE: usize = 2 << 20;
    let start = ptr as usize;
    let end = start + len * std::mem::size_of::<f64>();
    let first = start.next_multiple_of(HUGE);
    let last = end - end % HUGE;
    if last > first {
        // SAFETY: [first, last) lies inside the live allocation [start, end) and is page
        // aligned; MADV_HUGEPAGE is advisory and never changes the contents or validity of
        // the memory. A failure (e.g. THP disabled) is harmless and ignored.
        unsafe {
            libc::madvise(
                first as *mut libc::c_void,
                last - first,
                libc::MADV_HUGEPAGE,
            );
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_ptr: *mut f64, _len: usize) {}

/// Run statistics of every route, modal (with a corrector) and direct: what a route does
/// not do stays 0.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Newton iterations over the run (0 when every step equation is linear and solved
    /// directly).
    pub newton_iterations: usize,
    /// Steps solved by the closed-form cubic.
    pub closed_form_steps: usize,
    /// Factorisations of a kept iteration matrix (modified Newton of the first-order
    /// corrector; the direct integrators' iteration matrix, the mass matrix factorised once
    /// for the initial acceleration not counted).
    pub factorizations: usize,
    /// Steps whose equation did not converge and that were retried in halves.
    pub subdivided_steps: usize,
    /// The deepest subdivision reached (substeps of `dt / 2^depth`).
    pub subdivision_depth: usize,
}
