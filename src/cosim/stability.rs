//! Where each co-simulation scheme is stable on a split of two linear units, in theory: the first
//! takes a torque and gives a speed, the second takes that speed and gives the torque back. Two
//! splits are drawn: d-grid-step (drivetrain D's undamped 2-mass model | the generator's electrical
//! spring: load angle δ integrated exactly, torque K·δ) and d-shaft-cut (the rotor's inertia | the
//! rest of the drivetrain, its LSS turned at the rotor's speed, the LSS torque out). Both units are
//! solved exactly over a macro step H for the input polynomial the master gives them (held,
//! extrapolated, or interpolated from the new value), so the macro step is a linear map of the
//! coupled state; the scheme is stable where that map's spectral radius is at most 1 (Busch 2016
//! analyses a two-mass oscillator this way). The `iterative` algorithm's plain
//! fixed-point iteration converges where |g| < 1, g the sweep's sensitivity to its own end-of-step
//! torque guess.
//!
//! What the master does, and what this copies (src/cosim/master.rs `source_polynomial`): units
//! step in scene order (the first, then the second); an input from a unit not yet stepped is
//! extrapolated from the last 1, 2 or 3 communication points (order 0, 1, 2); from a unit already
//! stepped (Gauss–Seidel) it is held at the new value (order 0) or interpolated linearly from the
//! old to the new (order ≥ 1); the converged iterative step interpolates every input linearly.

use crate::physics::torsional::{
    INPUT_CUT_ANGLE, INPUT_CUT_SPEED, INPUT_CUT_TORQUE, INPUT_GENERATOR_TORQUE, TorsionalModel,
};
use crate::solver::SecondOrderSystem;
use nalgebra::{DMatrix, DVector};

/// A coupling scheme of the master on this split.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheme {
    /// Both units from the last communication point, inputs extrapolated to `order`.
    Jacobi(usize),
    /// The first unit (extrapolated to `order`), then the second from its new output.
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

/// A linear unit with one input and one output: ẋ = A·x + b·u, y = c·x + d·u.
pub struct Unit {
    a: DMatrix<f64>,
    b: DVector<f64>,
    c: DVector<f64>,
    d: f64,
}

/// A unit's exact responses over one macro step.
struct UnitStep {
    phi: DMatrix<f64>,
    /// Responses to u(s) = u0 + u1·s + u2·s²/2: columns Γ0, Γ1, Γ2.
    gamma: [DVector<f64>; 3],
}

impl Unit {
    /// A torsional model (state [θ, θ̇]) loaded by the torque of input `input`, its output the speed
    /// of DOF `speed_dof`.
    pub fn mechanical(model: &TorsionalModel, input: usize, speed_dof: usize) -> Self {
        let (a, m_inv) = Self::dynamics(model, 0);
        let n = model.dofs();
        let mut b = DVector::zeros(2 * n);
        b.rows_mut(n, n).copy_from(&(&m_inv * Self::loads(model, input)));
        let mut c = DVector::zeros(2 * n);
        c[n + speed_dof] = 1.0;
        Self { a, b, c, d: 0.0 }
    }

    /// A spring to ground turned at its input speed: δ̇ = u, torque K·δ (the generator on the grid).
    pub fn spring(stiffness: f64) -> Self {
        Self {
            a: DMatrix::zeros(1, 1),
            b: DVector::from_element(1, 1.0),
            c: DVector::from_element(1, stiffness),
            d: 0.0,
        }
    }

    /// A drivetrain cut from its rotor ([`crate::physics::torsional::Section::Drivetrain`]): state
    /// [θ, θ̇, θ_b], the boundary angle θ_b integrating the input speed; the output the LSS torque,
    /// which the shaft's damping makes depend on the input directly.
    pub fn cut_drivetrain(model: &TorsionalModel) -> Self {
        let n = model.dofs();
        let (a, m_inv) = Self::dynamics(model, 1);
        let mut a = a;
        let angle_load = &m_inv * Self::loads(model, INPUT_CUT_ANGLE);
        a.view_mut((n, 2 * n), (n, 1)).copy_from(&angle_load);
        let mut b = DVector::zeros(2 * n + 1);
        b.rows_mut(n, n)
            .copy_from(&(&m_inv * Self::loads(model, INPUT_CUT_SPEED)));
        b[2 * n] = 1.0;
        let lss = model.shafts[0].expect("a drivetrain has an LSS");
        let e = &model.elements[lss.element];
        let mut c = DVector::zeros(2 * n + 1);
        for &(dof, g) in &e.coeffs {
            c[dof] += lss.factor * e.stiffness * g;
            c[n + dof] += lss.factor * e.damping * g;
        }
        c[2 * n] = lss.factor * e.stiffness * e.boundary;
        Self {
            a,
            b,
            c,
            d: lss.factor * e.damping * e.boundary,
        }
    }

    /// [[0, I], [−M⁻¹K, −M⁻¹C]] of the linearised model, with `extra` zero states after it; and M⁻¹.
    fn dynamics(model: &TorsionalModel, extra: usize) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = model.dofs();
        let lin = model.linearise(&vec![0.0; n], &vec![0.0; n]);
        let m_inv = lin.mass.clone().try_inverse().expect("a mass matrix is invertible");
        let mut a = DMatrix::zeros(2 * n + extra, 2 * n + extra);
        a.view_mut((0, n), (n, n)).copy_from(&DMatrix::identity(n, n));
        a.view_mut((n, 0), (n, n)).copy_from(&(-&m_inv * &lin.stiffness));
        a.view_mut((n, n), (n, n)).copy_from(&(-&m_inv * &lin.damping));
        (a, m_inv)
    }

    /// The load of input `input` on each DOF per unit input.
    fn loads(model: &TorsionalModel, input: usize) -> DVector<f64> {
        let mut force = DVector::zeros(model.dofs());
        for l in model.input_loads().iter().filter(|l| l.input == input) {
            force[l.dof] += l.gain;
        }
        force
    }

    fn step(&self, h: f64) -> UnitStep {
        let m = self.a.nrows();
        // exp of [[A, b, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]]·h carries u, u', u''
        let mut aug = DMatrix::zeros(m + 3, m + 3);
        aug.view_mut((0, 0), (m, m)).copy_from(&self.a);
        aug.view_mut((0, m), (m, 1)).copy_from(&self.b);
        aug[(m, m + 1)] = 1.0;
        aug[(m + 1, m + 2)] = 1.0;
        let e = (aug * h).exp();
        let col = |k: usize| e.view((0, m + k), (m, 1)).column(0).into_owned();
        UnitStep {
            phi: e.view((0, 0), (m, m)).into_owned(),
            gamma: [col(0), col(1), col(2)],
        }
    }

    fn states(&self) -> usize {
        self.a.nrows()
    }
}

impl UnitStep {
    /// The state after the step from `x` under the input polynomial [u0, u1, u2].
    fn advance(&self, x: &DVector<f64>, p: [f64; 3]) -> DVector<f64> {
        &self.phi * x + &self.gamma[0] * p[0] + &self.gamma[1] * p[1] + &self.gamma[2] * p[2]
    }
}

/// Two units coupled: the first's output is the second's input and back.
pub struct Split {
    first: Unit,
    second: Unit,
    /// The coupling stiffness (the spring's, or the cut shaft's), N·m/rad.
    pub stiffness: f64,
}

impl Split {
    /// The d-grid-step split: a torsional model (undamped or not) and a spring of stiffness
    /// `stiffness` from its generator DOF to ground.
    pub fn new(model: &TorsionalModel, stiffness: f64) -> Self {
        Self {
            first: Unit::mechanical(model, INPUT_GENERATOR_TORQUE, model.generator),
            second: Unit::spring(stiffness),
            stiffness,
        }
    }

    /// The d-shaft-cut split: the rotor section (its speed out) and the drivetrain section (the LSS
    /// torque out), models cut by [`TorsionalModel::into_section`].
    pub fn shaft_cut(rotor: &TorsionalModel, drivetrain: &TorsionalModel) -> Self {
        let lss = drivetrain.shafts[0].expect("a drivetrain has an LSS");
        Self {
            first: Unit::mechanical(rotor, INPUT_CUT_TORQUE, 0),
            second: Unit::cut_drivetrain(drivetrain),
            stiffness: drivetrain.elements[lss.element].stiffness,
        }
    }

    /// The macro-step map of `scheme` on s = [x₁, x₂, τ_n−1, τ_n−2, y_n−1, y_n−2] (τ the second
    /// unit's output, y the first's).
    pub fn map(&self, scheme: Scheme, h: f64) -> DMatrix<f64> {
        let steps = (self.first.step(h), self.second.step(h));
        let dim = self.first.states() + self.second.states() + 4;
        let mut t = DMatrix::zeros(dim, dim);
        for j in 0..dim {
            let mut s = DVector::zeros(dim);
            s[j] = 1.0;
            t.set_column(j, &self.advance(&steps, scheme, h, &s));
        }
        t
    }

    fn advance(&self, (st1, st2): &(UnitStep, UnitStep), scheme: Scheme, h: f64, s: &DVector<f64>) -> DVector<f64> {
        let (m1, m2) = (self.first.states(), self.second.states());
        let (u1, u2) = (&self.first, &self.second);
        let x1 = s.rows(0, m1).into_owned();
        let x2 = s.rows(m1, m2).into_owned();
        let hist = m1 + m2;
        let y = [u1.c.dot(&x1), s[hist + 2], s[hist + 3]];
        let tau = [u2.c.dot(&x2) + u2.d * y[0], s[hist], s[hist + 1]];
        let (x1_new, x2_new) = match scheme {
            Scheme::Jacobi(p) => (
                st1.advance(&x1, extrapolate(tau, h, p)),
                st2.advance(&x2, extrapolate(y, h, p)),
            ),
            Scheme::GaussSeidel(p) => {
                let x1_new = st1.advance(&x1, extrapolate(tau, h, p));
                let y_new = u1.c.dot(&x1_new);
                let w = if p == 0 {
                    [y_new, 0.0, 0.0]
                } else {
                    [y[0], (y_new - y[0]) / h, 0.0]
                };
                (x1_new, st2.advance(&x2, w))
            }
            Scheme::Converged => {
                // both inputs linear over the step to the unknown end values: y' = a + α·τ',
                // τ' = b + β·y', solved together
                let free1 = st1.advance(&x1, [tau[0], -tau[0] / h, 0.0]);
                let free2 = st2.advance(&x2, [y[0], -y[0] / h, 0.0]);
                let (alpha, beta) = self.sensitivities(st1, st2, h);
                let (a, b) = (u1.c.dot(&free1), u2.c.dot(&free2));
                let y_new = (a + alpha * b) / (1.0 - alpha * beta);
                let tau_new = b + beta * y_new;
                (
                    free1 + &st1.gamma[1] * (tau_new / h),
                    free2 + &st2.gamma[1] * (y_new / h),
                )
            }
        };
        let mut out = DVector::zeros(s.len());
        out.rows_mut(0, m1).copy_from(&x1_new);
        out.rows_mut(m1, m2).copy_from(&x2_new);
        out[hist] = tau[0];
        out[hist + 1] = tau[1];
        out[hist + 2] = y[0];
        out[hist + 3] = y[1];
        out
    }

    /// α = ∂y'/∂τ' of the first unit and β = ∂τ'/∂y' of the second over a step whose inputs end at
    /// those values (linear interpolation).
    fn sensitivities(&self, st1: &UnitStep, st2: &UnitStep, h: f64) -> (f64, f64) {
        (
            self.first.c.dot(&st1.gamma[1]) / h,
            self.second.c.dot(&st2.gamma[1]) / h + self.second.d,
        )
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
        let (u1, u2) = (&self.first, &self.second);
        let (m1, m2) = (u1.states(), u2.states());
        let mut full = DMatrix::zeros(m1 + m2, m1 + m2);
        full.view_mut((0, 0), (m1, m1))
            .copy_from(&(&u1.a + &u1.b * u1.c.transpose() * u2.d));
        full.view_mut((0, m1), (m1, m2)).copy_from(&(&u1.b * u2.c.transpose()));
        full.view_mut((m1, 0), (m2, m1)).copy_from(&(&u2.b * u1.c.transpose()));
        full.view_mut((m1, m1), (m2, m2)).copy_from(&u2.a);
        full.complex_eigenvalues()
            .iter()
            .map(|z| z.im.abs())
            .fold(0.0, f64::max)
    }

    /// |g| of the plain fixed-point iteration of the iterative algorithm: it converges where < 1.
    pub fn iteration_factor(&self, h: f64) -> f64 {
        let (alpha, beta) = self.sensitivities(&self.first.step(h), &self.second.step(h), h);
        (alpha * beta).abs()
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
    /// 3.7, where the master's plain iteration stops converging (tests/it/cosim_master.rs).
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
    /// at 5 ms and not at 10 ms: the limits the master shows (tests/it/cosim_master.rs
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

    /// The shaft cut: its top coupled mode is the two-mass problem's ω (2.524 Hz), its converged
    /// coupling neutral, and its limits those `windrive chart stability --split shaft` runs at the
    /// nominal shaft (Gauss–Seidel with hold stable at 0.1 s, not at 0.2 s; Jacobi with linear
    /// extrapolation at 20 ms, not at 50 ms; 20 s, amplitude at most doubled). Free-free, the map has
    /// the rigid rotation's double eigenvalue 1 (a Jordan block), computed only to about
    /// √(ε·cond): 8e-8 at 1 ms, 1e-5 at 1 s with torques of 1e7 beside angles in one state; the
    /// neutral check allows 1e-6 up to 0.1 s.
    #[test]
    fn shaft_cut_limits_match_the_masters() {
        let (rotor, drivetrain) = crate::reference::shaft_cut::models(1.0);
        let s = Split::shaft_cut(&rotor, &drivetrain);
        let (_, omega) = crate::reference::shaft_cut::exact_lss_torque(1.0, &[]);
        assert!((s.top_mode() / omega - 1.0).abs() < 1e-9, "{} {omega}", s.top_mode());
        for h in [1e-3, 1e-2, 0.1] {
            let r = s.spectral_radius(Scheme::Converged, h);
            assert!((r - 1.0).abs() < 1e-6, "H = {h}: {r}");
        }
        let stable = |scheme, h| !s.grows(scheme, h, 15.0, 2.0);
        assert!(stable(Scheme::GaussSeidel(0), 0.1) && !stable(Scheme::GaussSeidel(0), 0.2));
        assert!(stable(Scheme::Jacobi(1), 0.02) && !stable(Scheme::Jacobi(1), 0.05));
    }
}
