//! Newmark average acceleration (β = 1/4, γ = 1/2), the trapezoidal rule for second-order systems:
//! A-stable, second order, no numerical damping, and exactly energy-conserving for an undamped
//! linear model. Each step solves J Δ = r with J = K_t + (2/h) C + (4/h²) M. J depends only on the
//! step size, the contact pattern of backlash meshes and the single/double tooth contact pattern, so
//! J⁻¹ is cached per pattern: a linear drivetrain inverts once per step size and then each step is
//! one element sweep and one small matrix–vector product.
//!
//! Stick–slip of the HSS brake is solved inside the step: the solution is affine in the brake torque
//! T (Δ = Δ₀ + T·J⁻¹e_g), so T is the torque that makes the generator speed exactly zero at the end
//! of the step if the brake can supply it (stick), else ±capacity (slip). A stuck brake therefore
//! never creeps and never chatters.

use super::{DynState, Loads, external_forces, internal_forces};
use crate::physics::torsional::TorsionalModel;
use nalgebra::{DMatrix, DVector};

const MAX_ITERATIONS: usize = 50;

/// Why a step could not be taken.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NewmarkError {
    /// The backlash contact pattern kept changing between Newton iterations: the step is too long
    /// to resolve the contact event; the caller subdivides it.
    #[error("backlash contact did not settle in {MAX_ITERATIONS} Newton iterations")]
    NotSettled,
    #[error("Newmark iteration matrix is singular")]
    Singular,
}
const CACHE_LIMIT: usize = 64;

struct Factor {
    key: Key,
    /// The step size the matrices were built for.
    h: f64,
    /// J⁻¹, column-major: Δ += Σ_j r_j·(column j) vectorises, a row-by-row dot product would not.
    inverse: Vec<f64>,
    /// J⁻¹ e_g: response to a unit torque on the generator DOF.
    unit_brake: Vec<f64>,
    /// J⁻¹ e_r: response to a unit torque on the rotor.
    unit_rotor: Vec<f64>,
    /// Linear models only: Δ = W·[q; v; a] + J⁻¹f, with W = [−J⁻¹K | J⁻¹(C + 4M/h) | J⁻¹M]
    /// (n × 3n, column-major). One product replaces the element sweep and the solve.
    step_map: Option<Vec<f64>>,
}

/// (contact pattern, double-contact pattern); the step size is matched separately, with tolerance.
type Key = (u64, u64);

/// Step sizes this close share one factorisation. Masters that accumulate time pass step sizes that
/// differ in the last bits ((n+1)·h − n·h); treating them as one keeps results independent of that
/// noise and avoids refactorising. The time error it implies is below 1e-15 of a step.
const SAME_STEP: f64 = 1e-12;

fn same_step(a: f64, b: f64) -> bool {
    (a - b).abs() <= SAME_STEP * a.abs()
}

#[derive(Default)]
struct Work {
    f: Vec<f64>,
    fi: Vec<f64>,
    q1: Vec<f64>,
    v1: Vec<f64>,
    r: Vec<f64>,
    delta: Vec<f64>,
    padded: Vec<f64>,
    x: Vec<f64>,
}

/// Rows of the step map are padded to a multiple of this (one SSE2 register holds two f64).
const LANES: usize = 2;

fn padded(n: usize) -> usize {
    n.div_ceil(LANES) * LANES
}

/// y += Σ A_k·x_k for column-major blocks A_k whose columns have y.len() rows (a multiple of
/// LANES): every column of every block is accumulated into registers holding all of y at once
/// (register blocking), so y is loaded and stored once per step. On x86_64 this uses SSE2, part of
/// the x86_64 baseline, so the FMU still runs on every x86_64 CPU; elsewhere it is plain Rust.
fn axpy_columns(blocks: [(&[f64], &[f64]); 3], y: &mut [f64]) {
    let rows = y.len();
    assert!(rows.is_multiple_of(LANES));
    for (a, x) in blocks {
        assert_eq!(a.len(), rows * x.len());
    }
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY (all arms): the asserts above guarantee every block holds rows × x.len() values and
        // y holds rows values; the kernel reads and writes exactly those.
        match rows / 2 {
            1 => return unsafe { sse2_kernel::<1>(blocks, y) },
            2 => return unsafe { sse2_kernel::<2>(blocks, y) },
            3 => return unsafe { sse2_kernel::<3>(blocks, y) },
            4 => return unsafe { sse2_kernel::<4>(blocks, y) },
            5 => return unsafe { sse2_kernel::<5>(blocks, y) },
            6 => return unsafe { sse2_kernel::<6>(blocks, y) },
            7 => return unsafe { sse2_kernel::<7>(blocks, y) },
            8 => return unsafe { sse2_kernel::<8>(blocks, y) },
            _ => {}
        }
    }
    for (a, x) in blocks {
        for (column, &s) in a.chunks_exact(rows).zip(x) {
            for (yi, ai) in y.iter_mut().zip(column) {
                *yi += ai * s;
            }
        }
    }
}

/// `axpy_columns` for 2·P rows held in P SSE2 registers.
///
/// # Safety
/// `y` has 2·P entries and every block's matrix has 2·P × x.len() entries.
#[cfg(target_arch = "x86_64")]
unsafe fn sse2_kernel<const P: usize>(blocks: [(&[f64], &[f64]); 3], y: &mut [f64]) {
    use std::arch::x86_64::{__m128d, _mm_add_pd, _mm_loadu_pd, _mm_mul_pd, _mm_set1_pd, _mm_storeu_pd};
    unsafe {
        let out = y.as_mut_ptr();
        let mut acc: [__m128d; P] = std::array::from_fn(|k| _mm_loadu_pd(out.add(2 * k)));
        for (a, x) in blocks {
            let mut column = a.as_ptr();
            for &s in x {
                let sv = _mm_set1_pd(s);
                for (k, r) in acc.iter_mut().enumerate() {
                    *r = _mm_add_pd(*r, _mm_mul_pd(_mm_loadu_pd(column.add(2 * k)), sv));
                }
                column = column.add(2 * P);
            }
        }
        for (k, r) in acc.iter().enumerate() {
            _mm_storeu_pd(out.add(2 * k), *r);
        }
    }
}

/// Brake torque on the generator DOF for a step whose end speed would be `speed` without the brake
/// and changes by `per_torque` per unit brake torque: the torque that stops the disk exactly if the
/// brake can hold `hold` (stick), else the kinetic `capacity` against the motion (slip).
fn brake_torque(speed: f64, per_torque: f64, hold: f64, capacity: f64) -> (f64, bool) {
    let stick = -speed / per_torque;
    if stick.abs() <= hold {
        (stick, true)
    } else {
        (capacity * stick.signum(), false)
    }
}

/// Integrator with its cache of inverses and scratch vectors. Cloning gives an empty cache,
/// refilled on demand with identical inverses, so snapshots stay cheap and bit-identical.
pub struct Newmark {
    cache: Vec<Factor>,
    last: usize,
    work: Work,
    pub factorizations: u64,
    pub iterations: u64,
}

impl Clone for Newmark {
    fn clone(&self) -> Self {
        Self::new()
    }
}

impl Default for Newmark {
    fn default() -> Self {
        Self::new()
    }
}

/// Bit patterns of backlash meshes in contact and of meshes in double tooth contact.
fn patterns(model: &TorsionalModel, q_contact: &[f64], q_stiff: &[f64]) -> (u64, u64) {
    let (mut contact, mut double) = (0u64, 0u64);
    if !model.has_backlash() && !model.has_stiffness_variation() {
        return (0, 0);
    }
    for (i, e) in model.elements.iter().enumerate().take(64) {
        if e.half_backlash > 0.0 && e.contact(e.deflection(q_contact)).1 {
            contact |= 1 << i;
        }
        if let Some(v) = &e.variation
            && v.stiffness(q_stiff[v.dof]) == v.k_double
        {
            double |= 1 << i;
        }
    }
    (contact, double)
}

impl Newmark {
    pub fn new() -> Self {
        Self {
            cache: Vec::new(),
            last: usize::MAX,
            work: Work::default(),
            factorizations: 0,
            iterations: 0,
        }
    }

    /// Index of the cached inverse for this step size and pattern, computing it when new.
    fn factor(
        &mut self,
        model: &TorsionalModel,
        h: f64,
        contact: u64,
        double: u64,
        q_stiff: &[f64],
    ) -> Result<usize, NewmarkError> {
        let key = (contact, double);
        if self
            .cache
            .get(self.last)
            .is_some_and(|f| f.key == key && same_step(f.h, h))
        {
            return Ok(self.last);
        }
        if let Some(i) = self.cache.iter().position(|f| f.key == key && same_step(f.h, h)) {
            self.last = i;
            return Ok(i);
        }
        let n = model.dofs();
        let mut j = DMatrix::from_diagonal(&DVector::from_iterator(n, model.mass.iter().map(|m| 4.0 / (h * h) * m)));
        model.assemble_into(&mut j, |i, e| {
            let touching = e.half_backlash == 0.0 || i >= 64 || contact & (1 << i) != 0;
            if touching {
                e.stiffness_at(q_stiff) + 2.0 / h * e.damping
            } else {
                0.0
            }
        });
        let inv = j.try_inverse().ok_or(NewmarkError::Singular)?;
        let inverse: Vec<f64> = inv.as_slice().to_vec(); // nalgebra stores column-major
        let unit_brake: Vec<f64> = (0..n).map(|i| inv[(i, model.generator)]).collect();
        let unit_rotor: Vec<f64> = (0..n).map(|i| inv[(i, model.rotor)]).collect();
        let step_map = (!model.has_backlash() && !model.has_stiffness_variation()).then(|| {
            let (k, c) = model.stiffness_and_damping();
            let m = DMatrix::from_diagonal(&DVector::from_column_slice(&model.mass));
            let mut w = DMatrix::<f64>::zeros(n, 3 * n);
            w.columns_mut(0, n).copy_from(&(-&inv * &k));
            w.columns_mut(n, n).copy_from(&(&inv * (&c + &m * (4.0 / h))));
            w.columns_mut(2 * n, n).copy_from(&(&inv * &m));
            let np = padded(n);
            let mut padded_map = vec![0.0; np * 3 * n];
            for (dst, src) in padded_map.chunks_exact_mut(np).zip(w.as_slice().chunks_exact(n)) {
                dst[..n].copy_from_slice(src);
            }
            padded_map
        });
        self.factorizations += 1;
        if self.cache.len() >= CACHE_LIMIT {
            self.cache.clear();
        }
        self.cache.push(Factor {
            key,
            h,
            inverse,
            unit_brake,
            unit_rotor,
            step_map,
        });
        self.last = self.cache.len() - 1;
        Ok(self.last)
    }

    /// The step of a linear drivetrain: Δ = W·[x; v; a] + J⁻¹f with the cached step map, then the
    /// brake, then the Newmark update. Same equations as the general path, none of its generality.
    fn linear_step(
        &mut self,
        model: &TorsionalModel,
        st: &mut DynState,
        h: f64,
        loads: &Loads,
        static_ratio: f64,
    ) -> Result<(), NewmarkError> {
        let n = model.dofs();
        let np = padded(n);
        let (g, rotor) = (model.generator, model.rotor);
        let idx = self.factor(model, h, 0, 0, &st.q)?;
        self.iterations += 1;
        let Newmark { cache, work: w, .. } = self;
        let factor = &cache[idx];
        let map = factor.step_map.as_deref().ok_or(NewmarkError::Singular)?;
        let h = factor.h; // equal to the requested h within SAME_STEP
        let (c1, c2) = (2.0 / h, 4.0 / (h * h));
        if w.padded.len() != np {
            w.padded = vec![0.0; np];
            w.x = vec![0.0; n];
        }
        let (q, v, a) = (&mut st.q[..n], &mut st.v[..n], &mut st.a[..n]);
        let (ratio, x, delta) = (&model.speed_ratio[..n], &mut w.x[..n], &mut w.padded[..np]);
        let (unit_rotor, unit_brake) = (&factor.unit_rotor[..n], &factor.unit_brake[..n]);
        // external torques act on the rotor (driving) and the generator (opposing)
        let (tr, tg) = (loads.rotor_torque, -loads.generator_torque);
        for i in 0..n {
            delta[i] = unit_rotor[i] * tr + unit_brake[i] * tg;
            // K·q = K·(q − r·q_rotor): angles relative to rigid rotation keep the deflections' digits
            x[i] = q[i] - ratio[i] * q[rotor];
        }
        let (mq, rest) = map.split_at(np * n);
        let (mv, ma) = rest.split_at(np * n);
        axpy_columns([(mq, x), (mv, v), (ma, a)], delta);
        let (mut torque, mut stuck) = (0.0, false);
        if loads.brake_capacity > 0.0 {
            let hold = if st.locked { static_ratio } else { 1.0 } * loads.brake_capacity;
            (torque, stuck) = brake_torque(c1 * delta[g] - v[g], c1 * unit_brake[g], hold, loads.brake_capacity);
            for i in 0..n {
                delta[i] += torque * unit_brake[i];
            }
            if stuck {
                // exactly at rest: the trapezoidal position update then adds no creep
                delta[g] = 0.5 * h * v[g];
            }
        }
        for i in 0..n {
            let d = delta[i];
            let v_new = c1 * d - v[i];
            a[i] = c2 * d - 2.0 * c1 * v[i] - a[i];
            q[i] += d;
            v[i] = v_new;
        }
        if stuck {
            v[g] = 0.0;
            a[g] = 0.0;
        }
        st.locked = stuck;
        st.brake_torque = -torque;
        st.applied = Some((loads.rotor_torque, loads.generator_torque));
        Ok(())
    }

    /// Advances `st` from t to t + h with loads evaluated at t + h.
    /// On error `st` is unchanged.
    pub fn step(
        &mut self,
        model: &TorsionalModel,
        st: &mut DynState,
        h: f64,
        loads: &Loads,
        static_ratio: f64,
    ) -> Result<(), NewmarkError> {
        let linear = !model.has_backlash() && !model.has_stiffness_variation();
        if linear {
            return self.linear_step(model, st, h, loads, static_ratio);
        }
        let n = model.dofs();
        let g = model.generator;
        if self.work.f.len() != n {
            self.work = Work {
                f: vec![0.0; n],
                fi: vec![0.0; n],
                q1: vec![0.0; n],
                v1: vec![0.0; n],
                r: vec![0.0; n],
                delta: vec![0.0; n],
                padded: vec![0.0; padded(n)],
                x: vec![0.0; n],
            };
        }
        external_forces(model, loads, &mut self.work.f);
        // the mesh stiffness pattern is lagged to the start of the step (st.q is unchanged until the end)
        let nonlinear = model.has_backlash();
        let (mut contact, double) = patterns(model, &st.q, &st.q);
        let hold = if st.locked { static_ratio } else { 1.0 } * loads.brake_capacity;
        // the step size of the factorisation in use (equal to h within SAME_STEP)
        let mut idx = self.factor(model, h, contact, double, &st.q)?;
        let h = self.cache[idx].h;
        let (c1, c2) = (2.0 / h, 4.0 / (h * h));
        let mut torque = 0.0;
        let mut stuck = false;
        for iteration in 0.. {
            if iteration == MAX_ITERATIONS {
                return Err(NewmarkError::NotSettled);
            }
            self.iterations += 1;
            let Newmark { cache, work: w, .. } = self;
            let factor = &cache[idx];
            // r = −R₀(Δ) = f − F_int(q + Δ, c1·Δ − v) − M a(Δ), a(Δ) = c2·Δ − 2c1·v − a
            if iteration == 0 {
                // Δ = 0: the residual needs no trial state
                for (v1, v) in w.v1.iter_mut().zip(&st.v) {
                    *v1 = -v;
                }
                internal_forces(model, &st.q, &w.v1, &st.q, &mut w.fi);
                for d in 0..n {
                    w.r[d] = w.f[d] - w.fi[d] + model.mass[d] * (2.0 * c1 * st.v[d] + st.a[d]);
                }
                w.delta.iter_mut().for_each(|x| *x = 0.0);
            } else {
                for d in 0..n {
                    w.q1[d] = st.q[d] + w.delta[d];
                    w.v1[d] = c1 * w.delta[d] - st.v[d];
                }
                internal_forces(model, &w.q1, &w.v1, &st.q, &mut w.fi);
                for d in 0..n {
                    let a1 = c2 * w.delta[d] - 2.0 * c1 * st.v[d] - st.a[d];
                    w.r[d] = w.f[d] - w.fi[d] - model.mass[d] * a1;
                }
            }
            for (column, r) in factor.inverse.chunks_exact(n).zip(&w.r) {
                for (x, a) in w.delta.iter_mut().zip(column) {
                    *x += a * r;
                }
            }
            // Brake: generator speed at the end of the step is c1·(Δ_g + T s_g) − v_g.
            (torque, stuck) = (0.0, false);
            if loads.brake_capacity > 0.0 {
                let speed = c1 * w.delta[g] - st.v[g];
                (torque, stuck) = brake_torque(speed, c1 * factor.unit_brake[g], hold, loads.brake_capacity);
                for (x, u) in w.delta.iter_mut().zip(&factor.unit_brake) {
                    *x += torque * u;
                }
            }
            if !nonlinear {
                break;
            }
            for d in 0..n {
                w.q1[d] = st.q[d] + w.delta[d];
            }
            let (now, _) = patterns(model, &w.q1, &st.q);
            if now == contact {
                break;
            }
            // Δ keeps the brake term: the next Newton pass recovers the brake-free solution for the
            // new contact pattern and adds the brake torque again.
            contact = now;
            idx = self.factor(model, h, contact, double, &st.q)?;
        }
        let delta = &mut self.work.delta;
        if stuck {
            // exactly at rest: the trapezoidal position update then adds no creep
            delta[g] = 0.5 * h * st.v[g];
        }
        for d in 0..n {
            let a1 = c2 * delta[d] - 2.0 * c1 * st.v[d] - st.a[d];
            let v_new = c1 * delta[d] - st.v[d];
            st.q[d] += delta[d];
            st.v[d] = v_new;
            st.a[d] = a1;
        }
        if stuck {
            st.v[g] = 0.0;
            st.a[g] = 0.0;
        }
        st.locked = stuck;
        // T acts on the DOF; report it positive when it opposes positive rotation.
        st.brake_torque = -torque;
        st.applied = Some((loads.rotor_torque, loads.generator_torque));
        Ok(())
    }
}
