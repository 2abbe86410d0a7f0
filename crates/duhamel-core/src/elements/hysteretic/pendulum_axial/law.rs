//! The friction pendulum's law with its normal force from the model: the friction
//! coefficient (constant, velocity- and pressure-dependent, OpenSees' `Coulomb`,
//! `VelDependent` and `VelPressureDep`) and the bearing's response at a trial state
//! (uplift, sticking, sliding) with its consistent tangents, in the local coordinates
//! `(u_x, u_y, w)` (`u_y = 0` for a uniaxial bearing).

/// The friction coefficient `mu(s, N)` at the sliding speed `s` and normal force `N`:
/// `mu_f(N) - (mu_f(N) - mu_slow) exp(-rate s)` with `mu_f(N) = mu_fast - delta_mu
/// tanh(alpha N / A)` (`N > 0`; `mu_fast` without pressure dependence), `mu_f(N)` without
/// velocity dependence.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Coefficient {
    pub mu_fast: f64,
    /// `(mu_slow, rate)`.
    pub velocity: Option<(f64, f64)>,
    /// `(area A, delta_mu, alpha)`.
    pub pressure: Option<(f64, f64, f64)>,
}

impl Coefficient {
    /// `(mu, dmu/ds, dmu/dN)`.
    pub fn at(&self, s: f64, n: f64) -> (f64, f64, f64) {
        let (mu_f, dmuf_dn) = match self.pressure {
            Some((area, delta, alpha)) if n > 0.0 => {
                let th = (alpha * n / area).tanh();
                (
                    self.mu_fast - delta * th,
                    -delta * alpha / area * (1.0 - th * th),
                )
            }
            _ => (self.mu_fast, 0.0),
        };
        match self.velocity {
            None => (mu_f, 0.0, dmuf_dn),
            Some((slow, rate)) => {
                let e = (-rate * s).exp();
                let mu = mu_f - (mu_f - slow) * e;
                (mu, rate * (mu_f - slow) * e, dmuf_dn * (1.0 - e))
            }
        }
    }
}

/// The bearing's geometry and stiffnesses.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Law {
    pub radius: f64,
    /// Initial (pre-sliding) stiffness `k_i`.
    pub k_init: f64,
    /// Axial stiffness `k_v`.
    pub kv: f64,
    pub friction: Coefficient,
}

/// The response at a trial state: shear `V`, axial force `P` (compression > 0), trial
/// plastic displacement, and the tangents of `(V_x, V_y, P)` in `(u_x, u_y, w)` (`kx`) and
/// in the velocities (`cv`), row-major 3 x 3.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Response {
    pub shear: [f64; 2],
    pub axial: f64,
    pub plastic: [f64; 2],
    pub kx: [f64; 9],
    pub cv: [f64; 9],
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The most Newton iterations on `N` (pressure-dependent sliding).
const MAX_NEWTON: usize = 50;

impl Law {
    /// The sliding speed on the spherical surface `s = sqrt(|u'|^2 + (u . u' / R)^2)` (the
    /// slider's vertical velocity `u . u' / R` included, as OpenSees writes it) and its
    /// gradients in `u` and `u'` (zero at rest).
    fn speed(&self, u: [f64; 2], v: [f64; 2]) -> (f64, [f64; 2], [f64; 2]) {
        let r2 = self.radius * self.radius;
        let uv = dot(u, v);
        let s = (dot(v, v) + uv * uv / r2).sqrt();
        if s == 0.0 {
            return (0.0, [0.0; 2], [0.0; 2]);
        }
        let ds_du = [uv * v[0] / (r2 * s), uv * v[1] / (r2 * s)];
        let ds_dv = [(v[0] + uv * u[0] / r2) / s, (v[1] + uv * u[1] / r2) / s];
        (s, ds_du, ds_dv)
    }

    /// The response at the horizontal displacement `u`, vertical `w` (up), horizontal
    /// velocity `v`, from the committed plastic displacement `up_c`.
    pub fn respond(&self, u: [f64; 2], w: f64, v: [f64; 2], up_c: [f64; 2]) -> Response {
        let (r, ki, kv) = (self.radius, self.k_init, self.kv);
        let mut out = Response {
            shear: [0.0; 2],
            axial: 0.0,
            plastic: up_c,
            kx: [0.0; 9],
            cv: [0.0; 9],
        };
        if w >= 0.0 {
            // no compression: no shear; lifted off, the slider goes with the top
            if w > 0.0 {
                out.plastic = u;
            }
            return out;
        }
        let p = -kv * w;
        out.axial = p;
        out.kx[8] = -kv;
        let d = [u[0] - up_c[0], u[1] - up_c[1]];
        let (s, ds_du, ds_dv) = self.speed(u, v);
        // sticking: N = (P + k_i d.u / R) / (1 - u.u_p / R^2), V = k_i d + N u_p / R
        let den = 1.0 - dot(u, up_c) / (r * r);
        let num = p + ki * dot(d, u) / r;
        let n = num / den;
        let (mu, _, _) = self.friction.at(s, n);
        let dn = d[0].hypot(d[1]);
        let stick = if mu > 0.0 {
            ((ki - n / r) * dn).abs() <= mu * n
        } else {
            dn == 0.0
        };
        if stick {
            for j in 0..2 {
                // dnum/du_j = k_i (u_j + d_j) / R, dden/du_j = -u_p,j / R^2
                let dn_du = (ki * (u[j] + d[j]) / r * den + num * up_c[j] / (r * r)) / (den * den);
                for (i, up) in up_c.iter().enumerate() {
                    let kron = if i == j { ki } else { 0.0 };
                    out.kx[3 * i + j] = kron + up / r * dn_du;
                }
            }
            let dn_dw = -kv / den;
            out.kx[2] = up_c[0] / r * dn_dw;
            out.kx[5] = up_c[1] / r * dn_dw;
            out.shear = [ki * d[0] + n * up_c[0] / r, ki * d[1] + n * up_c[1] / r];
            return out;
        }
        self.slide(out, (u, d, dn, p), (s, ds_du, ds_dv))
    }

    /// Sliding: `f = mu N n` (`n = d / |d|`), `V = N a` with `a = u / R + mu n`, and
    /// `N (1 - a . u / R) = P` (solved by Newton on `N` when `mu` depends on `N`).
    fn slide(
        &self,
        mut out: Response,
        (u, d, dn, p): ([f64; 2], [f64; 2], f64, f64),
        (s, ds_du, ds_dv): (f64, [f64; 2], [f64; 2]),
    ) -> Response {
        let (r, ki, kv) = (self.radius, self.k_init, self.kv);
        let nv = if dn > 0.0 {
            [d[0] / dn, d[1] / dn]
        } else {
            [0.0; 2]
        };
        let q = 1.0 - dot(u, u) / (r * r);
        let c = dot(nv, u) / r;
        // N: closed form when mu does not depend on N, else Newton from it
        let (mu0, _, _) = self.friction.at(s, p);
        let mut n = p / (q - mu0 * c);
        if self.friction.pressure.is_some() {
            let mut converged = false;
            for _ in 0..MAX_NEWTON {
                let (mu, _, mu_n) = self.friction.at(s, n);
                let g = n * (q - mu * c) - p;
                let step = g / (q - mu * c - n * mu_n * c);
                n -= step;
                if step.abs() <= 1e-14 * n.abs().max(p) {
                    converged = true;
                    break;
                }
            }
            if !converged {
                n = f64::NAN;
            }
        }
        let (mu, mu_s, mu_n) = self.friction.at(s, n);
        let den = q - mu * c;
        let a = [u[0] / r + mu * nv[0], u[1] / r + mu * nv[1]];
        // projector (I - n n^T) / |d| (dn/du)
        let proj = |i: usize, j: usize| {
            if dn > 0.0 {
                ((if i == j { 1.0 } else { 0.0 }) - nv[i] * nv[j]) / dn
            } else {
                0.0
            }
        };
        // partial derivatives of den at fixed N: in u, in v; and in N
        let mut dden_du = [0.0; 2];
        let mut dden_dv = [0.0; 2];
        for j in 0..2 {
            // d(n . u)/du_j = n_j + sum_i u_i proj(i, j)
            let dnu = nv[j] + u[0] * proj(0, j) + u[1] * proj(1, j);
            dden_du[j] = -2.0 * u[j] / (r * r) - mu / r * dnu - c * mu_s * ds_du[j];
            dden_dv[j] = -c * mu_s * ds_dv[j];
        }
        let dden_dn = -c * mu_n;
        // total dN/dx from N den(N, x) = P(w)
        let g_n = den + n * dden_dn;
        let dn_du = [-n * dden_du[0] / g_n, -n * dden_du[1] / g_n];
        let dn_dv = [-n * dden_dv[0] / g_n, -n * dden_dv[1] / g_n];
        let dn_dw = -kv / g_n;
        for i in 0..2 {
            for j in 0..2 {
                let dmu_du = mu_s * ds_du[j] + mu_n * dn_du[j];
                let dmu_dv = mu_s * ds_dv[j] + mu_n * dn_dv[j];
                let da_du = (if i == j { 1.0 / r } else { 0.0 }) + mu * proj(i, j) + nv[i] * dmu_du;
                out.kx[3 * i + j] = a[i] * dn_du[j] + n * da_du;
                out.cv[3 * i + j] = a[i] * dn_dv[j] + n * nv[i] * dmu_dv;
            }
            out.kx[3 * i + 2] = a[i] * dn_dw + n * nv[i] * mu_n * dn_dw;
        }
        out.shear = [n * a[0], n * a[1]];
        let k0 = ki - n / r;
        out.plastic = [u[0] - mu * n * nv[0] / k0, u[1] - mu * n * nv[1] / k0];
        out
    }
}
