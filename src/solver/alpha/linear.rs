//! The step of a linear system: Δ = W·[x; v; a; u] with the cached step map W, then the
//! friction, then the update. Same equations as the Newton path, none of its generality; and the
//! plain step the driver takes for a whole communication step while the friction contact is open,
//! which is the same arithmetic without the friction's bookkeeping and with the finiteness check
//! folded into the update.

use super::{AlphaIntegrator, Coefficients, Span, Work, finish_friction};
use crate::solver::factor::{Factor, Solver, axpy_columns, padded, set_columns};
use crate::solver::state::{DynState, SolverError, Statistics};
use crate::solver::system::{Friction, SecondOrderSystem, input_count};

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
        // the driver checks finiteness once after all the sub-steps: the answer is dropped
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
        self.work.fit(sys.dofs());
        let c = self.coefficients_for(h);
        let idx = self.linear_factor(sys, &c, t, st, None, stats)?;
        let AlphaIntegrator { cache, work: w, .. } = self;
        let finite = increment_and_update(sys, &c, cache.get(idx), w, st, Ends { t, u0, u1 })?;
        finish_friction(st, None, 0.0, u1);
        stats.steps += 1;
        Ok(finite)
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

/// [`increment`], then [`update`] with its finiteness check, on the CPU's widest vectors: AVX where it
/// has it, four values a register in the rigid-mode shift and the update instead of SSE2's two.
/// Each value goes through the same operations either way (no fused multiply–adds): the same bits.
fn increment_and_update<S: SecondOrderSystem>(
    sys: &S,
    c: &Coefficients,
    factor: &Factor,
    w: &mut Work,
    st: &mut DynState,
    ends: Ends,
) -> Result<bool, SolverError> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX.
        return unsafe { increment_and_update_avx(sys, c, factor, w, st, ends) };
    }
    increment_then_update(sys, c, factor, w, st, ends)
}

/// [`increment_then_update`] compiled for AVX.
///
/// # Safety
/// The CPU has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn increment_and_update_avx<S: SecondOrderSystem>(
    sys: &S,
    c: &Coefficients,
    factor: &Factor,
    w: &mut Work,
    st: &mut DynState,
    ends: Ends,
) -> Result<bool, SolverError> {
    increment_then_update(sys, c, factor, w, st, ends)
}

#[inline(always)]
fn increment_then_update<S: SecondOrderSystem>(
    sys: &S,
    c: &Coefficients,
    factor: &Factor,
    w: &mut Work,
    st: &mut DynState,
    ends: Ends,
) -> Result<bool, SolverError> {
    increment(sys, c, factor, w, st, ends)?;
    let n = sys.dofs();
    let (q, v, a) = (&mut st.q[..n], &mut st.v[..n], &mut st.a[..n]);
    Ok(update(c, &w.padded[..n], q, v, a))
}

/// Δ = W·[x; v; a; u] (and the start's friction force for methods that weight the start) into
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
    // inputs that load no DOF (a brake command) have no column
    let inputs = map.len() / np - 3 * n;
    if w.z.len() < n + inputs {
        w.z.resize(n + inputs, 0.0);
    }
    let (x, u) = w.z[..n + inputs].split_at_mut(n);
    let delta = &mut w.padded[..np];
    let q = &st.q[..n];
    let x: &[f64] = match sys.rigid_mode() {
        Some((ratio, reference)) => {
            let (ratio, q_ref) = (&ratio[..n], q[reference]);
            for i in 0..n {
                x[i] = q[i] - ratio[i] * q_ref;
            }
            x
        }
        None => q,
    };
    assert!(
        u0.len() >= u.len() && u1.len() >= u.len(),
        "an input the system reads is missing"
    );
    for ((u, u1), u0) in u.iter_mut().zip(u1).zip(u0) {
        *u = (1.0 - c.af) * u1 + c.af * u0;
    }
    // four blocks, the columns of W_q, W_v, W_a and J⁻¹B in the order the products were always added,
    // v and a read where they are: gathering them into one vector took two calls of libc's memcpy, a
    // twentieth of the torsional FMU's communication step in wall time (perf), for fewer instructions
    let (m_x, rest) = map.split_at(n * np);
    let (m_v, rest) = rest.split_at(n * np);
    let (m_a, m_u) = rest.split_at(n * np);
    let blocks = [(m_x, x), (m_v, &st.v[..n]), (m_a, &st.a[..n]), (m_u, &*u)];
    if c.af != 0.0
        && st.friction_force != 0.0
        && let Some((_, resp)) = &factor.friction_response
    {
        delta.fill(0.0);
        for (d, r) in delta.iter_mut().zip(resp) {
            *d += c.af * st.friction_force * r;
        }
        axpy_columns(blocks, delta);
    } else {
        // what the product adds to a zeroed Δ, without zeroing it
        set_columns(blocks, delta);
    }
    Ok(())
}

/// q, v and a at the step's end from the increment Δ. Returns whether they are all finite, a
/// comparison and an AND a value that vectorise with the update; a caller that drops the answer
/// drops its work with it (the function is inlined).
#[inline(always)]
fn update(c: &Coefficients, delta: &[f64], q: &mut [f64], v: &mut [f64], a: &mut [f64]) -> bool {
    let mut finite = true;
    for i in 0..q.len() {
        let d = delta[i];
        let v_new = c.velocity(d, v[i], a[i]);
        a[i] = c.acceleration(d, v[i], a[i]);
        q[i] += d;
        v[i] = v_new;
        finite &= q[i].is_finite() & v_new.is_finite() & a[i].is_finite();
    }
    finite
}

/// W = [−J⁻¹K | −J⁻¹((1 − α_m)k_av·M + ((1 − α_f)k_vv + α_f)·C) | −J⁻¹(((1 − α_m)k_aa + α_m)·M +
/// (1 − α_f)k_va·C) | J⁻¹B], rows padded for the vector kernels: Δ = W·[x; v; a; u] for a linear
/// system.
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
    let inputs = input_count(sys);
    let mut map = vec![0.0; np * (3 * n + inputs)];
    for (b, block) in blocks.iter().enumerate() {
        for col in 0..n {
            let out = &mut map[(b * n + col) * np..(b * n + col) * np + n];
            let rhs: Vec<f64> = block.column(col).iter().copied().collect();
            solver.add_solution(&rhs, out);
        }
    }
    // J⁻¹B: the response to each unit input
    let input_response = &mut map[3 * n * np..];
    for l in sys.input_loads() {
        let column = solver.unit_response(n, l.dof);
        for (x, y) in input_response[l.input * np..l.input * np + n].iter_mut().zip(column) {
            *x += l.gain * y;
        }
    }
    map
}
