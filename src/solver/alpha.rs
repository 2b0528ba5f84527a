//! The generalised-α family of implicit integrators for second-order systems, with a Newton
//! iteration on the position increment Δ = q_{n+1} − q_n:
//!
//! ```text
//! a₁ = (Δ − h·v − h²(½ − β)·a) / (β h²)        v₁ = v + h((1 − γ)·a + γ·a₁)
//! M((1 − α_m)·a₁ + α_m·a) + (1 − α_f)·f_int(q + Δ, v₁) + α_f·f_int(q, v) = (1 − α_f)·f₁ + α_f·f₀
//! ```
//!
//! - **Newmark average acceleration** (α_m = α_f = 0, β = ¼, γ = ½): the trapezoidal rule, second
//!   order, no numerical damping, energy-conserving for an undamped linear model. The default.
//! - **HHT-α** (α_m = 0, α_f = (1 − ρ∞)/(1 + ρ∞) ∈ [0, ⅓]): second order, damps modes with h·ω ≫ 1
//!   to the spectral radius ρ∞ ∈ [½, 1] (Hilber, Hughes, Taylor 1977).
//! - **Generalised-α** (Chung & Hulbert 1993): α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1),
//!   ρ∞ ∈ [0, 1]; least low-frequency damping for a given high-frequency damping.
//!
//! Forces are interpolated (α_f weights f_int at the start of the step), the form used for
//! nonlinear structural dynamics; for a linear model it is the original method.
//!
//! The Coulomb friction contact (the HSS brake) is solved inside the step: for a fixed Jacobian the
//! solution is affine in the friction force T (Δ = Δ₀ + T·(1 − α_f)·J⁻¹e_f), so T is the force that
//! stops the DOF exactly at the end of the step if the contact can hold it (stick), else ± the
//! kinetic capacity (slip). A stuck contact therefore never creeps and never chatters.

use super::factor::{Cache, Factor, Orderings, Solver, padded, same_key, same_step};
use super::norms::max_abs;
use super::state::{DynState, ForcesAt, SolverError, Statistics};
use super::system::{Friction, Linearity, SecondOrderSystem, external_forces};
use nalgebra::DMatrix;

mod linear;

/// Newton iterations before a step is given up (and halved by the driver).
pub const MAX_ITERATIONS: usize = 50;

/// An iterate whose residual is this fraction of the largest force acting is converged: below it
/// the residual is the rounding of the forces (absolute angles of thousands of radians resolve
/// deflections to about 1e-13 m), and further increments only chase that noise.
const RESIDUAL_TOLERANCE: f64 = 1e-9;

/// A smooth nonlinear iteration has converged when the last increment is below this fraction of
/// the step's motion (‖δ‖∞ ≤ tol·max(‖Δ‖∞, h‖v‖∞)): ten digits of the position increment.
const INCREMENT_TOLERANCE: f64 = 1e-10;

/// The same for the nearly piecewise-linear class (roller sets), whose modified Newton iteration
/// gains about 1.5 digits per iteration on its cached Jacobian: eight digits of the step's motion
/// (on the GRC 8e-10 m and rad, the HSS turning 0.08 rad a step) take 3.9 iterations a step instead
/// of 5.2, and change the shutdown scene's bearing loads and contact pressures by under 1e-4 of
/// their peaks and the HSS torque by 0.13 % RMS, less than the step's own error (0.5 against 0.25 ms: 0.33 %).
pub const NEARLY_LINEAR_INCREMENT_TOLERANCE: f64 = 1e-8;

/// Iterations of the nearly piecewise-linear class after which each increment is halved. Its
/// iterates can settle into a two-cycle across a kink (a roller or lamina at the edge of contact, a
/// damping force clipped at zero) when loads are small: in drivetrain C's held shutdown (2 MW,
/// scenes/c-shutdown-6dof) 1700 steps in 20 s cycled with increments of 1e-10 until the step was
/// halved; the halved increment lands between the two iterates and converges. From then on a
/// residual of ten times RESIDUAL_TOLERANCE is accepted: the rounding floor such a held gearbox
/// stalls at (2.5e-4 N against 1.2e5 N, absolute angles of 1500 rad). With both, that scene runs
/// in 12.6 s instead of 298.
const RELAXED_AFTER: usize = 6;

/// Iterations of the nearly piecewise-linear class, past [`RELAXED_AFTER`], over which the increment must
/// at least halve; one that has not is given up at once (the driver halves the step) instead of after
/// [`MAX_ITERATIONS`]. Such an iteration has settled into a cycle across contact kinks, its iterates
/// repeating to every printed digit (traced on d-shutdown-6dof: 214 steps in 30 s cycled with period two
/// or three, the residual alternating between about 21 and 24 N, until the fiftieth iteration), while a
/// relaxed iteration that converges halves its increment in about two iterations.
const STALL_ITERATIONS: usize = 6;

/// [`Newton::keep`]: a kept factorisation is refreshed (a fresh tangent at the current iterate) when
/// an increment is more than this fraction of the one before it (the contraction rate θ of Hairer and
/// Wanner's RADAU5), or after [`KEPT_ITERATIONS`] iterations on it without convergence.
pub const THETA_REFRESH: f64 = 0.5;

/// [`Newton::keep`]: iterations on one factorisation within a step before it is refreshed; a fresh one
/// that diverges or does not converge within as many sends the step back to the default iteration.
pub const KEPT_ITERATIONS: usize = 6;

/// [`Newton::keep`]: the smallest η = θ/(1 − θ) the increment test credits a contracting iteration
/// with (an increment up to ten times the tolerance is accepted when the next would be θ times it).
pub const ETA_FLOOR: f64 = 0.1;

/// [`Newton::keep`]: after a step the kept iteration gave up on, the next steps are taken the default
/// way at once (from Δ = 0, no kept J tried first) until one of them converges within this many
/// iterations: restarts come in runs while a held gearbox rattles in its backlash (86 % of the steps
/// after a restart restarted too, each after some six iterations spent on the kept J), and a step
/// the default way converges that fast only once the contacts have settled.
pub const RATTLE_ITERATIONS: u64 = 4;

/// [`Newton::keep`]: the most steps taken the default way in one run of [`RATTLE_ITERATIONS`]' mode;
/// then the kept iteration is tried again, so that a model whose default iteration always takes
/// more iterations (no contact pattern to settle) is not held in the mode for good.
pub const RATTLE_RUN: u32 = 16;

/// How the Newton iteration of the nearly piecewise-linear class (the 6-DOF gearbox, whose contact
/// pattern changes at almost every step) treats its Jacobian and where it starts. The default (both
/// false) is the iteration every other class takes: Δ = 0, the pattern's factorisation, a new one
/// whenever an iterate's pattern changes. Either option changes the iteration's path, so outputs move
/// at the Newton tolerance; the converged iterates meet the same tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Newton {
    /// Modified Newton on a kept factorisation: the last step's J is reused across steps and
    /// patterns (same step size) while the iteration contracts (θ ≤ [`THETA_REFRESH`]), refreshed
    /// at the iterate when it does not, and the step retaken the default way from Δ = 0 when even the
    /// fresh J stalls (counted in `Statistics::newton_restarts`; the steps after it go the default way
    /// at once until one converges fast, [`RATTLE_ITERATIONS`]). The increment tolerance then
    /// bounds the iterate's error θ/(1 − θ)·‖δ‖ (Hairer and Wanner's test), not the increment ‖δ‖,
    /// and no contact pattern is compared: a pattern is taken only to cache a fresh factorisation.
    /// The kept J is history no state holds, and so are the cached ones: a pattern's J is assembled at
    /// the point where it was first needed, so which point that was decides a later step's J too. A
    /// clone starts without any, and the gearbox FMU drops them whenever a state is taken or restored
    /// ([`AlphaIntegrator::forget_factorisations`]): the run that goes on and every rerun from the
    /// state then build the same ones at the same points and repeat bit for bit.
    pub keep: bool,
    /// Start from the constant-acceleration predictor Δ = h·v + ½h²·a (a₁ = a under every member of
    /// the family) instead of Δ = 0, whose first iterate has v₁ ≈ −v.
    pub predict: bool,
    /// The nearly piecewise-linear class's increment tolerance, a fraction of the step's motion
    /// ([`NEARLY_LINEAR_INCREMENT_TOLERANCE`] unless set; docs/PERFORMANCE.md measures what a looser
    /// one saves and moves).
    pub tolerance: f64,
    /// The least "motion of the step" the nearly piecewise-linear class's increment tolerance is a
    /// fraction of (m or rad, as the DOFs): the increment is converged at `tolerance` times the larger
    /// of the step's motion and this floor. A held gearbox moves by a micrometre a step or less, and a
    /// fraction of that motion alone asks its Newton iteration for increments of 1e-13 m, four
    /// decades finer than the same tolerance resolves in operation (the GRC's HSS turns 0.19 rad a
    /// step at rated speed); 0 takes the step's motion alone. docs/PERFORMANCE.md measures what it
    /// saves and moves.
    pub motion_floor: f64,
    /// Solve with J on its own sparsity pattern where that saves half the work
    /// ([`Solver::new_with`](super::factor::Solver::new_with)) instead of by dense LU: other rounding,
    /// so other bits at the Newton tolerance.
    pub sparse: bool,
}

impl Default for Newton {
    fn default() -> Self {
        Self::PATTERN
    }
}

impl Newton {
    /// The iteration every class takes (see [`Newton`]), at the default tolerance.
    pub const PATTERN: Self = Self {
        keep: false,
        predict: false,
        tolerance: NEARLY_LINEAR_INCREMENT_TOLERANCE,
        motion_floor: 0.0,
        sparse: false,
    };

    /// The FMU parameter's spelling: `pattern` (this type's default), `kept`, `predicted` or `kept+predicted`
    /// (the gearbox FMU's default).
    pub fn parse(s: &str) -> Option<Self> {
        let (keep, predict) = match s.trim().to_ascii_lowercase().as_str() {
            "" | "pattern" => (false, false),
            "kept" => (true, false),
            "predicted" => (false, true),
            "kept+predicted" => (true, true),
            _ => return None,
        };
        Some(Self {
            keep,
            predict,
            ..Self::PATTERN
        })
    }
}

/// One step: from `t` by `h`, inputs `u0` at t and `u1` at t + h; `fi0`, when the caller has them,
/// the internal forces at the step's start state (the methods that weight the start of the step
/// need them, and a driver has just evaluated them for the consistent accelerations).
#[derive(Debug, Clone, Copy)]
pub struct Span<'a> {
    pub t: f64,
    pub h: f64,
    pub u0: &'a [f64],
    pub u1: &'a [f64],
    pub fi0: Option<&'a [f64]>,
}

/// The four parameters of the family.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alpha {
    pub alpha_m: f64,
    pub alpha_f: f64,
    pub beta: f64,
    pub gamma: f64,
}

impl Alpha {
    pub const NEWMARK: Self = Self {
        alpha_m: 0.0,
        alpha_f: 0.0,
        beta: 0.25,
        gamma: 0.5,
    };

    /// HHT-α with spectral radius ρ∞ ∈ [½, 1] at infinite frequency (1 = Newmark).
    pub fn hht(rho_inf: f64) -> Result<Self, String> {
        if !(0.5..=1.0).contains(&rho_inf) {
            return Err(format!("HHT-alpha needs a spectral radius in [0.5, 1], got {rho_inf}"));
        }
        let a = (1.0 - rho_inf) / (1.0 + rho_inf);
        Ok(Self {
            alpha_m: 0.0,
            alpha_f: a,
            beta: 0.25 * (1.0 + a) * (1.0 + a),
            gamma: 0.5 + a,
        })
    }

    /// Generalised-α with spectral radius ρ∞ ∈ [0, 1] at infinite frequency.
    pub fn generalised(rho_inf: f64) -> Result<Self, String> {
        if !(0.0..=1.0).contains(&rho_inf) {
            return Err(format!(
                "generalised-alpha needs a spectral radius in [0, 1], got {rho_inf}"
            ));
        }
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        Ok(Self {
            alpha_m,
            alpha_f,
            beta: 0.25 * (1.0 - alpha_m + alpha_f).powi(2),
            gamma,
        })
    }
}

impl Alpha {
    /// The spectral radius of the method's amplification matrix on an undamped oscillator at Ω = h·ω:
    /// the amplitude a mode keeps per step (1 for Newmark at every Ω; → ρ∞ as Ω → ∞ for HHT-α and
    /// generalised-α). From the defining equations, state (x, h·v, h²·a):
    /// x₁ − β·a₁ = x + v + (½ − β)·a, v₁ − γ·a₁ = v + (1 − γ)·a,
    /// (1 − α_m)·a₁ + α_m·a + Ω²·((1 − α_f)·x₁ + α_f·x) = 0.
    pub fn amplification_radius(&self, omega_h: f64) -> f64 {
        use nalgebra::Matrix3;
        let (am, af, b, g) = (self.alpha_m, self.alpha_f, self.beta, self.gamma);
        let w2 = omega_h * omega_h;
        let l = Matrix3::new(1.0, 0.0, -b, 0.0, 1.0, -g, (1.0 - af) * w2, 0.0, 1.0 - am);
        let r = Matrix3::new(1.0, 1.0, 0.5 - b, 0.0, 1.0, 1.0 - g, -af * w2, 0.0, -am);
        match l.try_inverse() {
            Some(li) => (li * r)
                .complex_eigenvalues()
                .iter()
                .map(|z| z.norm())
                .fold(0.0, f64::max),
            None => f64::NAN,
        }
    }
}

/// The coefficients of one step size: the update a₁, v₁ = k_·Δ + k_·v + k_·a and the iteration
/// matrix J = c_m·M + c_c·C_t + c_k·K_t.
#[derive(Debug, Clone, Copy)]
struct Coefficients {
    h: f64,
    ka: [f64; 3],
    kv: [f64; 3],
    c_m: f64,
    c_c: f64,
    c_k: f64,
    am: f64,
    af: f64,
}

impl Coefficients {
    fn new(p: &Alpha, h: f64) -> Self {
        let (b, g) = (p.beta, p.gamma);
        let ka = [1.0 / (b * h * h), -1.0 / (b * h), -(0.5 - b) / b];
        let kv = [g / (b * h), 1.0 - g / b, h * (1.0 - g / (2.0 * b))];
        Self {
            h,
            ka,
            kv,
            c_m: (1.0 - p.alpha_m) * ka[0],
            c_c: (1.0 - p.alpha_f) * kv[0],
            c_k: 1.0 - p.alpha_f,
            am: p.alpha_m,
            af: p.alpha_f,
        }
    }

    fn acceleration(&self, d: f64, v: f64, a: f64) -> f64 {
        self.ka[0] * d + self.ka[1] * v + self.ka[2] * a
    }

    fn velocity(&self, d: f64, v: f64, a: f64) -> f64 {
        self.kv[0] * d + self.kv[1] * v + self.kv[2] * a
    }

    /// Sets the friction force for an increment Δ that holds the effect of `previous` (force on the
    /// friction DOF `f` whose unit response J⁻¹e_f is `resp`, start speed and acceleration `va`) and
    /// moves Δ to match: Δ is affine in the force, so stick (the force that stops the DOF at the end of
    /// the step, if the contact can hold it) or slip is decided exactly. Returns (force, stuck).
    fn resolve_friction(
        &self,
        fr: &Friction,
        locked: bool,
        (f, resp): (usize, &[f64]),
        delta: &mut [f64],
        (v, a): (f64, f64),
        previous: f64,
    ) -> (f64, bool) {
        let scale = 1.0 - self.af;
        let per = self.kv[0] * scale * resp[f];
        let free = self.velocity(delta[f], v, a) - per * previous;
        let (next, stuck) = friction_force(free, per, fr.hold(locked), fr.kinetic);
        for (d, r) in delta.iter_mut().zip(resp) {
            *d += scale * (next - previous) * r;
        }
        (next, stuck)
    }

    /// The increment that brings a DOF to rest at the end of the step (v₁ = 0).
    fn increment_to_rest(&self, v: f64, a: f64) -> f64 {
        (-self.kv[1] * v - self.kv[2] * a) / self.kv[0]
    }
}

/// Friction force for a step whose end speed would be `speed` without it and changes by
/// `per_force` per unit force: the force that stops the DOF exactly if the contact can hold it
/// (stick), else the kinetic capacity against the motion (slip).
fn friction_force(speed: f64, per_force: f64, hold: f64, kinetic: f64) -> (f64, bool) {
    let stick = -speed / per_force;
    if stick.abs() <= hold {
        (stick, true)
    } else {
        (kinetic * stick.signum(), false)
    }
}

#[derive(Default)]
struct Work {
    f1: Vec<f64>,
    f0: Vec<f64>,
    fi: Vec<f64>,
    fi0: Vec<f64>,
    q1: Vec<f64>,
    v1: Vec<f64>,
    r: Vec<f64>,
    delta: Vec<f64>,
    step: Vec<f64>,
    padded: Vec<f64>,
    key: Vec<u64>,
    key_new: Vec<u64>,
    /// What a linear step's map multiplies besides the speeds and accelerations, which it reads in
    /// place: [x; u], the positions less the rigid rotation and the inputs interpolated to the α-point
    /// (sized by the step).
    z: Vec<f64>,
}

impl Work {
    /// The check every step makes, inlined; the rebuild stays out of line.
    #[inline(always)]
    fn fit(&mut self, n: usize) {
        if self.f1.len() != n {
            self.refit(n);
        }
    }

    #[cold]
    #[inline(never)]
    fn refit(&mut self, n: usize) {
        {
            let z = vec![0.0; n];
            *self = Self {
                f1: z.clone(),
                f0: z.clone(),
                fi: z.clone(),
                fi0: z.clone(),
                q1: z.clone(),
                v1: z.clone(),
                r: z.clone(),
                delta: z.clone(),
                step: z.clone(),
                padded: vec![0.0; padded(n)],
                key: Vec::new(),
                key_new: Vec::new(),
                z,
            };
        }
    }
}

/// The integrator with its cache of factorisations and scratch vectors. Cloning gives an empty
/// cache, refilled on demand: with identical factors where J does not depend on the point it is
/// assembled at (the linear classes), so their snapshots stay cheap and bit-identical; the nearly
/// piecewise-linear class's depend on it ([`Newton::keep`] says what its owner does about that).
pub struct AlphaIntegrator {
    pub params: Alpha,
    /// The nearly piecewise-linear class's iteration (default: as every class).
    pub newton: Newton,
    /// [`Newton::keep`]: the cache entry of the factorisation the last step converged on.
    kept: Option<usize>,
    /// [`Newton::keep`]: the steps taken the default way since the kept iteration last gave up, while
    /// none of them has converged within [`RATTLE_ITERATIONS`] (None: the kept iteration goes first).
    /// History, as `kept` is.
    rattle_run: Option<u32>,
    /// The coefficients of the last step size (seven divisions saved per step).
    coefficients: Option<Coefficients>,
    cache: Cache,
    /// The sparsity ordering of the patterns J has had: history, as the factorisations are.
    orderings: Orderings,
    work: Work,
    /// Whether a Newton step leaves its end's internal forces from its own equation of motion
    /// ([`Self::end_forces`]) instead of its owner evaluating them again.
    pub forces_by_equation: bool,
    /// With `forces_by_equation`: f_int at the end of the last step, by its equation, and the state
    /// it belongs to (the next step within one call of the driver starts from them).
    end: ForcesAt,
}

impl Clone for AlphaIntegrator {
    fn clone(&self) -> Self {
        let mut c = Self::new(self.params);
        c.newton = self.newton;
        c.forces_by_equation = self.forces_by_equation;
        c
    }
}

impl AlphaIntegrator {
    pub fn new(params: Alpha) -> Self {
        Self {
            params,
            newton: Newton::default(),
            kept: None,
            rattle_run: None,
            coefficients: None,
            cache: Cache::default(),
            orderings: Orderings::default(),
            work: Work::default(),
            forces_by_equation: false,
            end: ForcesAt::default(),
        }
    }

    /// f_int at (q, v) when the last step ended there and left it ([`Self::forces_by_equation`]).
    pub fn end_forces(&self, q: &[f64], v: &[f64]) -> Option<&[f64]> {
        self.end.at(q, v)
    }

    /// Forgets the end forces: the system's forces may have changed with its owner's inputs (the
    /// gearbox's rotor loads follow its inputs) between two calls of the driver.
    pub fn forget_end_forces(&mut self) {
        self.end.valid = false;
    }

    /// Drops every factorisation, the one [`Newton::keep`] carries from step to step with the cached
    /// ones, the sparsity ordering the patterns met so far made and the run of steps taken the default
    /// way after a restart: the next step builds its own where it needs them, as a clone does.
    pub fn forget_factorisations(&mut self) {
        self.kept = None;
        self.rattle_run = None;
        self.cache = Cache::default();
        self.orderings = Orderings::default();
    }

    /// A cached factorisation for this key and step size that already holds the friction response
    /// the step needs: the lookup every step makes, kept small enough to inline.
    #[inline(always)]
    fn cached(&mut self, key: &[u64], h: f64, friction_dof: Option<usize>) -> Option<usize> {
        let i = self.cache.find(key, h)?;
        (friction_dof.is_none() || self.cache.get(i).friction_response.as_ref().map(|f| f.0) == friction_dof)
            .then_some(i)
    }

    /// Index of the cached factorisation of J for this step size and key, computed when new.
    fn factor<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        c: &Coefficients,
        at: (f64, &[f64], &[f64]),
        key_from_work: bool,
        friction_dof: Option<usize>,
        stats: &mut Statistics,
    ) -> Result<usize, SolverError> {
        // a smooth nonlinear tangent changes with every iterate: never reuse it
        if sys.linearity() != Linearity::Nonlinear {
            // the key is taken out of the scratch for the lookup, which borrows the integrator
            let key = std::mem::take(&mut self.work.key);
            let key_used: &[u64] = if key_from_work { &key } else { &[] };
            let hit = self.cached(key_used, c.h, friction_dof).or_else(|| {
                // a factor first built while the friction contact was open lacks its response
                let i = self.cache.find(key_used, c.h)?;
                let entry = self.cache.get_mut(i);
                if let Some(d) = friction_dof {
                    entry.friction_response = Some((d, entry.solver.unit_response(sys.dofs(), d)));
                }
                Some(i)
            });
            self.work.key = key;
            if let Some(i) = hit {
                return Ok(i);
            }
        }
        self.build(sys, c, at, key_from_work, friction_dof, stats)
    }

    /// Assembles and factorises J and what the steps take from it, and caches them.
    #[inline(never)]
    fn build<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        c: &Coefficients,
        (t, q, v): (f64, &[f64], &[f64]),
        key_from_work: bool,
        friction_dof: Option<usize>,
        stats: &mut Statistics,
    ) -> Result<usize, SolverError> {
        let key: &[u64] = if key_from_work { &self.work.key } else { &[] };
        let linear = sys.linearity() == Linearity::Linear;
        let n = sys.dofs();
        let mut j = DMatrix::zeros(n, n);
        sys.mass().add_to(c.c_m, &mut j);
        sys.add_tangent(t, q, v, c.c_c, c.c_k, &mut j);
        let reused = sys.linearity() != Linearity::Nonlinear;
        let solver = if self.newton.sparse {
            Solver::new_with(j, reused, &mut self.orderings)
        } else {
            Solver::new(j, reused)
        };
        let solver = solver.ok_or(SolverError::SingularJacobian { time: t, step: c.h })?;
        let friction_response = friction_dof.map(|d| (d, solver.unit_response(n, d)));
        let step_map = linear.then(|| linear::step_map(sys, c, &solver));
        stats.factorizations += 1;
        let key = key.to_vec();
        Ok(self.cache.insert(Factor {
            key,
            h: c.h,
            solver,
            friction_response,
            step_map,
        }))
    }

    /// The coefficients of step size `h`, kept from the last step when it had the same size.
    #[inline(always)]
    fn coefficients_for(&mut self, h: f64) -> Coefficients {
        match self.coefficients {
            Some(c) if same_step(c.h, h) => c,
            _ => {
                let c = Coefficients::new(&self.params, h);
                self.coefficients = Some(c);
                c
            }
        }
    }

    /// Advances `st` over `span`. On error `st` is unchanged.
    pub fn step<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        span: &Span,
        stats: &mut Statistics,
    ) -> Result<(), SolverError> {
        let Span { h, u1, .. } = *span;
        let n = sys.dofs();
        self.work.fit(n);
        let c = self.coefficients_for(h);
        let friction = sys.friction(u1).filter(|f| f.kinetic > 0.0 || f.holding > 0.0);
        let linear = sys.linearity() == Linearity::Linear;
        if linear {
            self.linear_step(sys, st, &c, span, friction, stats)
        } else {
            self.newton_step(sys, st, &c, span, friction, stats)
        }?;
        stats.steps += 1;
        Ok(())
    }

    /// The Newton iteration for piecewise-linear and nonlinear systems.
    fn newton_step<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        c: &Coefficients,
        span: &Span,
        friction: Option<Friction>,
        stats: &mut Statistics,
    ) -> Result<(), SolverError> {
        let Span { t, u0, u1, .. } = *span;
        let n = sys.dofs();
        let friction_dof = friction.map(|f| f.dof);
        {
            let w = &mut self.work;
            external_forces(sys, u1, &mut w.f1);
            if c.af != 0.0 {
                external_forces(sys, u0, &mut w.f0);
                // given ones first: the last step's end forces are compared with the state only without
                match span.fi0.or_else(|| self.end.at(&st.q, &st.v)) {
                    Some(fi) => w.fi0[..n].copy_from_slice(&fi[..n]),
                    None => sys.internal_forces(t, &st.q, &st.v, &mut w.fi0),
                }
                if let Some(f) = friction_dof {
                    w.f0[f] += st.friction_force;
                }
            }
        }
        let nearly = sys.linearity() == Linearity::NearlyPiecewiseLinear;
        let keep = nearly && self.newton.keep;
        let predict = nearly && self.newton.predict;
        // a step after the kept iteration gave up goes the default way at once (RATTLE_ITERATIONS)
        let rattling = keep && self.rattle_run.is_some();
        if !keep || rattling {
            sys.factor_key(t, &st.q, &mut self.work.key);
        }
        let mut outcome = None;
        if keep && !rattling {
            self.work.start(st, c, predict);
            outcome = self.kept_iteration(sys, st, c, t, friction, stats)?;
            if outcome.is_none() {
                stats.newton_restarts += 1;
                sys.factor_key(t, &st.q, &mut self.work.key);
            }
        }
        let (force, held) = match outcome {
            Some(done) => {
                self.rattle_run = None;
                done
            }
            None => {
                // a restarted step is taken the default way, from Δ = 0
                self.work.start(st, c, predict && !keep);
                let before = stats.newton_iterations;
                let (force, held, idx) = self.pattern_iteration(sys, st, c, t, friction, stats)?;
                if keep {
                    self.kept = Some(idx);
                    self.rattle_run = match self.rattle_run {
                        // a restart starts a run
                        None => Some(0),
                        Some(run) => {
                            stats.newton_rattle_steps += 1;
                            let settled = stats.newton_iterations - before <= RATTLE_ITERATIONS;
                            (!settled && run + 1 < RATTLE_RUN).then_some(run + 1)
                        }
                    };
                }
                (force, held)
            }
        };
        let w = &mut self.work;
        let stuck = friction_dof.filter(|_| held);
        if let Some(f) = stuck {
            w.delta[f] = c.increment_to_rest(st.v[f], st.a[f]);
        }
        if self.forces_by_equation {
            // the start's accelerations into r (free after the iteration), for the end forces
            w.r[..n].copy_from_slice(&st.a[..n]);
        }
        for d in 0..n {
            let (dd, v, a) = (w.delta[d], st.v[d], st.a[d]);
            st.q[d] += dd;
            st.v[d] = c.velocity(dd, v, a);
            st.a[d] = c.acceleration(dd, v, a);
        }
        finish_friction(st, stuck, force, u1);
        self.end.valid = false;
        if self.forces_by_equation {
            self.equation_forces(sys, st, c, friction_dof);
        }
        Ok(())
    }

    /// [`Self::forces_by_equation`]: f_int at the step's end as its equation of motion has it,
    /// M·((1 − α_m)·a₁ + α_m·a₀) = (1 − α_f)·(f₁ − f_int,1 + friction) + α_f·(f₀ − f_int,0), solved
    /// for f_int,1 with the accelerations the step ended with (the start's in `r`). The Newton
    /// iteration solved that equation to its tolerance at the iterate before its last increment,
    /// so these differ from an evaluation at the end by what that increment, below the tolerance,
    /// moves the forces beyond the tangent's prediction; an evaluation costs as much as an iteration.
    fn equation_forces<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &DynState,
        c: &Coefficients,
        friction_dof: Option<usize>,
    ) {
        let n = sys.dofs();
        let w = &mut self.work;
        for d in 0..n {
            w.step[d] = (1.0 - c.am) * st.a[d] + c.am * w.r[d];
        }
        let forces = &mut self.end.forces;
        forces.clear();
        forces.resize(n, 0.0);
        sys.mass().add_product(-1.0, &w.step, forces);
        let weight = 1.0 - c.af;
        for d in 0..n {
            let start = if c.af != 0.0 { c.af * (w.f0[d] - w.fi0[d]) } else { 0.0 };
            forces[d] = w.f1[d] + (start + forces[d]) / weight;
        }
        if let Some(f) = friction_dof {
            forces[f] += st.friction_force;
        }
        self.end.belong_to(&st.q, &st.v);
    }

    /// The iteration every class takes from the Δ in the work: the factorisation of the start's
    /// pattern, a new one (cached per pattern) whenever an iterate's pattern changes. Returns the
    /// friction force, whether the contact holds, and the cache entry it converged on.
    fn pattern_iteration<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &DynState,
        c: &Coefficients,
        t: f64,
        friction: Option<Friction>,
        stats: &mut Statistics,
    ) -> Result<(f64, bool, usize), SolverError> {
        let t1 = t + c.h;
        let linearity = sys.linearity();
        let friction_dof = friction.map(|f| f.dof);
        let mut idx = self.factor(sys, c, (t1, &st.q, &st.v), true, friction_dof, stats)?;
        let mut force = 0.0;
        let mut held = false;
        let mut residual = f64::INFINITY;
        // ‖δ‖∞ of the last STALL_ITERATIONS iterations, by iteration modulo their count
        let mut sizes = [f64::INFINITY; STALL_ITERATIONS];
        for iteration in 0.. {
            if iteration == MAX_ITERATIONS {
                return Err(match linearity {
                    Linearity::Nonlinear | Linearity::NearlyPiecewiseLinear => SolverError::NewtonDiverged {
                        time: t,
                        iterations: iteration,
                        residual,
                    },
                    _ => SolverError::ContactNotSettled {
                        time: t,
                        iterations: iteration,
                    },
                });
            }
            stats.newton_iterations += 1;
            let AlphaIntegrator { cache, work: w, .. } = self;
            let factor = cache.get(idx);
            // r = −R(Δ) with the friction force of the current iterate
            residual = w.residual(sys, st, c, t1, friction_dof, force);
            // a residual at the rounding level of the forces themselves cannot be reduced further
            // (only the smooth classes ask: the piecewise-linear one converges on its pattern)
            // past RELAXED_AFTER iterations a residual ten times the tolerance is the rounding floor the
            // iteration stalls at (absolute angles of 1500 rad with the loads of a held rotor), and each
            // increment is halved
            let relaxed = linearity == Linearity::NearlyPiecewiseLinear && iteration >= RELAXED_AFTER;
            let floor = if relaxed { 10.0 } else { 1.0 };
            (force, held) = w.increment(factor, c, friction, st, relaxed, (force, held));
            let converged = match linearity {
                Linearity::Linear => true,
                Linearity::PiecewiseLinear => w.same_pattern(sys, st, t1),
                Linearity::NearlyPiecewiseLinear => {
                    w.same_pattern(sys, st, t1)
                        && (w.settled(residual, floor)
                            || small_increment(w, st, c, self.newton.tolerance, self.newton.motion_floor))
                }
                Linearity::Nonlinear => {
                    w.settled(residual, floor) || small_increment(w, st, c, INCREMENT_TOLERANCE, 0.0)
                }
            };
            if converged {
                break;
            }
            if linearity == Linearity::NearlyPiecewiseLinear {
                let size = max_abs(&w.step);
                let before = std::mem::replace(&mut sizes[iteration % STALL_ITERATIONS], size);
                if iteration >= RELAXED_AFTER + STALL_ITERATIONS && size > 0.5 * before {
                    return Err(SolverError::NewtonDiverged {
                        time: t,
                        iterations: iteration + 1,
                        residual,
                    });
                }
            }
            idx = self.factor_at_iterate(sys, st, c, t1, friction_dof, false, stats)?;
        }
        Ok((force, held, idx))
    }

    /// [`Newton::keep`]: modified Newton from the Δ in the work on the factorisation the last step
    /// converged on (the start's pattern's when there is none for this step size), refreshed once at
    /// the iterate when the iteration contracts slowly or not within [`KEPT_ITERATIONS`]. Returns the
    /// friction force and whether the contact holds, or None when even the fresh factorisation stalls
    /// (the caller retakes the step the default way).
    fn kept_iteration<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &DynState,
        c: &Coefficients,
        t: f64,
        friction: Option<Friction>,
        stats: &mut Statistics,
    ) -> Result<Option<(f64, bool)>, SolverError> {
        let n = sys.dofs();
        let t1 = t + c.h;
        let friction_dof = friction.map(|f| f.dof);
        let kept = self
            .kept
            .filter(|&i| self.cache.holds(i) && same_step(self.cache.get(i).h, c.h));
        let mut idx = match kept {
            Some(i) => {
                let entry = self.cache.get_mut(i);
                if let Some(d) = friction_dof
                    && entry.friction_response.as_ref().map(|f| f.0) != Some(d)
                {
                    entry.friction_response = Some((d, entry.solver.unit_response(n, d)));
                }
                i
            }
            None => {
                sys.factor_key(t, &st.q, &mut self.work.key);
                self.factor(sys, c, (t1, &st.q, &st.v), true, friction_dof, stats)?
            }
        };
        let mut fresh = false;
        let mut on_factor = 0;
        // ‖δ‖∞ of the previous iteration on this factorisation (NaN: none yet)
        let mut previous = f64::NAN;
        let (mut force, mut held) = (0.0, false);
        for _ in 0..2 * KEPT_ITERATIONS {
            stats.newton_iterations += 1;
            let AlphaIntegrator { cache, work: w, .. } = self;
            let factor = cache.get(idx);
            let residual = w.residual(sys, st, c, t1, friction_dof, force);
            (force, held) = w.increment(factor, c, friction, st, false, (force, held));
            on_factor += 1;
            let size = max_abs(&w.step);
            // the contraction rate θ of the increments on one J: the new iterate is within
            // η·‖δ‖ of the solution, η = θ/(1 − θ), and the increment test asks that of this error
            // (with η no smaller than ETA_FLOOR); ‖δ‖ itself on the first iteration on a J
            let theta = size / previous;
            previous = size;
            let eta = if theta.is_nan() {
                1.0
            } else if theta < 1.0 {
                (theta / (1.0 - theta)).max(ETA_FLOOR)
            } else {
                f64::INFINITY
            };
            let fraction = self.newton.tolerance / eta;
            // no pattern test: the forces are continuous across a change of contact pattern, so an
            // increment small enough here moves the residual as little whether or not it changed one
            // (the default iteration compares patterns because its J is the pattern's). A varying
            // mesh stiffness steps with the teeth's roll: an increment at the tolerance (some 10⁻⁸
            // of a base pitch) seldom straddles such a step, and the next step starts from the
            // forces at the state accepted
            if w.settled(residual, 1.0) || small_increment(w, st, c, fraction, self.newton.motion_floor) {
                self.kept = Some(idx);
                return Ok(Some((force, held)));
            }
            let stalled = on_factor == KEPT_ITERATIONS;
            if fresh && (stalled || theta >= 1.0) {
                break;
            }
            if !fresh && (stalled || theta > THETA_REFRESH) {
                // the fresh factorisation is cached under the iterate's own pattern
                self.work.key_at_iterate(sys, st, t1);
                idx = self.factor_at_iterate(sys, st, c, t1, friction_dof, true, stats)?;
                fresh = true;
                on_factor = 0;
                previous = f64::NAN;
            }
        }
        self.kept = None;
        Ok(None)
    }

    /// The factorisation at the current iterate, for its pattern (the key in the work): the cached
    /// one, or built afresh (`fresh`, or none cached).
    #[allow(clippy::too_many_arguments)]
    fn factor_at_iterate<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &DynState,
        c: &Coefficients,
        t1: f64,
        friction_dof: Option<usize>,
        fresh: bool,
        stats: &mut Statistics,
    ) -> Result<usize, SolverError> {
        let n = sys.dofs();
        let w = &mut self.work;
        for d in 0..n {
            w.q1[d] = st.q[d] + w.delta[d];
            w.v1[d] = c.velocity(w.delta[d], st.v[d], st.a[d]);
        }
        let (q1, v1) = (std::mem::take(&mut w.q1), std::mem::take(&mut w.v1));
        let found = if fresh {
            self.build(sys, c, (t1, &q1, &v1), true, friction_dof, stats)
        } else {
            self.factor(sys, c, (t1, &q1, &v1), true, friction_dof, stats)
        };
        self.work.q1 = q1;
        self.work.v1 = v1;
        found
    }
}

impl Work {
    /// The iteration's first Δ: zero, or the constant-acceleration predictor h·v + ½h²·a.
    fn start(&mut self, st: &DynState, c: &Coefficients, predict: bool) {
        if predict {
            for (d, (v, a)) in self.delta.iter_mut().zip(st.v.iter().zip(&st.a)) {
                *d = c.h * v + 0.5 * c.h * c.h * a;
            }
        } else {
            self.delta.iter_mut().for_each(|x| *x = 0.0);
        }
    }

    /// r = −R(Δ) with the friction force `force` of the current iterate; returns ‖r‖∞.
    fn residual<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &DynState,
        c: &Coefficients,
        t1: f64,
        friction_dof: Option<usize>,
        force: f64,
    ) -> f64 {
        let n = sys.dofs();
        // every vector cut to n first: the loops then need no bounds check and the compiler takes two
        // DOFs a register (the same operations on each value; by index with a check per access they
        // went one DOF at a time, a fifth of the residual's instructions besides the forces, callgrind)
        let (q, v, a, delta) = (&st.q[..n], &st.v[..n], &st.a[..n], &self.delta[..n]);
        {
            let (q1, v1) = (&mut self.q1[..n], &mut self.v1[..n]);
            for d in 0..n {
                q1[d] = q[d] + delta[d];
                v1[d] = c.velocity(delta[d], v[d], a[d]);
            }
        }
        sys.internal_forces(t1, &self.q1, &self.v1, &mut self.fi);
        let (step, r) = (&mut self.step[..n], &mut self.r[..n]);
        let (f1, fi, f0, fi0) = (&self.f1[..n], &self.fi[..n], &self.f0[..n], &self.fi0[..n]);
        for d in 0..n {
            let a1 = c.acceleration(delta[d], v[d], a[d]);
            step[d] = (1.0 - c.am) * a1 + c.am * a[d];
            r[d] = (1.0 - c.af) * (f1[d] - fi[d]) + c.af * (f0[d] - fi0[d]);
        }
        if let Some(f) = friction_dof {
            self.r[f] += (1.0 - c.af) * force;
        }
        {
            let (step, r) = (&self.step, &mut self.r);
            sys.mass().add_product(-1.0, step, r);
        }
        max_abs(&self.r)
    }

    /// Whether `residual` (of the iterate the forces in the work were evaluated at) is at the
    /// rounding level of the largest force acting, `floor` times the tolerance.
    fn settled(&self, residual: f64, floor: f64) -> bool {
        residual <= floor * RESIDUAL_TOLERANCE * max_abs(&self.fi).max(max_abs(&self.f1))
    }

    /// δ = J⁻¹r from the residual in `r` (halved when `relaxed`) into `step` and onto Δ, then the
    /// friction force re-solved on that J; `step` is left holding the increment the friction solve
    /// left. Returns the friction force and whether the contact holds.
    fn increment(
        &mut self,
        factor: &Factor,
        c: &Coefficients,
        friction: Option<Friction>,
        st: &DynState,
        relaxed: bool,
        (force, held): (f64, bool),
    ) -> (f64, bool) {
        self.step.iter_mut().for_each(|x| *x = 0.0);
        factor.solver.add_solution(&self.r, &mut self.step);
        if relaxed {
            self.step.iter_mut().for_each(|x| *x *= 0.5);
        }
        // r is free until the next residual: it keeps the iterate this increment starts from
        self.r.copy_from_slice(&self.delta);
        for (d, s) in self.delta.iter_mut().zip(&self.step) {
            *d += s;
        }
        match (friction, &factor.friction_response) {
            (Some(fr), Some((f, resp))) => {
                let solved =
                    c.resolve_friction(&fr, st.locked, (*f, resp), &mut self.delta, (st.v[*f], st.a[*f]), force);
                // the increment that counts for convergence is the one the friction solve left
                for ((s, d), r) in self.step.iter_mut().zip(&self.delta).zip(&self.r) {
                    *s = d - r;
                }
                solved
            }
            _ => (force, held),
        }
    }

    /// The pattern of the iterate Δ into the key.
    fn key_at_iterate<S: SecondOrderSystem>(&mut self, sys: &S, st: &DynState, t1: f64) {
        for ((q1, q), d) in self.q1.iter_mut().zip(&st.q).zip(&self.delta) {
            *q1 = q + d;
        }
        sys.factor_key(t1, &self.q1, &mut self.key);
    }

    /// Whether the pattern at the iterate Δ is the last iterate's; the key in the work becomes the
    /// new iterate's.
    fn same_pattern<S: SecondOrderSystem>(&mut self, sys: &S, st: &DynState, t1: f64) -> bool {
        for ((q1, q), d) in self.q1.iter_mut().zip(&st.q).zip(&self.delta) {
            *q1 = q + d;
        }
        sys.factor_key(t1, &self.q1, &mut self.key_new);
        let same = same_key(&self.key_new, &self.key);
        std::mem::swap(&mut self.key, &mut self.key_new);
        same
    }
}

/// The last Newton increment is below `fraction` of the step's motion (no less than `motion_floor`),
/// or at the resolution of the positions themselves (a few ulps of absolute angles of thousands of
/// radians: an increment there is rounding, not progress).
fn small_increment(w: &Work, st: &DynState, c: &Coefficients, fraction: f64, motion_floor: f64) -> bool {
    let size = max_abs(&w.delta);
    let motion = max_abs(&st.v) * c.h;
    let tolerance = fraction * size.max(motion).max(motion_floor).max(f64::MIN_POSITIVE);
    w.step
        .iter()
        .zip(st.q.iter().zip(&w.delta))
        .all(|(s, (q, d))| s.abs() <= tolerance.max(8.0 * f64::EPSILON * (q + d).abs()))
}

/// Friction bookkeeping at the end of a step: a stuck DOF is exactly at rest.
fn finish_friction(st: &mut DynState, stuck: Option<usize>, force: f64, u1: &[f64]) {
    if let Some(f) = stuck {
        st.v[f] = 0.0;
        st.a[f] = 0.0;
    }
    st.locked = stuck.is_some();
    st.friction_force = force;
    st.applied.clear();
    st.applied.extend_from_slice(u1);
}

#[cfg(test)]
mod tests {
    use super::{Alpha, AlphaIntegrator, RELAXED_AFTER, STALL_ITERATIONS, Span};
    use crate::solver::state::{DynState, SolverError, Statistics};
    use crate::solver::system::{InputLoad, Linearity, Mass, SecondOrderSystem};
    use nalgebra::DMatrix;

    /// One unit mass on a spring of force `force(q)` and stiffness `tangent(q)` (what its Jacobian is
    /// told), pushed by an input load.
    struct OneDof<F, K> {
        force: F,
        tangent: K,
        loads: [InputLoad; 1],
    }

    impl<F: Fn(f64) -> f64, K: Fn(f64) -> f64> SecondOrderSystem for OneDof<F, K> {
        fn dofs(&self) -> usize {
            1
        }
        fn linearity(&self) -> Linearity {
            Linearity::NearlyPiecewiseLinear
        }
        fn mass(&self) -> Mass<'_> {
            Mass::Diagonal(&[1.0])
        }
        fn input_loads(&self) -> &[InputLoad] {
            &self.loads
        }
        fn internal_forces(&self, _: f64, q: &[f64], _: &[f64], out: &mut [f64]) {
            out[0] = (self.force)(q[0]);
        }
        fn add_tangent(&self, _: f64, q: &[f64], _: &[f64], _: f64, c_k: f64, j: &mut DMatrix<f64>) {
            j[(0, 0)] += c_k * (self.tangent)(q[0]);
        }
    }

    /// One Newmark step of 1 ms of the spring (`force`, `tangent`) from (q, v) under the load `push`
    /// with the iteration `newton`: its result, the end state and the step's Newton iterations.
    fn one_dof_step(
        (force, tangent): (impl Fn(f64) -> f64, impl Fn(f64) -> f64),
        newton: super::Newton,
        (q, v): (f64, f64),
        push: f64,
    ) -> (Result<(), SolverError>, DynState, u64) {
        let sys = OneDof {
            force,
            tangent,
            loads: [InputLoad {
                input: 0,
                dof: 0,
                gain: 1.0,
            }],
        };
        let mut st = DynState::new(vec![q], vec![v]);
        let u = [push];
        let span = Span {
            t: 0.0,
            h: 1e-3,
            u0: &u,
            u1: &u,
            fi0: None,
        };
        let mut stats = Statistics::default();
        let mut integrator = AlphaIntegrator::new(Alpha::NEWMARK);
        integrator.newton = newton;
        let result = integrator.step(&sys, &mut st, &span, &mut stats).map(|_| ());
        (result, st, stats.newton_iterations)
    }

    /// A step whose iterates cycle across a kink is given up once its relaxed increments have stopped
    /// halving for STALL_ITERATIONS iterations, not after MAX_ITERATIONS; the same iteration without a
    /// kink (no jump) converges. The kink: a contact force that jumps by `jump` as it closes at q = 0 (a
    /// damping force acting from first touch does so), pushed by half that jump, so that no displacement
    /// balances the push.
    #[test]
    fn a_cycle_across_a_kink_is_given_up_once_it_stalls() {
        let step = |jump: f64| {
            let kink = (move |q: f64| 10.0 * q + if q > 0.0 { jump } else { 0.0 }, |_: f64| 10.0);
            let (result, _, iterations) = one_dof_step(kink, super::Newton::PATTERN, (0.0, 0.0), 50.0);
            (result, iterations)
        };
        let (result, iterations) = step(100.0);
        match result {
            Err(SolverError::NewtonDiverged { iterations: n, .. }) => {
                assert_eq!(n as u64, iterations);
                assert_eq!(n, RELAXED_AFTER + STALL_ITERATIONS + 1);
            }
            other => panic!("{other:?} after {iterations} iterations"),
        }
        let (result, iterations) = step(0.0);
        assert!(
            result.is_ok() && iterations <= 3,
            "{result:?} after {iterations} iterations"
        );
    }

    /// `motion_floor`: a step that barely moves (a held gearbox) ends its iteration at the tolerance
    /// times the floor instead of times its own nanometre, in fewer iterations and within that
    /// resolution of the iteration without the floor; a step that moves by more than the floor is
    /// untouched, bit for bit. Both with and without the kept factorisation. The spring stiffens,
    /// f = k·q·(1 + (q/a)²), and its tangent is understated by a fifth (as the gearbox's leaves out
    /// frame terms), so that its modified Newton iteration contracts by about a fifth an iteration.
    #[test]
    fn a_step_that_barely_moves_is_resolved_to_the_motion_floor() {
        const K: f64 = 1e4;
        const A: f64 = 1e-4;
        let force = |q: f64| K * q * (1.0 + (q / A) * (q / A));
        let spring = (force, |q: f64| 0.8 * K * (1.0 + 3.0 * (q / A) * (q / A)));
        // pushed beyond the load that balances q = a
        let step = |newton, v| {
            let (result, st, iterations) = one_dof_step(spring, newton, (A, v), force(A) + 2e-3);
            result.unwrap();
            (st, iterations)
        };
        for base in [super::Newton::PATTERN, super::Newton::parse("kept+predicted").unwrap()] {
            let floored = super::Newton {
                motion_floor: 1e-3,
                ..base
            };
            // held: at rest, the push moves the mass by about a nanometre within the step
            let (exact, n_exact) = step(base, 0.0);
            let (fast, n_fast) = step(floored, 0.0);
            let moved = (exact.q[0] - A).abs();
            assert!(moved > 1e-10 && moved < 1e-8, "{moved:e}");
            assert!(
                n_fast < n_exact,
                "{n_fast} iterations with the floor, {n_exact} without"
            );
            let resolution = base.tolerance * floored.motion_floor;
            assert!(
                (fast.q[0] - exact.q[0]).abs() <= resolution,
                "{:e} from the iteration without the floor, resolution {resolution:e}",
                fast.q[0] - exact.q[0]
            );
            // moving: 10 mm a step, ten times the floor
            let (a, n_a) = step(base, 10.0);
            let (b, n_b) = step(floored, 10.0);
            assert_eq!(
                (a.q[0].to_bits(), a.v[0].to_bits(), n_a),
                (b.q[0].to_bits(), b.v[0].to_bits(), n_b)
            );
        }
    }

    /// Newmark keeps every mode (radius 1 at any h·ω); HHT-α and generalised-α tend to their ρ∞ as
    /// h·ω grows and leave low modes (h·ω = 0.01) within 1e-6 of 1.
    #[test]
    fn amplification_radius_limits() {
        for omega_h in [0.01, 1.0, 10.0, 1e4] {
            assert!((Alpha::NEWMARK.amplification_radius(omega_h) - 1.0).abs() < 1e-12);
        }
        for rho in [0.5, 0.6, 0.9] {
            let p = Alpha::hht(rho).unwrap();
            assert!(
                (p.amplification_radius(1e6) - rho).abs() < 1e-4,
                "hht {rho}: {}",
                p.amplification_radius(1e6)
            );
            assert!((p.amplification_radius(0.01) - 1.0).abs() < 1e-6);
        }
        for rho in [0.0, 0.3, 0.8] {
            let p = Alpha::generalised(rho).unwrap();
            assert!(
                (p.amplification_radius(1e6) - rho).abs() < 1e-3,
                "generalised {rho}: {}",
                p.amplification_radius(1e6)
            );
            assert!((p.amplification_radius(0.01) - 1.0).abs() < 1e-6);
        }
    }
}
