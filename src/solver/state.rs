//! What an integrator advances, statistics it keeps, and how a step can fail.

use serde::{Deserialize, Serialize};

/// The dynamic state of a second-order system.
#[derive(Debug, PartialEq, Serialize, Deserialize)]
pub struct DynState {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    /// Accelerations consistent with the inputs at the start of the next step.
    pub a: Vec<f64>,
    /// The friction contact holds its DOF at rest.
    pub locked: bool,
    /// Friction force on its DOF at the end of the last step (acting on the DOF, so negative
    /// while it brakes a positive motion).
    pub friction_force: f64,
    /// The inputs `a` is consistent with (empty: not yet computed).
    pub applied: Vec<f64>,
}

/// `clone_from` reuses the vectors: an FMU state updated in place at every macro step (the
/// master's rollback) allocates nothing.
impl Clone for DynState {
    fn clone(&self) -> Self {
        Self {
            q: self.q.clone(),
            v: self.v.clone(),
            a: self.a.clone(),
            locked: self.locked,
            friction_force: self.friction_force,
            applied: self.applied.clone(),
        }
    }

    fn clone_from(&mut self, other: &Self) {
        self.q.clone_from(&other.q);
        self.v.clone_from(&other.v);
        self.a.clone_from(&other.a);
        self.locked = other.locked;
        self.friction_force = other.friction_force;
        self.applied.clone_from(&other.applied);
    }
}

/// Whether two f64 slices hold the same bits: a byte comparison the library vectorises (an f64
/// comparison per entry cost 4 % of a 6-DOF step where a mass matrix is checked), stricter than `==`
/// only for a −0 against a 0 and for NaNs.
pub fn same_bits(a: &[f64], b: &[f64]) -> bool {
    // SAFETY: any f64 is eight initialised bytes; the views live as long as the slices.
    let bytes = |x: &[f64]| unsafe { std::slice::from_raw_parts(x.as_ptr().cast::<u8>(), std::mem::size_of_val(x)) };
    bytes(a) == bytes(b)
}

/// Internal forces and the state (q, v) they belong to, compared bit for bit: whoever holds them
/// hands them to a step that starts from that very state instead of evaluating them again, and no path
/// that changes the state can hand a step stale ones.
#[derive(Debug, Clone, Default)]
pub struct ForcesAt {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub forces: Vec<f64>,
    pub valid: bool,
}

impl ForcesAt {
    /// The forces when they are the ones at (q, v).
    pub fn at(&self, q: &[f64], v: &[f64]) -> Option<&[f64]> {
        (self.valid && same_bits(&self.q, q) && same_bits(&self.v, v)).then_some(&self.forces[..])
    }

    /// Marks the forces as those at (q, v), which the caller has written to `forces`.
    pub fn belong_to(&mut self, q: &[f64], v: &[f64]) {
        for (own, x) in [(&mut self.q, q), (&mut self.v, v)] {
            own.clear();
            own.extend_from_slice(x);
        }
        self.valid = true;
    }
}

impl DynState {
    pub fn new(q: Vec<f64>, v: Vec<f64>) -> Self {
        let n = q.len();
        Self {
            q,
            v,
            a: vec![0.0; n],
            locked: false,
            friction_force: 0.0,
            applied: Vec::new(),
        }
    }

    /// An entry is infinite or NaN exactly when its exponent field is all ones; adding one at the
    /// exponent's lowest bit then carries into bit 63, which no finite entry reaches. OR-ed over the
    /// slices in integers the loops vectorise with SSE2 (and, or, add), where a float fold must
    /// keep its order and ran as a serial chain of 33 dependent adds (≈ 230 instructions, a tenth
    /// of the torsional FMU's step, by callgrind).
    pub fn is_finite(&self) -> bool {
        const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
        const EXPONENT_ONE: u64 = 1 << 52;
        let carry = |x: &[f64]| {
            x.iter()
                .fold(0u64, |acc, v| acc | (v.to_bits() & EXPONENT).wrapping_add(EXPONENT_ONE))
        };
        (carry(&self.q) | carry(&self.v) | carry(&self.a)) >> 63 == 0
    }
}

/// Work counters, deterministic for the same calls (tests pin them instead of timings).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Statistics {
    /// Accepted internal steps.
    pub steps: u64,
    /// Linear solves inside Newton iterations (one per iteration).
    pub newton_iterations: u64,
    /// Jacobians factorised (the cache's misses).
    pub factorizations: u64,
    /// Steps that failed and were split in two.
    pub halvings: u64,
    /// Communication steps taken as one plain linear step (`Driver::advance`'s path for a linear
    /// system with its friction contact open), counted in `steps` as well.
    #[serde(default)]
    pub plain_steps: u64,
    /// Steps whose modified Newton iteration on a kept factorisation ([`crate::solver::alpha::Newton`]'s
    /// `keep`) stalled even on a fresh tangent and were taken again from Δ = 0 the default way.
    #[serde(default)]
    pub newton_restarts: u64,
    /// Steps taken the default way at once, without the kept iteration first, because the step before
    /// had been restarted and had not converged fast since ([`crate::solver::alpha::RATTLE_ITERATIONS`]).
    #[serde(default)]
    pub newton_rattle_steps: u64,
}

/// Why a step could not be taken. Times are the start of the failing (sub)step, s.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolverError {
    #[error("Newton iteration did not converge at t = {time} s: residual {residual:.3e} after {iterations} iterations")]
    NewtonDiverged {
        time: f64,
        iterations: usize,
        residual: f64,
    },
    #[error("contact pattern did not settle at t = {time} s in {iterations} Newton iterations")]
    ContactNotSettled { time: f64, iterations: usize },
    #[error("the iteration matrix is singular at t = {time} s (step {step:.3e} s)")]
    SingularJacobian { time: f64, step: f64 },
    #[error("step {step:.3e} s exceeds the explicit method's stability limit {limit:.3e} s")]
    AboveStabilityLimit { step: f64, limit: f64 },
    #[error("the state became non-finite in the step from t = {time} s")]
    NonFinite { time: f64 },
    #[error("{cause} (after halving the step {halvings} times to {step:.3e} s)")]
    StepTooSmall {
        cause: Box<SolverError>,
        halvings: u32,
        step: f64,
    },
    #[error("step size {step} s is not positive and finite")]
    BadStep { step: f64 },
    #[error(
        "the communication step of {step} s needs {steps:.0} internal steps, more than max_steps_per_call = {limit:.0}; \
         take shorter communication steps or raise the limit"
    )]
    TooManySteps { step: f64, steps: f64, limit: f64 },
    #[error(
        "{iterations} Newton iterations in the communication step from t = {time} s, more than its budget of \
         {budget} (steps iterating and halving on and on): the model cannot follow its inputs (an input far beyond \
         its rating?)"
    )]
    OverBudget { time: f64, iterations: u64, budget: u64 },
}

impl SolverError {
    /// Whether a shorter step can cure it (contact and convergence failures can; the others not).
    pub fn is_recoverable(&self) -> bool {
        matches!(self, Self::NewtonDiverged { .. } | Self::ContactNotSettled { .. })
    }
}

#[cfg(test)]
mod tests {
    use super::DynState;

    /// Every non-finite value is caught in every vector and at every position; the extremes of the
    /// finite range (largest, subnormal, negative zero) are not.
    #[test]
    fn is_finite_flags_exactly_the_non_finite_states() {
        let finite = [f64::MAX, -f64::MAX, f64::MIN_POSITIVE, 5e-324, -0.0, 0.0, 1.0, -1e300];
        let mut st = DynState::new(finite.to_vec(), finite.to_vec());
        st.a = finite.to_vec();
        assert!(st.is_finite());
        for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN, -f64::NAN] {
            for vector in 0..3 {
                for i in 0..finite.len() {
                    let mut s = st.clone();
                    [&mut s.q, &mut s.v, &mut s.a][vector][i] = bad;
                    assert!(!s.is_finite(), "{bad} at {i} of vector {vector}");
                }
            }
        }
    }
}
