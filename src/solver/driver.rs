//! One communication step of any [`SecondOrderSystem`]: inputs sampled from the host's input
//! polynomial, consistent accelerations at the communication point, sub-steps no longer than the
//! model allows, step halving where a contact event or a Newton iteration needs it, the explicit
//! method's stability limit, friction lock and release reported as events, and a final check that
//! the state is finite. FMU faces call [`Driver::advance`] and nothing below it.

use super::alpha::{Alpha, AlphaIntegrator, Newton, Span};
use super::rk4::{MassSolver, Rk4};
use super::state::{DynState, SolverError, Statistics};
use super::system::{Friction, Linearity, Mass, SecondOrderSystem, external_forces};

/// Deepest halving of a sub-step whose contact pattern or Newton iteration does not settle:
/// 2⁻¹² of a sub-step (0.24 µs at 1 ms) resolves any mesh contact event of these drivetrains.
pub const MAX_HALVINGS: u32 = 12;

/// Newton iterations one `advance` may spend per internal step, plus a spare for a contact event's
/// halvings: a communication step's work stays proportional to its length, whatever its inputs.
/// The implicit steps of these drivetrains take 1 to 6 iterations, a contact event a few halvings;
/// an input thousands of times a model's rating makes every step iterate and halve, for minutes.
const ITERATIONS_PER_STEP: u64 = 32;
const ITERATIONS_SPARE: u64 = 1 << MAX_HALVINGS;

/// The integration method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Generalised-α family (Newmark average acceleration, HHT-α, generalised-α).
    Implicit(Alpha),
    /// Explicit RK4, refused above `stability_limit` (s).
    Rk4 { stability_limit: f64 },
}

/// A friction contact locking (stiction) or releasing (slipping) at `time`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    pub time: f64,
    pub locked: bool,
}

#[derive(Clone)]
pub struct Driver {
    pub method: Method,
    alpha: AlphaIntegrator,
    rk4: Rk4,
    pub stats: Statistics,
    /// Lock changes of the last `advance`.
    pub events: Vec<Event>,
    u0: Vec<f64>,
    u1: Vec<f64>,
    f: Vec<f64>,
    fi: Vec<f64>,
    /// `fi` holds the internal forces at the communication point's state (the consistent
    /// accelerations evaluated them), which the first sub-step's start-weighted methods reuse.
    fi_at_start: bool,
    /// Whether the first sub-step reuses `fi` (true, the default); false evaluates them afresh, the
    /// check that reusing them changes no bit.
    pub reuse_start_forces: bool,
    /// `fi` holds the internal forces at the state the next `advance` starts from, given by the
    /// caller ([`Driver::give_start_forces`]).
    start_forces_given: bool,
    /// Whether a step that qualifies takes [`Driver::plain_linear_step`] (true, the default); false
    /// takes every step the general way, the check that the plain way changes no bit.
    pub plain_linear_steps: bool,
    /// The friction force's accelerations (dense mass).
    friction_a: Vec<f64>,
    /// The dense mass matrix's factor for consistent accelerations.
    mass: MassSolver,
    /// Most internal steps one `advance` may take: a host's absurd communication step (1e6 s) is
    /// refused at once instead of running for minutes.
    pub max_steps_per_call: f64,
    /// `stats.newton_iterations` when the running `advance` began, and the iterations it may spend
    /// (see [`ITERATIONS_PER_STEP`]).
    iteration_start: u64,
    iteration_budget: u64,
}

impl Driver {
    pub fn new(method: Method) -> Self {
        let alpha = match method {
            Method::Implicit(p) => p,
            Method::Rk4 { .. } => Alpha::NEWMARK,
        };
        Self {
            method,
            alpha: AlphaIntegrator::new(alpha),
            rk4: Rk4::default(),
            stats: Statistics::default(),
            events: Vec::new(),
            u0: Vec::new(),
            u1: Vec::new(),
            f: Vec::new(),
            fi: Vec::new(),
            fi_at_start: false,
            reuse_start_forces: true,
            start_forces_given: false,
            plain_linear_steps: true,
            friction_a: Vec::new(),
            mass: MassSolver::default(),
            max_steps_per_call: 1e6,
            iteration_start: 0,
            iteration_budget: u64::MAX,
        }
    }

    /// The Newton iteration of the nearly piecewise-linear class ([`Newton`]; default: as every class).
    pub fn set_newton(&mut self, newton: Newton) {
        self.alpha.newton = newton;
    }

    /// Whether the implicit integrator's Newton steps leave their end's internal forces from their own
    /// equation of motion ([`AlphaIntegrator::forces_by_equation`]; [`Self::end_forces`]).
    pub fn set_forces_by_equation(&mut self, on: bool) {
        self.alpha.forces_by_equation = on;
    }

    /// f_int at (q, v) when the last call's last step ended there and left it by its equation of
    /// motion ([`Self::set_forces_by_equation`]): the owner may hand it to the next call
    /// ([`Self::give_start_forces`]) once it has made it its own inputs' (the system's forces that
    /// follow the owner's inputs are in it as they were during that call).
    pub fn end_forces(&self, q: &[f64], v: &[f64]) -> Option<&[f64]> {
        self.alpha.end_forces(q, v)
    }

    /// Drops every factorisation the integrator holds, kept or cached, and the history that picks
    /// between them: the next step builds the ones it needs, as after a rebuild (an FMU state taken or
    /// restored; see [`Newton::keep`]).
    pub fn forget_factorisations(&mut self) {
        self.alpha.forget_factorisations();
    }

    /// The internal forces at the state the next [`Self::advance`] starts from, from a caller that has
    /// them (the 6-DOF gearbox evaluates them for the loads it reports at a communication point):
    /// that advance takes them for its consistent accelerations instead of evaluating them again.
    /// `fill` writes exactly what `internal_forces` would at that state, to the bit; the next
    /// advance forgets them, whether it used them or not.
    pub fn give_start_forces(&mut self, n: usize, fill: impl FnOnce(&mut [f64])) {
        self.fi.resize(n, 0.0);
        fill(&mut self.fi[..n]);
        self.start_forces_given = true;
    }

    /// Advances `st` from `t` by `h` in sub-steps of at most `max_step`; `inputs(τ, u)` writes the
    /// inputs τ seconds after `t` into `u` (length `input_count`). On error the state may be
    /// part-way through the step; the caller treats the instance as failed.
    ///
    /// A linear system whose communication step is one internal step and whose friction contact
    /// is open takes [`Self::plain_linear_step`]: the same arithmetic as the general way below,
    /// so the same bits, without its bookkeeping.
    #[allow(clippy::too_many_arguments)]
    pub fn advance<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        t: f64,
        h: f64,
        max_step: f64,
        input_count: usize,
        inputs: impl Fn(f64, &mut [f64]),
    ) -> Result<(), SolverError> {
        // given forces serve this call or none: taken before any way out of it
        let given = std::mem::take(&mut self.start_forces_given);
        // the last call's end forces are the owner's to hand on: its inputs may have changed them
        self.alpha.forget_end_forces();
        // positive and finite (NaN fails both comparisons), as two comparisons
        if !(0.0 < h && h < f64::INFINITY) {
            return Err(SolverError::BadStep { step: h });
        }
        if !(0.0 < max_step && max_step < f64::INFINITY) {
            return Err(SolverError::BadStep { step: max_step });
        }
        self.events.clear();
        self.u0.resize(input_count, 0.0);
        self.u1.resize(input_count, 0.0);
        // `inputs` only writes `u`: sampling the start before the general way's checks changes nothing
        inputs(0.0, &mut self.u0);
        if self.plain_step_applies(sys, st, h, max_step) {
            inputs(h, &mut self.u1);
            if self.friction_open_at_end(sys) {
                return self.plain_linear_step(sys, st, t, h);
            }
        }
        self.start_forces_given = given;
        self.advance_in_substeps(sys, st, t, h, max_step, &inputs)
    }

    /// Whether the communication step can be [`Self::plain_linear_step`] as far as its start tells:
    /// one internal step covers it (the count `advance_in_substeps` would take), the method is
    /// implicit, the system linear with a lumped mass, the accelerations consistent with inputs
    /// applied before (so only the loaded DOFs' change), and the friction contact open at the start
    /// with no friction force left from the step before.
    #[inline(always)]
    fn plain_step_applies<S: SecondOrderSystem>(&self, sys: &S, st: &DynState, h: f64, max_step: f64) -> bool {
        let n = sys.dofs();
        self.plain_linear_steps
            && matches!(self.method, Method::Implicit(_))
            && h / max_step * (1.0 - 1e-12) <= 1.0
            && self.max_steps_per_call >= 1.0
            && sys.linearity() == Linearity::Linear
            && matches!(sys.mass(), Mass::Diagonal(_))
            && st.applied.len() == self.u0.len()
            && (st.q.len(), st.v.len(), st.a.len()) == (n, n, n)
            && st.friction_force == 0.0
            && active_friction(sys, &self.u0).is_none()
    }

    /// Whether the friction contact is still open at the step's end (`u1`), as the step sees it.
    #[inline(always)]
    fn friction_open_at_end<S: SecondOrderSystem>(&self, sys: &S) -> bool {
        active_friction(sys, &self.u1).is_none()
    }

    /// The communication step as one internal step of a linear system whose friction contact is open
    /// at both ends, inputs `u0` and `u1` already sampled: what `advance_in_substeps` computes in this
    /// case (the consistent accelerations' O(1) update, one sub-step that needs no iteration budget,
    /// halving or lock events, the finiteness check) in the same order of operations, with the
    /// finiteness check folded into the integrator's update.
    fn plain_linear_step<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        t: f64,
        h: f64,
    ) -> Result<(), SolverError> {
        let Mass::Diagonal(m) = sys.mass() else {
            unreachable!("plain_step_applies checked the mass is lumped")
        };
        follow_input_change(sys, st, &self.u0, m);
        self.fi_at_start = false;
        let finite = self
            .alpha
            .plain_linear_step(sys, st, t + 0.0, h, (&self.u0, &self.u1), &mut self.stats)?;
        self.stats.plain_steps += 1;
        if !finite {
            return Err(SolverError::NonFinite { time: t });
        }
        Ok(())
    }

    /// The general way: sub-steps of at most `max_step`, `self.u0` holding the inputs at `t`.
    fn advance_in_substeps<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        t: f64,
        h: f64,
        max_step: f64,
        inputs: &impl Fn(f64, &mut [f64]),
    ) -> Result<(), SolverError> {
        // taken first, so that no way out of this call leaves the given forces for a later one
        let start_forces_given = std::mem::take(&mut self.start_forces_given);
        let substeps = (h / max_step * (1.0 - 1e-12)).ceil().max(1.0);
        if substeps > self.max_steps_per_call {
            return Err(SolverError::TooManySteps {
                step: h,
                steps: substeps,
                limit: self.max_steps_per_call,
            });
        }
        let hs = h / substeps;
        if let Method::Rk4 { stability_limit } = self.method
            && hs > stability_limit
        {
            return Err(SolverError::AboveStabilityLimit {
                step: hs,
                limit: stability_limit,
            });
        }
        self.consistent_acceleration(sys, st, t, start_forces_given);
        let n = substeps as usize;
        self.iteration_start = self.stats.newton_iterations;
        self.iteration_budget = ITERATIONS_PER_STEP * n as u64 + ITERATIONS_SPARE;
        let mut start = 0.0;
        for i in 0..n {
            let end = if i + 1 == n { h } else { (i + 1) as f64 * hs };
            let was_locked = st.locked;
            self.substep(sys, st, t, (start, end), inputs, 0)?;
            if st.locked != was_locked {
                self.events.push(Event {
                    time: t + end,
                    locked: st.locked,
                });
            }
            start = end;
        }
        if !st.is_finite() {
            return Err(SolverError::NonFinite { time: t });
        }
        Ok(())
    }

    /// One sub-step over `span` (seconds after t), halved recursively while it fails in a way a
    /// shorter step can cure.
    fn substep<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        t: f64,
        span: (f64, f64),
        inputs: &impl Fn(f64, &mut [f64]),
        depth: u32,
    ) -> Result<(), SolverError> {
        // the start inputs matter only to methods that weight the start of the step (α_f > 0)
        if let Method::Implicit(p) = self.method
            && p.alpha_f != 0.0
        {
            inputs(span.0, &mut self.u0);
        }
        inputs(span.1, &mut self.u1);
        let spent = self.stats.newton_iterations - self.iteration_start;
        if spent > self.iteration_budget {
            return Err(SolverError::OverBudget {
                time: t,
                iterations: spent,
                budget: self.iteration_budget,
            });
        }
        let h = span.1 - span.0;
        let result = match self.method {
            Method::Implicit(_) => {
                // a sub-step from the communication point starts where the consistent
                // accelerations evaluated the internal forces (a failed step leaves the state)
                let reuse = self.reuse_start_forces && self.fi_at_start && span.0 == 0.0;
                let fi0 = reuse.then_some(&self.fi[..]);
                let span = Span {
                    t: t + span.0,
                    h,
                    u0: &self.u0,
                    u1: &self.u1,
                    fi0,
                };
                self.alpha.step(sys, st, &span, &mut self.stats)
            }
            Method::Rk4 { .. } => {
                self.rk4.step(sys, st, t + span.0, h, &self.u1, &mut self.stats);
                Ok(())
            }
        };
        match result {
            Err(e) if e.is_recoverable() && depth < MAX_HALVINGS => {
                self.stats.halvings += 1;
                let mid = 0.5 * (span.0 + span.1);
                self.substep(sys, st, t, (span.0, mid), inputs, depth + 1)?;
                self.substep(sys, st, t, (mid, span.1), inputs, depth + 1)
            }
            Err(e) if e.is_recoverable() => Err(SolverError::StepTooSmall {
                cause: Box::new(e),
                halvings: depth,
                step: h,
            }),
            other => other,
        }
    }

    /// Sets the accelerations from the equations of motion at the start of a step, so input jumps
    /// at a communication point act from that point on (zero-order hold), friction included.
    ///
    /// For a linear system with a lumped mass the accelerations already satisfy the equations of
    /// motion for the previously applied inputs (the implicit step enforces them at every step
    /// end), so only the loaded DOFs change: O(inputs) instead of a sweep over every force.
    fn consistent_acceleration<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        t: f64,
        forces_given: bool,
    ) {
        let n = sys.dofs();
        let u = &self.u0;
        let friction = active_friction(sys, u);
        let mass = sys.mass();
        self.fi_at_start = false;
        match mass {
            Mass::Diagonal(m)
                if sys.linearity() == Linearity::Linear
                    && st.applied.len() == u.len()
                    && (friction.is_some() || st.friction_force == 0.0) =>
            {
                follow_input_change(sys, st, u, m);
                if let Some(fr) = friction {
                    // undo the last friction force; it is decided afresh below
                    st.a[fr.dof] -= st.friction_force / m[fr.dof];
                }
            }
            _ => {
                self.f.resize(n, 0.0);
                self.fi.resize(n, 0.0);
                external_forces(sys, u, &mut self.f);
                if !forces_given {
                    sys.internal_forces(t, &st.q, &st.v, &mut self.fi);
                }
                self.fi_at_start = true;
                for (f, fi) in self.f.iter_mut().zip(&self.fi) {
                    *f -= fi;
                }
                self.mass.solve(mass, &self.f, &mut st.a);
            }
        }
        let (force, locked) = match friction {
            None => (0.0, false),
            Some(fr) if st.v[fr.dof] != 0.0 => (-fr.kinetic * st.v[fr.dof].signum(), false),
            Some(fr) => {
                let hold = self.mass.holding_force(mass, &st.a, fr.dof);
                if hold.abs() <= fr.hold(st.locked) {
                    (hold, true)
                } else {
                    (fr.kinetic * hold.signum(), false)
                }
            }
        };
        if let Some(fr) = friction
            && force != 0.0
        {
            match mass {
                Mass::Diagonal(m) => st.a[fr.dof] += force / m[fr.dof],
                Mass::Dense(_) | Mass::Sparse(..) => {
                    // the force vector and its accelerations in the driver's scratch buffers
                    self.f.clear();
                    self.f.resize(n, 0.0);
                    self.f[fr.dof] = force;
                    // (not in `fi`: the first sub-step reuses it)
                    self.friction_a.resize(n, 0.0);
                    self.mass.solve(mass, &self.f, &mut self.friction_a);
                    for (a, d) in st.a.iter_mut().zip(&self.friction_a) {
                        *a += d;
                    }
                }
            }
        }
        st.friction_force = force;
        st.locked = locked;
        st.applied.clear();
        st.applied.extend_from_slice(u);
    }
}

/// A linear system with lumped mass `m` whose accelerations satisfy its equations of motion for the
/// inputs it last applied: the accelerations for inputs `u`, changed on the loaded DOFs alone.
#[inline(always)]
fn follow_input_change<S: SecondOrderSystem>(sys: &S, st: &mut DynState, u: &[f64], m: &[f64]) {
    for l in sys.input_loads() {
        st.a[l.dof] += l.gain * (u[l.input] - st.applied[l.input]) / m[l.dof];
    }
}

/// The friction contact for inputs `u` if it can exert a force (the integrators' test).
#[inline(always)]
fn active_friction<S: SecondOrderSystem>(sys: &S, u: &[f64]) -> Option<Friction> {
    sys.friction(u).filter(|f| f.kinetic > 0.0 || f.holding > 0.0)
}
