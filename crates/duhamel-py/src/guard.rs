//! The one place where a Rust panic becomes a Python exception.
//!
//! Bad input never panics: the core and the binding check it and raise `ValueError` or
//! `TypeError` naming the parameter. A panic that still happens is a bug in duhamel: every
//! entry point that runs engine code calls it through [`guarded`], which catches the unwind
//! (also one resumed from a rayon worker or a scoped thread, which propagate their panic to
//! the thread that joins them) and raises `duhamel.errors.InternalError` with the panic's
//! message and location. Without this, pyo3 would raise its `PanicException`, a
//! `BaseException` that `except Exception` does not catch. The release profile keeps
//! `panic = "unwind"` (Cargo.toml): with `abort` no panic could be caught.

use std::any::Any;
use std::collections::VecDeque;
use std::panic::{self, AssertUnwindSafe};
use std::sync::{Mutex, Once};

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// Panics seen by the hook, numbered: `(number, "message (at file:line)")`, the last few only.
/// A caught panic's payload carries its message only, and a panic that crossed a scoped
/// thread comes back as "a scoped thread panicked": these say what first went wrong, where.
static PANICS: Mutex<(u64, VecDeque<(u64, String)>)> = Mutex::new((0, VecDeque::new()));
/// How many panics [`PANICS`] keeps.
const KEPT: usize = 8;

fn panics() -> std::sync::MutexGuard<'static, (u64, VecDeque<(u64, String)>)> {
    PANICS.lock().unwrap_or_else(|p| p.into_inner())
}

/// Replaces the default panic hook (which prints the message and, with `RUST_BACKTRACE`, a
/// backtrace to stderr, noise for a panic that becomes an exception) by one that records
/// the message and where the panic happened, for the exception. With `RUST_BACKTRACE` set
/// (and not `0`), the default hook prints as well.
pub(crate) fn install_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let default = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            let mut text = payload_message(info.payload());
            if let Some(l) = info.location() {
                text += &format!(" (at {}:{})", l.file(), l.line());
            }
            {
                let mut seen = panics();
                seen.0 += 1;
                let number = seen.0;
                if seen.1.len() == KEPT {
                    seen.1.pop_front();
                }
                seen.1.push_back((number, text));
            }
            if std::env::var_os("RUST_BACKTRACE").is_some_and(|v| v != "0") {
                default(info);
            }
        }));
    });
}

/// The text of a panic payload (`panic!` with a literal or with a format string).
fn payload_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// `duhamel.errors.InternalError` for a caught panic, with the panics recorded since panic
/// number `since` (a `RuntimeError` if that class cannot be had).
fn internal_error(payload: &(dyn Any + Send), since: u64) -> PyErr {
    let seen: Vec<String> = panics()
        .1
        .iter()
        .filter(|(number, _)| *number > since)
        .map(|(_, text)| text.clone())
        .collect();
    let what = if seen.is_empty() {
        payload_message(payload)
    } else {
        seen.join("; then ")
    };
    let text = format!(
        "internal error in duhamel's native core: {what}. This is a bug in duhamel, not in \
         your input: please report it, with the input that raised it"
    );
    // Entry points hold the GIL already: this only gets the token.
    Python::attach(|py| {
        py.import("duhamel.errors")
            .and_then(|m| m.getattr("InternalError"))
            .and_then(|cls| cls.call1((text.clone(),)))
            .map_or_else(|_| PyRuntimeError::new_err(text.clone()), PyErr::from_value)
    })
}

/// Runs `f` (an entry point's body, engine code included), turning a panic into
/// `duhamel.errors.InternalError`.
///
/// The state `f` touched is dropped with the failed call (nothing it built outlives it), so
/// asserting unwind safety is sound.
pub(crate) fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    let since = panics().0;
    match panic::catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(payload) => Err(internal_error(payload.as_ref(), since)),
    }
}

/// Test only (`_core._panic_for_tests`): panics on purpose, to check that a panic comes out
/// as `InternalError`: `"here"` on the calling thread, `"detached"` with the GIL released,
/// `"rayon"` inside a worker of a rayon pool, `"thread"` in a scoped thread.
#[pyfunction]
pub(crate) fn _panic_for_tests(py: Python<'_>, kind: &str) -> PyResult<()> {
    use rayon::prelude::*;
    guarded(|| match kind {
        "here" => panic!("forced panic (test)"),
        "detached" => py.detach(|| panic!("forced panic with the GIL released (test)")),
        "rayon" => py.detach(|| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(2)
                .build()
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            pool.install(|| {
                (0..64_usize).into_par_iter().for_each(|i| {
                    if i == 37 {
                        panic!("forced panic in a rayon worker (test, item {i})");
                    }
                })
            });
            Ok(())
        }),
        "thread" => {
            std::thread::scope(|s| {
                s.spawn(|| panic!("forced panic in a scoped thread (test)"));
            });
            Ok(())
        }
        other => Err(PyValueError::new_err(format!(
            "`kind` must be 'here', 'detached', 'rayon' or 'thread', got {other:?}"
        ))),
    })
}
