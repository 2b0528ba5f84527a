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

/// Rows of the step map are padded to a multiple of this, so its columns split into fixed-size
/// chunks that compile to SIMD without bounds checks or remainder loops.
const LANES: usize = 4;

fn padded(n: usize) -> usize {
    n.div_ceil(LANES) * LANES
}

/// y += Σ A_k·x_k for column-major blocks A_k whose columns have y.len() rows (a multiple of
/// LANES). Rows are taken LANES at a time and accumulated in registers over every column of every
/// block (register blocking). On x86_64 the accumulation uses SSE2, part of the x86_64 baseline, so
/// the binary runs on every x86_64 CPU; elsewhere the same loop is plain Rust.
fn axpy_columns(blocks: [(&[f64], &[f64]); 3], y: &mut [f64]) {
    let rows = y.len();
    assert!(rows.is_multiple_of(LANES));
    for (a, x) in blocks {
        assert_eq!(a.len(), rows * x.len());
    }
    for start in (0..rows).step_by(LANES) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_add_pd, _mm_loadu_pd, _mm_mul_pd, _mm_set1_pd, _mm_storeu_pd};
            // SAFETY: SSE2 is always present on x86_64. Every access reads or writes two f64 at
            // offsets start, start + 2 (< rows) of a column of `rows` entries, inside slices whose
            // lengths were asserted above.
            unsafe {
                let out = y.as_mut_ptr().add(start);
                let (mut lo, mut hi) = (_mm_loadu_pd(out), _mm_loadu_pd(out.add(2)));
                for (a, x) in blocks {
                    let mut p = a.as_ptr().add(start);
                    for &s in x {
                        let sv = _mm_set1_pd(s);
                        lo = _mm_add_pd(lo, _mm_mul_pd(_mm_loadu_pd(p), sv));
                        hi = _mm_add_pd(hi, _mm_mul_pd(_mm_loadu_pd(p.add(2)), sv));
                        p = p.add(rows);
                    }
                }
                _mm_storeu_pd(out, lo);
                _mm_storeu_pd(out.add(2), hi);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let mut acc = [0.0; LANES];
            acc.copy_from_slice(&y[start..start + LANES]);
            for (a, x) in blocks {
                for (column, &s) in a.chunks_exact(rows).zip(x) {
                    for i in 0..LANES {
                        acc[i] += column[start + i] * s;
                    }
                }
            }
            y[start..start + LANES].copy_from_slice(&acc);
        }
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
        for (i, e) in model.elements.iter().enumerate() {
            let touching = e.half_backlash == 0.0 || i >= 64 || contact & (1 << i) != 0;
            if !touching {
                continue;
            }
            let k = e.stiffness_at(q_stiff) + 2.0 / h * e.damping;
            for &(a, ga) in &e.coeffs {
                for &(b, gb) in &e.coeffs {
                    j[(a, b)] += k * ga * gb;
                }
            }
        }
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
        let first = self.factor(model, h, contact, double, &st.q)?;
        let h = self.cache[first].h;
        let (c1, c2) = (2.0 / h, 4.0 / (h * h));
        let mut torque = 0.0;
        let mut stuck = false;
        let linear = !nonlinear && !model.has_stiffness_variation();
        for iteration in 0.. {
            if iteration == MAX_ITERATIONS {
                return Err(NewmarkError::NotSettled);
            }
            self.iterations += 1;
            let idx = self.factor(model, h, contact, double, &st.q)?;
            let Newmark { cache, work: w, .. } = self;
            let factor = &cache[idx];
            // r = −R₀(Δ) = f − F_int(q + Δ, c1·Δ − v) − M a(Δ), a(Δ) = c2·Δ − 2c1·v − a
            if let Some(map) = factor.step_map.as_ref().filter(|_| linear) {
                // Δ = W·[q; v; a] + J⁻¹ f (f acts on the rotor and generator only)
                let (tr, tg) = (w.f[model.rotor], w.f[g]);
                for ((x, ur), ug) in w.delta.iter_mut().zip(&factor.unit_rotor).zip(&factor.unit_brake) {
                    *x = ur * tr + ug * tg;
                }
                let np = padded(n);
                w.padded[..n].copy_from_slice(&w.delta);
                let (mq, rest) = map.split_at(np * n);
                let (mv, ma) = rest.split_at(np * n);
                // K·q = K·(q − r·q_rotor): angles relative to rigid rotation keep the digits of the deflections
                for ((x, q), r) in w.x.iter_mut().zip(&st.q).zip(&model.speed_ratio) {
                    *x = q - r * st.q[model.rotor];
                }
                axpy_columns([(mq, &w.x), (mv, &st.v), (ma, &st.a)], &mut w.padded);
                w.delta.copy_from_slice(&w.padded[..n]);
            } else if iteration == 0 {
                // Δ = 0: the residual needs no trial state
                if linear {
                    model.linear_forces(&st.q, &st.v, -1.0, &mut w.fi);
                } else {
                    for (v1, v) in w.v1.iter_mut().zip(&st.v) {
                        *v1 = -v;
                    }
                    internal_forces(model, &st.q, &w.v1, &st.q, &mut w.fi);
                }
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
            if factor.step_map.is_none() || !linear {
                for (column, r) in factor.inverse.chunks_exact(n).zip(&w.r) {
                    for (x, a) in w.delta.iter_mut().zip(column) {
                        *x += a * r;
                    }
                }
            }
            // Brake: generator speed at the end of the step is c1·(Δ_g + T s_g) − v_g.
            torque = 0.0;
            stuck = false;
            if loads.brake_capacity > 0.0 {
                let s = factor.unit_brake[g];
                let stick = -(c1 * w.delta[g] - st.v[g]) / (c1 * s);
                if stick.abs() <= hold {
                    torque = stick;
                    stuck = true;
                } else {
                    torque = loads.brake_capacity * stick.signum();
                }
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
