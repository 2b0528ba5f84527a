//! Where each co-simulation scheme is stable on the d-grid-step split, in theory: drivetrain D's
//! undamped 2-mass model in one FMU (generator torque in, generator speed out), the generator's
//! electrical spring in the other (speed in, load angle δ integrated exactly, torque K·δ out). Both
//! subsystems are solved exactly over a macro step H for the input polynomial the master gives them
//! (held, extrapolated, or interpolated from the new value), so the macro step is a linear map of
//! the coupled state; the scheme is stable where that map's spectral radius is at most 1 (Busch
//! 2016; FMI-NOTES §6 computes the same for a two-inertia split). The `iterative` algorithm's plain
//! fixed-point iteration converges where |g| < 1, g = K·c·Γ₁/2 the sweep's sensitivity to its own
//! end-of-step torque guess.
//!
//! What the master does, and what this copies (src/cosim/master.rs `source_polynomial`): units
//! step in scene order (torsional, then generator); an input from a unit not yet stepped is
//! extrapolated from the last 1, 2 or 3 communication points (order 0, 1, 2); from a unit already
//! stepped (Gauss–Seidel) it is held at the new value (order 0) or interpolated linearly from the
//! old to the new (order ≥ 1); the converged iterative step interpolates every input linearly.

use crate::physics::torsional::{INPUT_GENERATOR_TORQUE, TorsionalModel};
use crate::solver::SecondOrderSystem;
use nalgebra::{DMatrix, DVector};

/// A coupling scheme of the master on this split.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheme {
    /// Both units from the last communication point, inputs extrapolated to `order`.
    Jacobi(usize),
    /// Torsional first (extrapolated to `order`), the generator from its new speed.
    GaussSeidel(usize),
    /// The implicit coupling the iterative algorithm converges to (order 1).
    Converged,
}

impl Scheme {
    pub fn name(self) -> String {
        match self {
            Scheme::Jacobi(p) => format!("jacobi p{p}"),
            Scheme::GaussSeidel(p) => format!("gauss-seidel p{p}"),
            Scheme::Converged => "iterative (converged)".into(),
        }
    }
}

/// The linear split: mechanical ẋ = A·x + b·τ, speed y = c·x, and the spring τ = K·δ, δ̇ = y.
pub struct Split {
    a: DMatrix<f64>,
    b: DVector<f64>,
    c: DVector<f64>,
    pub stiffness: f64,
}

/// The subsystems' exact responses over one macro step.
struct Step {
    h: f64,
    phi: DMatrix<f64>,
    /// Responses to τ(s) = τ0 + τ1·s + τ2·s²/2: columns Γ0, Γ1, Γ2.
    gamma: [DVector<f64>; 3],
}

impl Split {
    /// The split of a torsional model (undamped or not) and a spring of stiffness `stiffness` on its
    /// generator DOF.
    pub fn new(model: &TorsionalModel, stiffness: f64) -> Self {
        let n = model.dofs();
        let lin = model.linearise(&vec![0.0; n], &vec![0.0; n]);
        let m_inv = lin.mass.clone().try_inverse().expect("a mass matrix is invertible");
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).copy_from(&DMatrix::identity(n, n));
        a.view_mut((n, 0), (n, n)).copy_from(&(-&m_inv * &lin.stiffness));
        a.view_mut((n, n), (n, n)).copy_from(&(-&m_inv * &lin.damping));
        let mut force = DVector::zeros(n);
        for l in model.input_loads().iter().filter(|l| l.input == INPUT_GENERATOR_TORQUE) {
            force[l.dof] += l.gain;
        }
        let mut b = DVector::zeros(2 * n);
        b.rows_mut(n, n).copy_from(&(&m_inv * force));
        let mut c = DVector::zeros(2 * n);
        c[n + model.generator] = 1.0;
        Self { a, b, c, stiffness }
    }

    fn step(&self, h: f64) -> Step {
        let m = self.a.nrows();
        // exp of [[A, b, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]]·h carries τ, τ', τ''
        let mut aug = DMatrix::zeros(m + 3, m + 3);
        aug.view_mut((0, 0), (m, m)).copy_from(&self.a);
        aug.view_mut((0, m), (m, 1)).copy_from(&self.b);
        aug[(m, m + 1)] = 1.0;
        aug[(m + 1, m + 2)] = 1.0;
        let e = (aug * h).exp();
        let col = |k: usize| e.view((0, m + k), (m, 1)).column(0).into_owned();
        Step {
            h,
            phi: e.view((0, 0), (m, m)).into_owned(),
            gamma: [col(0), col(1), col(2)],
        }
    }

    /// The macro-step map of `scheme` on s = [x, δ_n, δ_n−1, δ_n−2, y_n−1, y_n−2].
    pub fn map(&self, scheme: Scheme, h: f64) -> DMatrix<f64> {
        let st = self.step(h);
        let m = self.a.nrows();
        let dim = m + 5;
        let mut t = DMatrix::zeros(dim, dim);
        for j in 0..dim {
            let mut s = DVector::zeros(dim);
            s[j] = 1.0;
            t.set_column(j, &self.advance(&st, scheme, &s));
        }
        t
    }

    fn advance(&self, st: &Step, scheme: Scheme, s: &DVector<f64>) -> DVector<f64> {
        let m = self.a.nrows();
        let (h, k) = (st.h, self.stiffness);
        let x = s.rows(0, m).into_owned();
        let delta = [s[m], s[m + 1], s[m + 2]];
        let y = [self.c.dot(&x), s[m + 3], s[m + 4]];
        let tau = delta.map(|d| k * d);
        // mechanical response to a torque polynomial [τ0, τ1, τ2]
        let mech = |p: [f64; 3]| &st.phi * &x + &st.gamma[0] * p[0] + &st.gamma[1] * p[1] + &st.gamma[2] * p[2];
        // the spring's load angle after the step under a speed polynomial
        let spring = |w: [f64; 3]| delta[0] + w[0] * h + w[1] * h * h / 2.0 + w[2] * h * h * h / 6.0;
        let (x_new, delta_new) = match scheme {
            Scheme::Jacobi(p) => (mech(extrapolate(tau, h, p)), spring(extrapolate(y, h, p))),
            Scheme::GaussSeidel(p) => {
                let x_new = mech(extrapolate(tau, h, p));
                let y_new = self.c.dot(&x_new);
                let w = if p == 0 {
                    [y_new, 0.0, 0.0]
                } else {
                    [y[0], (y_new - y[0]) / h, 0.0]
                };
                (x_new, spring(w))
            }
            Scheme::Converged => {
                // δ' = δ + h/2·(y + c·x'), x' = Φx + Γ0·Kδ + Γ1·K(δ' − δ)/h: linear in δ'
                let free = mech([tau[0], -tau[0] / h, 0.0]);
                let g = k * self.c.dot(&st.gamma[1]) / h;
                let delta_new = (delta[0] + h / 2.0 * (y[0] + self.c.dot(&free))) / (1.0 - h / 2.0 * g);
                (free + &st.gamma[1] * (k * delta_new / h), delta_new)
            }
        };
        let mut out = DVector::zeros(s.len());
        out.rows_mut(0, m).copy_from(&x_new);
        out[m] = delta_new;
        out[m + 1] = delta[0];
        out[m + 2] = delta[1];
        out[m + 3] = y[0];
        out[m + 4] = y[1];
        out
    }

    /// Spectral radius of the macro-step map: > 1 grows.
    pub fn spectral_radius(&self, scheme: Scheme, h: f64) -> f64 {
        self.map(scheme, h)
            .complex_eigenvalues()
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max)
    }

    /// Whether the amplitude grows by more than `factor` over `duration` seconds of macro steps `h`:
    /// ρ^(duration/h) > factor. Zero-order-hold Jacobi is unstable at every step in the strict sense
    /// (ρ > 1 by 6e-4 at 1 ms); what a run of finite length shows is this growth.
    pub fn grows(&self, scheme: Scheme, h: f64, duration: f64, factor: f64) -> bool {
        self.spectral_radius(scheme, h).ln() * duration / h > factor.ln()
    }

    /// Angular frequency of the fastest mode of the coupled system (the split undone), rad/s.
    pub fn top_mode(&self) -> f64 {
        let m = self.a.nrows();
        let mut full = DMatrix::zeros(m + 1, m + 1);
        full.view_mut((0, 0), (m, m)).copy_from(&self.a);
        full.view_mut((0, m), (m, 1)).copy_from(&(&self.b * self.stiffness));
        full.view_mut((m, 0), (1, m)).copy_from(&self.c.transpose());
        full.complex_eigenvalues()
            .iter()
            .map(|z| z.im.abs())
            .fold(0.0, f64::max)
    }

    /// |g| of the plain fixed-point iteration of the iterative algorithm: it converges where < 1.
    pub fn iteration_factor(&self, h: f64) -> f64 {
        let st = self.step(h);
        (self.stiffness * self.c.dot(&st.gamma[1]) / 2.0).abs()
    }

    /// The largest macro step of `candidates` (ascending) up to which `stable(h)` holds at every step.
    pub fn limit(candidates: &[f64], stable: impl Fn(f64) -> bool) -> Option<f64> {
        let mut last = None;
        for &h in candidates {
            if !stable(h) {
                break;
            }
            last = Some(h);
        }
        last
    }
}

/// The master's polynomial [a0, a1, a2] from the last three values (newest first), equal steps h.
fn extrapolate(u: [f64; 3], h: f64, order: usize) -> [f64; 3] {
    match order {
        0 => [u[0], 0.0, 0.0],
        1 => [u[0], (u[0] - u[1]) / h, 0.0],
        _ => {
            let f01 = (u[0] - u[1]) / h;
            let f12 = (u[1] - u[2]) / h;
            let f012 = (f01 - f12) / (2.0 * h);
            [u[0], f01 + f012 * h, 2.0 * f012]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(kappa: f64) -> Split {
        let built = crate::reference::grid_step::torsional_params().build().unwrap();
        Split::new(&built.model, kappa * built.drivetrain.k_generator)
    }

    /// The converged implicit coupling of an undamped system neither grows nor decays (|λ| = 1 within
    /// 1e-9 from H·ω = 0.04 to 37); the plain iteration's factor passes 1 between H·ω = 1.85 and
    /// 3.7, where the master's plain iteration stops converging (tests/cosim_master.rs).
    #[test]
    fn converged_coupling_is_neutral_and_plain_iteration_fails_where_measured() {
        let s = split(1.0);
        for h in [1e-3, 1e-2, 0.1, 1.0] {
            let r = s.spectral_radius(Scheme::Converged, h);
            assert!((r - 1.0).abs() < 1e-9, "H = {h}: {r}");
        }
        assert!(s.iteration_factor(0.05) < 1.0 && s.iteration_factor(0.1) > 1.0);
    }

    /// Over 10 s (amplitude at most doubled): Gauss–Seidel with hold is stable at 50 ms and unstable
    /// at 100 ms; zero-order-hold Jacobi grows already at 1 ms; linear-extrapolation Jacobi is stable
    /// at 5 ms and not at 10 ms: the limits the master shows (tests/cosim_master.rs
    /// `stability_limits_of_the_coupling_algorithms`). The top coupled mode is the 5.89 Hz one.
    #[test]
    fn limits_match_the_masters() {
        let s = split(1.0);
        assert!(
            (s.top_mode() / std::f64::consts::TAU - 5.889).abs() < 0.01,
            "{}",
            s.top_mode()
        );
        let stable = |scheme, h| !s.grows(scheme, h, 10.0, 2.0);
        assert!(stable(Scheme::GaussSeidel(0), 0.05) && !stable(Scheme::GaussSeidel(0), 0.1));
        assert!(!stable(Scheme::Jacobi(0), 1e-3));
        assert!(stable(Scheme::Jacobi(1), 5e-3) && !stable(Scheme::Jacobi(1), 1e-2));
    }
}
