//! The step of a linear system: Δ = W·[x; v; a] + J⁻¹·f with the cached step map W, then the
//! friction, then the update. Same equations as the Newton path, none of its generality; and the
//! plain step the driver takes for a whole communication step while the friction contact is open,
//! which is the same arithmetic without the friction's bookkeeping and with the finiteness check
//! folded into the update.

use super::{AlphaIntegrator, Coefficients, Span, Work, finish_friction};
use crate::solver::factor::{Factor, Solver, axpy_columns, padded};
use crate::solver::state::{DynState, SolverError, Statistics, flags_non_finite, non_finite_flag};
use crate::solver::system::{Friction, SecondOrderSystem};

/// One step from `t` by `c.h` with the inputs `u0` at its start and `u1` at its end.
#[derive(Clone, Copy)]
struct Ends<'a> {
    t: f64,
    u0: &'a [f64],
    u1: &'a [f64],
}

impl AlphaIntegrator {
    /// The step of a linear system with the friction contact `friction` (None: open).
    pub(super) fn linear_step<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        c: &Coefficients,
        span: &Span,
        friction: Option<Friction>,
        stats: &mut Statistics,
    ) -> Result<(), SolverError> {
        let Span { t, u0, u1, .. } = *span;
        // a local copy: through the reference the coefficients would be reloaded after every store
        let c = *c;
        let n = sys.dofs();
        let friction_dof = friction.map(|f| f.dof);
        let idx = self.linear_factor(sys, &c, t, st, friction_dof, stats)?;
        let AlphaIntegrator { cache, work: w, .. } = self;
        let factor = cache.get(idx);
        increment(sys, &c, factor, w, st, Ends { t, u0, u1 })?;
        let (q, v, a) = (&mut st.q[..n], &mut st.v[..n], &mut st.a[..n]);
        let delta = &mut w.padded[..padded(n)];
        let mut stuck = None;
        let mut force = 0.0;
        if let (Some(fr), Some((f, resp))) = (friction, &factor.friction_response) {
            let f = *f;
            let held;
            (force, held) = c.resolve_friction(&fr, st.locked, (f, resp), delta, (v[f], a[f]), 0.0);
            if held {
                // exactly at rest: no creep from the position update
                delta[f] = c.increment_to_rest(v[f], a[f]);
                stuck = Some(f);
            }
        }
        // the driver checks finiteness once after all the sub-steps: the flags are dropped
        update(&c, &delta[..n], q, v, a);
        finish_friction(st, stuck, force, u1);
        Ok(())
    }

    /// One step of a linear system from `t` by `h`, inputs `u0` at its start and `u1` at its end,
    /// whose friction contact is open at both ends with no friction force left from the step
    /// before (`st.friction_force == 0`), and whose q, v and a have one entry per DOF:
    /// [`Self::step`] with no friction, to the bit. Returns whether the state is finite after it.
    #[allow(clippy::too_many_arguments)]
    pub fn plain_linear_step<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        t: f64,
        h: f64,
        (u0, u1): (&[f64], &[f64]),
        stats: &mut Statistics,
    ) -> Result<bool, SolverError> {
        let n = sys.dofs();
        self.work.fit(n);
        if self.work.u.len() < u1.len() {
            self.work.u.resize(u1.len(), 0.0);
        }
        let c = self.coefficients_for(h);
        let idx = self.linear_factor(sys, &c, t, st, None, stats)?;
        let AlphaIntegrator { cache, work: w, .. } = self;
        increment(sys, &c, cache.get(idx), w, st, Ends { t, u0, u1 })?;
        let (q, v, a) = (&mut st.q[..n], &mut st.v[..n], &mut st.a[..n]);
        let flags = update(&c, &w.padded[..n], q, v, a);
        st.locked = false;
        st.friction_force = 0.0;
        st.applied.clear();
        st.applied.extend_from_slice(u1);
        stats.steps += 1;
        Ok(!flags_non_finite(flags))
    }

    /// The cached factorisation of a linear system for this step size (and friction DOF), built
    /// when new; counts the step's one solve.
    #[inline(always)]
    fn linear_factor<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        c: &Coefficients,
        t: f64,
        st: &DynState,
        friction_dof: Option<usize>,
        stats: &mut Statistics,
    ) -> Result<usize, SolverError> {
        let idx = match self.cached(&[], c.h, friction_dof) {
            Some(i) => i,
            None => self.factor(sys, c, (t, &st.q, &st.v), false, friction_dof, stats)?,
        };
        stats.newton_iterations += 1;
        Ok(idx)
    }
}

/// Δ = W·[x; v; a] + J⁻¹·f (and the start's friction force for methods that weight the start) into
/// `w.padded`, x the positions less the rigid rotation.
#[inline(always)]
fn increment<S: SecondOrderSystem>(
    sys: &S,
    c: &Coefficients,
    factor: &Factor,
    w: &mut Work,
    st: &DynState,
    Ends { t, u0, u1 }: Ends,
) -> Result<(), SolverError> {
    let n = sys.dofs();
    let np = padded(n);
    let Some(map) = factor.step_map.as_deref() else {
        return Err(SolverError::SingularJacobian { time: t, step: c.h });
    };
    let (q, v, a) = (&st.q[..n], &st.v[..n], &st.a[..n]);
    let (x, delta) = (&mut w.x[..n], &mut w.padded[..np]);
    // inputs that load no DOF (a brake command) have no column
    let u = &mut w.u[..factor.input_response.len() / np];
    for k in 0..u.len() {
        u[k] = (1.0 - c.af) * u1[k] + c.af * u0[k];
    }
    match sys.rigid_mode() {
        Some((ratio, reference)) => {
            let (ratio, q_ref) = (&ratio[..n], q[reference]);
            for i in 0..n {
                x[i] = q[i] - ratio[i] * q_ref;
            }
        }
        None => x.copy_from_slice(q),
    }
    delta.iter_mut().for_each(|d| *d = 0.0);
    if c.af != 0.0
        && st.friction_force != 0.0
        && let Some((_, resp)) = &factor.friction_response
    {
        for (d, r) in delta.iter_mut().zip(resp) {
            *d += c.af * st.friction_force * r;
        }
    }
    let (mq, rest) = map.split_at(np * n);
    let (mv, ma) = rest.split_at(np * n);
    let inputs = &factor.input_response[..];
    axpy_columns([(mq, &*x), (mv, v), (ma, a), (inputs, &*u)], delta);
    Ok(())
}

/// q, v and a at the step's end from the increment Δ. Returns the OR of their
/// [`non_finite_flag`]s; a caller that drops it drops its work with it (the function is inlined).
#[inline(always)]
fn update(c: &Coefficients, delta: &[f64], q: &mut [f64], v: &mut [f64], a: &mut [f64]) -> u64 {
    let mut flags = 0;
    for i in 0..q.len() {
        let d = delta[i];
        let v_new = c.velocity(d, v[i], a[i]);
        a[i] = c.acceleration(d, v[i], a[i]);
        q[i] += d;
        v[i] = v_new;
        flags |= non_finite_flag(q[i]) | non_finite_flag(v_new) | non_finite_flag(a[i]);
    }
    flags
}

/// W = [−J⁻¹K | −J⁻¹((1 − α_m)k_av·M + ((1 − α_f)k_vv + α_f)·C) | −J⁻¹(((1 − α_m)k_aa + α_m)·M +
/// (1 − α_f)k_va·C)], rows padded for the SSE2 kernel: Δ = W·[x; v; a] + J⁻¹f for a linear system.
pub(super) fn step_map<S: SecondOrderSystem>(sys: &S, c: &Coefficients, solver: &Solver) -> Vec<f64> {
    let n = sys.dofs();
    let zeros = vec![0.0; n];
    let lin = sys.linearise(&zeros, &zeros);
    let mass = &lin.mass;
    let blocks = [
        -&lin.stiffness,
        -(mass * ((1.0 - c.am) * c.ka[1]) + &lin.damping * ((1.0 - c.af) * c.kv[1] + c.af)),
        -(mass * ((1.0 - c.am) * c.ka[2] + c.am) + &lin.damping * ((1.0 - c.af) * c.kv[2])),
    ];
    let np = padded(n);
    let mut map = vec![0.0; np * 3 * n];
    for (b, block) in blocks.iter().enumerate() {
        for col in 0..n {
            let out = &mut map[(b * n + col) * np..(b * n + col) * np + n];
            let rhs: Vec<f64> = block.column(col).iter().copied().collect();
            solver.add_solution(&rhs, out);
        }
    }
    map
}
