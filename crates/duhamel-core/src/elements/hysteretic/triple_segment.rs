//! One element of the triple friction pendulum's series model ([`super::triple`]): a
//! bidirectional elastoplastic element with linear kinematic hardening (radial return from
//! the committed plastic displacement, OpenSees' `BidirectionalPlastic`) in parallel with a
//! circular stop (`CircularElasticGap`), normalised by the vertical load.

pub(super) type V2 = [f64; 2];
pub(super) type M2 = [f64; 4];

/// One element of the series model (normalised by `W`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Segment {
    /// Yield force (the friction coefficient).
    pub fy: f64,
    /// Elastic (and gap) stiffness.
    pub e: f64,
    /// Kinematic hardening modulus.
    pub h: f64,
    /// The gap (restrainer) radius.
    pub gap: f64,
}

/// A segment's force, tangent, plastic displacement and potential at a displacement.
pub(super) struct SegmentState {
    pub f: V2,
    pub k: M2,
    pub ep: V2,
    pub energy: f64,
}

fn outer(a: V2, b: V2) -> M2 {
    [a[0] * b[0], a[0] * b[1], a[1] * b[0], a[1] * b[1]]
}

pub(super) fn inverse(k: M2) -> M2 {
    let det = k[0] * k[3] - k[1] * k[2];
    [k[3] / det, -k[1] / det, -k[2] / det, k[0] / det]
}

impl Segment {
    /// The tangent at the committed state `(d, ep)` for continued loading: sliding
    /// (`E I - (E - Ep) n n^T`) when the state is on its yield surface, elastic otherwise;
    /// plus the stop's.
    pub(super) fn loading_tangent(&self, d: V2, ep: V2) -> M2 {
        let Segment { fy, e, h, gap } = *self;
        let z = [d[0] - ep[0] - h * ep[0] / e, d[1] - ep[1] - h * ep[1] / e];
        let r = z[0].hypot(z[1]);
        let mut k = [e, 0.0, 0.0, e];
        if r >= (1.0 - 1e-9) * fy / e && r > 0.0 {
            let n = [z[0] / r, z[1] / r];
            let soft = e - e * h / (e + h);
            let nn = outer(n, n);
            k = [
                e - soft * nn[0],
                -soft * nn[1],
                -soft * nn[2],
                e - soft * nn[3],
            ];
        }
        let rd = d[0].hypot(d[1]);
        if rd > gap {
            let c = [d[0] / rd, d[1] / rd];
            let cc = outer(c, c);
            let a = gap / rd;
            k[0] += e * (1.0 - a + a * cc[0]);
            k[1] += e * a * cc[1];
            k[2] += e * a * cc[2];
            k[3] += e * (1.0 - a + a * cc[3]);
        }
        k
    }

    /// The state at displacement `d` from the committed plastic displacement `ep_c` (the
    /// back force is `H ep`).
    pub(super) fn eval(&self, d: V2, ep_c: V2) -> SegmentState {
        let Segment { fy, e, h, gap } = *self;
        let q = [h * ep_c[0], h * ep_c[1]];
        let z = [d[0] - ep_c[0] - q[0] / e, d[1] - ep_c[1] - q[1] / e];
        let r = z[0].hypot(z[1]);
        let ry = fy / e;
        let mut s = if r <= ry {
            SegmentState {
                f: [q[0] + e * z[0], q[1] + e * z[1]],
                k: [e, 0.0, 0.0, e],
                ep: ep_c,
                energy: q[0] * z[0] + q[1] * z[1] + 0.5 * e * r * r,
            }
        } else {
            let n = [z[0] / r, z[1] / r];
            let phi = e * (h * r + fy) / (e + h);
            let slope = e * h / (e + h);
            let secant = phi / r;
            let nn = outer(n, n);
            let dlam = (e * r - fy) / (e + h);
            SegmentState {
                f: [q[0] + phi * n[0], q[1] + phi * n[1]],
                k: [
                    secant + (slope - secant) * nn[0],
                    (slope - secant) * nn[1],
                    (slope - secant) * nn[2],
                    secant + (slope - secant) * nn[3],
                ],
                ep: [ep_c[0] + dlam * n[0], ep_c[1] + dlam * n[1]],
                energy: q[0] * z[0]
                    + q[1] * z[1]
                    + fy * fy / (2.0 * e)
                    + (0.5 * e * h * (r * r - ry * ry) + e * fy * (r - ry)) / (e + h),
            }
        };
        let rd = d[0].hypot(d[1]);
        if rd > gap {
            let c = [d[0] / rd, d[1] / rd];
            let open = rd - gap;
            let cc = outer(c, c);
            let a = gap / rd;
            s.f[0] += e * open * c[0];
            s.f[1] += e * open * c[1];
            s.k[0] += e * (1.0 - a + a * cc[0]);
            s.k[1] += e * a * cc[1];
            s.k[2] += e * a * cc[2];
            s.k[3] += e * (1.0 - a + a * cc[3]);
            s.energy += 0.5 * e * open * open;
        }
        s
    }
}
