//! The elements' deformations: a space whose every member is a scalar two-node element (a
//! `Bilinear`: force `F(u)` on the deformation `u = x_i - x_j`, `x_i` when grounded,
//! acting as `+F` on `i` and `-F` on `j`) is seen by its elements only through the `n_e`
//! deformations `e = B u` and acted on only through `B^T f`. The element-space step then
//! solves for the deformations (`n_e` unknowns, one per element) instead of the `n_d` element
//! dofs (two per hinge, fewer where hinges share a joint): a frame's 16 rotational hinges on
//! 32 dofs iterate on 16 unknowns, a quarter of the elimination's work.
//!
//! An element evaluated at the local state `x = (e, 0)` computes the deformation `e - 0 = e`
//! exactly, so its force, tangents and trial variables are those at any `x` with
//! `x_i - x_j = e` bit for bit; `e = u_i - u_j` from the element coordinates `u` is the very
//! subtraction the element performs on `x = (u_i, u_j)`.

use super::ElementSpace;
use crate::elements::{Element, Runtime, Shifted};
use crate::error::CoreError;

/// The deformations of a space of scalar two-node elements: per member its dofs' positions
/// in `D` (`j` absent when grounded), and `Phi_E = B Phi_D` (row-major `n_e x n_modes`).
pub(super) struct Deformations {
    pairs: Vec<(usize, Option<usize>)>,
    phi: Vec<f64>,
}

/// Whether `element` is a scalar two-node element: a `Bilinear`, itself or with a linear
/// part on its deformation alone taken out ([`Shifted::relative`]).
fn scalar(element: &dyn Element) -> bool {
    let bilinear = |e: &dyn Element| {
        let runtime = e.as_any().and_then(|a| a.downcast_ref::<Runtime>());
        runtime.is_some_and(|r| r.scalar_law().is_some())
    };
    let shifted = element.as_any().and_then(|a| a.downcast_ref::<Shifted>());
    bilinear(element) || shifted.is_some_and(|s| s.relative() && bilinear(s.inner()))
}

impl Deformations {
    /// The deformations of `members` (each with its local dofs' positions `at` in `D`) for
    /// `Phi_D` (`n_d x n`), when every member is a scalar two-node element and at least one
    /// has two dofs (otherwise the deformations are the element dofs themselves: None).
    pub(super) fn of<'m>(
        members: impl Iterator<Item = (&'m dyn Element, &'m [usize])>,
        phi_d: &[f64],
        n: usize,
    ) -> Option<Self> {
        let mut pairs = Vec::new();
        for (element, at) in members {
            let scalar = scalar(element);
            match (scalar, at) {
                (true, [i]) => pairs.push((*i, None)),
                (true, [i, j]) => pairs.push((*i, Some(*j))),
                _ => return None,
            }
        }
        if pairs.iter().all(|p| p.1.is_none()) {
            return None;
        }
        let row = |a: usize| &phi_d[a * n..(a + 1) * n];
        let phi = pairs
            .iter()
            .flat_map(|&(i, j)| {
                let (ri, rj) = (row(i), j.map(row));
                (0..n).map(move |m| match rj {
                    Some(rj) => ri[m] - rj[m],
                    None => ri[m],
                })
            })
            .collect();
        Some(Deformations { pairs, phi })
    }
}

impl ElementSpace<'_> {
    /// `n_e`, the number of deformations, when the space is one of scalar two-node elements
    /// with fewer deformations than element dofs ([`Deformations::of`]); None otherwise.
    pub fn deformation_count(&self) -> Option<usize> {
        self.deform.as_ref().map(|d| d.pairs.len())
    }

    fn deform(&self) -> &Deformations {
        self.deform.as_ref().expect("a space of deformations")
    }

    /// `out = B u`: each member's deformation `u_i - u_j` (`u_i` grounded) from the element
    /// coordinates `u` (`n_d`).
    pub fn to_deformation(&self, u: &[f64], out: &mut [f64]) {
        for (o, &(i, j)) in out.iter_mut().zip(&self.deform().pairs) {
            *o = match j {
                Some(j) => u[i] - u[j],
                None => u[i],
            };
        }
    }

    /// `out = B^T f` (`n_d`, overwritten): the element forces on the element dofs, summed
    /// member by member as [`ElementSpace::eval`] assembles them.
    pub fn scatter_deformation(&self, f: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (&fm, &(i, j)) in f.iter().zip(&self.deform().pairs) {
            out[i] += fm;
            if let Some(j) = j {
                out[j] -= fm;
            }
        }
    }

    /// `(B P)` from `P` (`n_d x n`, row-major) into `out` (`n_e x n`).
    pub fn rows_to_deformation(&self, p: &[f64], n: usize, out: &mut [f64]) {
        let row = |a: usize| &p[a * n..(a + 1) * n];
        for (o, &(i, j)) in out.chunks_exact_mut(n).zip(&self.deform().pairs) {
            match j {
                Some(j) => {
                    for ((x, a), b) in o.iter_mut().zip(row(i)).zip(row(j)) {
                        *x = a - b;
                    }
                }
                None => o.copy_from_slice(row(i)),
            }
        }
    }

    /// `B G B^T` (`n_e x n_e`) of `G` (`n_d x n_d`, row-major) into `out`.
    pub fn square_to_deformation(&self, g: &[f64], nd: usize, out: &mut [f64]) {
        let pairs = &self.deform().pairs;
        let ne = pairs.len();
        let side = |(i, j): (usize, Option<usize>), c: usize| match j {
            Some(j) => g[i * nd + c] - g[j * nd + c],
            None => g[i * nd + c],
        };
        for (m, &pm) in pairs.iter().enumerate() {
            for (k, &(c, d)) in pairs.iter().enumerate() {
                out[m * ne + k] = match d {
                    Some(d) => side(pm, c) - side(pm, d),
                    None => side(pm, c),
                };
            }
        }
    }

    /// `out = Phi_E^T f = Phi_D^T B^T f` (length `n_modes`, overwritten).
    pub fn project_deformation(&self, f: &[f64], out: &mut [f64]) {
        let n = self.n_modes;
        out.fill(0.0);
        let rows = f.iter().zip(self.deform().phi.chunks_exact(n));
        add_rows(
            out,
            rows.filter(|(fm, _)| **fm != 0.0)
                .map(|(fm, row)| (*fm, row)),
        );
    }

    /// The members' forces `f` (`n_e`) at the deformations `e` and their rates `ed` at time
    /// `t`; with `tangent`, `df/de` and `df/de'` per member (`n_e` each, the deformations are
    /// uncoupled). Each member is evaluated at `x = (e, 0)`, `v = (ed, 0)`.
    pub fn eval_deformation(
        &mut self,
        (e, ed): (&[f64], &[f64]),
        t: f64,
        f: &mut [f64],
        mut tangent: Option<(&mut [f64], &mut [f64])>,
    ) -> Result<(), CoreError> {
        for (m, member) in self.members.iter_mut().enumerate() {
            let state = (e[m], ed[m]);
            let (r, kx, cv) = member
                .eval
                .evaluate_deformation(state, t, tangent.is_some())?;
            f[m] = r;
            if let Some((k, c)) = tangent.as_mut() {
                (k[m], c[m]) = (kx, cv);
            }
        }
        Ok(())
    }
}

/// `out += c_k row_k` for each term in order, four terms per pass over `out` (each entry's
/// additions the same, in the same order, as one term at a time).
pub(super) fn add_rows<'r>(out: &mut [f64], mut terms: impl Iterator<Item = (f64, &'r [f64])>) {
    loop {
        match (terms.next(), terms.next(), terms.next(), terms.next()) {
            (Some((f0, r0)), Some((f1, r1)), Some((f2, r2)), Some((f3, r3))) => {
                let rows = r0.iter().zip(r1).zip(r2).zip(r3);
                for (o, (((a, b), c), d)) in out.iter_mut().zip(rows) {
                    *o = (((*o + f0 * a) + f1 * b) + f2 * c) + f3 * d;
                }
            }
            (a, b, c, _) => {
                for (fm, row) in [a, b, c].into_iter().flatten() {
                    for (o, p) in out.iter_mut().zip(row) {
                        *o += fm * p;
                    }
                }
                return;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::ElementSpace;
    use crate::elements::hysteretic::bilinear::Bilinear;
    use crate::elements::{Element, Runtime, Shifted};

    fn bilinear(i: usize, j: Option<usize>) -> Runtime {
        Runtime::Bilinear(Bilinear::new(i, j, 100.0, 1.0, 0.05).unwrap())
    }

    /// `Phi` of 3 dofs and 2 modes.
    const PHI: [f64; 6] = [0.3, -1.1, 0.7, 0.2, -0.4, 0.9];

    #[test]
    fn a_pair_and_a_grounded_bilinear_are_seen_through_their_deformations() {
        let (a, b) = (bilinear(0, Some(2)), bilinear(1, None));
        let elements: Vec<&dyn Element> = vec![&a, &b];
        let mut space = ElementSpace::new(&PHI, 2, &elements);
        assert_eq!(space.deformation_count(), Some(2));
        // the element dofs D = [0, 1, 2]: e = (u0 - u2, u1)
        let (u, ud) = ([0.004, -0.02, 0.013], [0.1, 0.2, -0.3]);
        let (mut e, mut ed) = ([0.0; 2], [0.0; 2]);
        space.to_deformation(&u, &mut e);
        space.to_deformation(&ud, &mut ed);
        assert_eq!(e, [0.004 - 0.013, -0.02]);
        // the forces and tangents at e are those the dof space assembles at u, bit for bit
        let (mut f, mut kd, mut cd) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        space.commit(&[0.0; 2], &[0.0; 2], 0.0, true).unwrap();
        space
            .eval_deformation((&e, &ed), 0.0, &mut f, Some((&mut kd, &mut cd)))
            .unwrap();
        let (mut r, mut k, mut c) = ([0.0; 3], [0.0; 9], [0.0; 9]);
        space
            .eval(&u, &ud, 0.0, &mut r, Some((&mut k, &mut c)))
            .unwrap();
        let mut scattered = [0.0; 3];
        space.scatter_deformation(&f, &mut scattered);
        assert_eq!(scattered, r);
        assert_eq!((kd[0], kd[1]), (k[0], k[4]));
        assert_eq!(cd, [0.0; 2]);
        // Phi_E^T f = Phi_D^T B^T f up to rounding
        let (mut t_e, mut t_d) = ([0.0; 2], [0.0; 2]);
        space.project_deformation(&f, &mut t_e);
        space.project(&r, &mut t_d);
        for (x, y) in t_e.iter().zip(&t_d) {
            assert!((x - y).abs() <= 1e-15 * y.abs().max(1.0), "{x} {y}");
        }
    }

    #[test]
    fn other_elements_keep_the_element_dofs() {
        // grounded only: the deformations are the dofs themselves
        let (a, b) = (bilinear(0, None), bilinear(1, None));
        let elements: Vec<&dyn Element> = vec![&a, &b];
        assert_eq!(
            ElementSpace::new(&PHI, 2, &elements).deformation_count(),
            None
        );
        // a linear part that is not on the deformation alone
        // (as the binding builds it: around a boxed trait object)
        let pair = |k0: Vec<f64>| {
            let inner: Box<dyn Element> = Box::new(bilinear(0, Some(2)));
            Shifted::new(inner, k0, vec![0.0; 4])
        };
        let relative = pair(vec![100.0, -100.0, -100.0, 100.0]).unwrap();
        let other = pair(vec![100.0, -100.0, -100.0, 50.0]).unwrap();
        assert!(relative.relative() && !other.relative());
        let elements: Vec<&dyn Element> = vec![&relative];
        assert_eq!(
            ElementSpace::new(&PHI, 2, &elements).deformation_count(),
            Some(1)
        );
        let elements: Vec<&dyn Element> = vec![&relative, &other];
        assert_eq!(
            ElementSpace::new(&PHI, 2, &elements).deformation_count(),
            None
        );
    }
}
