//! Newmark average acceleration (β = 1/4, γ = 1/2), the trapezoidal rule for second-order systems:
//! A-stable, second order, no numerical damping, and exactly energy-conserving for an undamped
//! linear model. Each step solves J Δ = r with J = K_t + (2/h) C + (4/h²) M. J depends only on the
//! step size, the contact pattern of backlash meshes and the single/double tooth contact pattern, so
//! factorisations are cached per pattern: a linear drivetrain factorises once per step size.
//!
//! Stick–slip of the HSS brake is solved inside the step: the solution is affine in the brake torque
//! T (Δ = Δ₀ + T·J⁻¹e_g), so T is the torque that makes the generator speed exactly zero at the end
//! of the step if the brake can supply it (stick), else ±capacity (slip). A stuck brake therefore
//! never creeps and never chatters.

use super::{DynState, Loads, external_forces, internal_forces};
use crate::physics::torsional::TorsionalModel;
use nalgebra::{DMatrix, DVector, LU, Dyn};
use std::collections::HashMap;

const MAX_ITERATIONS: usize = 50;
const CACHE_LIMIT: usize = 64;

#[derive(Clone)]
struct Factor {
    lu: LU<f64, Dyn, Dyn>,
    /// J⁻¹ e_g: response to a unit torque on the generator DOF.
    unit_brake: DVector<f64>,
}

type Key = (u64, u64, u64);

/// Integrator with its cache of factorisations and scratch vectors. Cloning gives an empty cache,
/// refilled on demand with identical factorisations, so snapshots stay cheap and bit-identical.
pub struct Newmark {
    cache: HashMap<Key, Factor>,
    last: Option<(Key, Factor)>,
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

/// Bit pattern of elements whose stiffness or contact differs from nominal.
fn patterns(model: &TorsionalModel, q_contact: &[f64], q_stiff: &[f64]) -> (u64, u64) {
    let (mut contact, mut double) = (0u64, 0u64);
    for (i, e) in model.elements.iter().enumerate().take(64) {
        if e.half_backlash > 0.0 && e.contact(e.deflection(q_contact)).1 {
            contact |= 1 << i;
        }
        if let Some(v) = &e.variation {
            if v.stiffness(q_stiff[v.dof]) == v.k_double {
                double |= 1 << i;
            }
        }
    }
    (contact, double)
}

impl Newmark {
    pub fn new() -> Self {
        Self { cache: HashMap::new(), last: None, factorizations: 0, iterations: 0 }
    }

    fn factor(&mut self, model: &TorsionalModel, h: f64, contact: u64, q_stiff: &[f64]) -> Result<Factor, String> {
        let (_, double) = patterns(model, q_stiff, q_stiff);
        let key = (h.to_bits(), contact, double);
        if let Some((k, f)) = &self.last {
            if *k == key {
                return Ok(f.clone());
            }
        }
        let factor = match self.cache.get(&key) {
            Some(f) => f.clone(),
            None => {
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
                let lu = j.lu();
                let mut unit = DVector::zeros(n);
                unit[model.generator] = 1.0;
                if !lu.solve_mut(&mut unit) {
                    return Err("Newmark iteration matrix is singular".into());
                }
                self.factorizations += 1;
                if self.cache.len() >= CACHE_LIMIT {
                    self.cache.clear();
                }
                let f = Factor { lu, unit_brake: unit };
                self.cache.insert(key, f.clone());
                f
            }
        };
        self.last = Some((key, factor.clone()));
        Ok(factor)
    }

    /// Advances `st` from t to t + h with loads evaluated at t + h.
    pub fn step(&mut self, model: &TorsionalModel, st: &mut DynState, h: f64, loads: &Loads, static_ratio: f64) -> Result<(), String> {
        let n = model.dofs();
        let g = model.generator;
        let mut f = vec![0.0; n];
        external_forces(model, loads, &mut f);
        let q_stiff = st.q.clone(); // mesh stiffness pattern lagged to the start of the step
        let nonlinear = model.has_backlash();
        let mut delta = DVector::<f64>::zeros(n);
        let mut q1 = st.q.clone();
        let mut v1 = vec![0.0; n];
        let mut fi = vec![0.0; n];
        let (mut contact, _) = patterns(model, &st.q, &q_stiff);
        let hold = if st.locked { static_ratio } else { 1.0 } * loads.brake_capacity;
        let (c1, c2) = (2.0 / h, 4.0 / (h * h));
        let mut torque = 0.0;
        let mut stuck = false;
        for iteration in 0.. {
            if iteration == MAX_ITERATIONS {
                return Err(format!("backlash contact did not settle in {MAX_ITERATIONS} Newton iterations"));
            }
            self.iterations += 1;
            let factor = self.factor(model, h, contact, &q_stiff)?;
            for d in 0..n {
                q1[d] = st.q[d] + delta[d];
                v1[d] = c1 * delta[d] - st.v[d];
            }
            internal_forces(model, &q1, &v1, &q_stiff, &mut fi);
            // r = −R₀(Δ) = f − F_int − M a(Δ)
            let mut r = DVector::from_fn(n, |d, _| {
                let a1 = c2 * delta[d] - 2.0 * c1 * st.v[d] - st.a[d];
                f[d] - fi[d] - model.mass[d] * a1
            });
            factor.lu.solve_mut(&mut r);
            delta += &r;
            // Brake: generator speed at the end of the step is c1·(Δ_g + T s_g) − v_g.
            torque = 0.0;
            stuck = false;
            if loads.brake_capacity > 0.0 {
                let s = factor.unit_brake[g];
                let stick = -(c1 * delta[g] - st.v[g]) / (c1 * s);
                if stick.abs() <= hold {
                    torque = stick;
                    stuck = true;
                } else {
                    torque = loads.brake_capacity * stick.signum();
                }
                delta.axpy(torque, &factor.unit_brake, 1.0);
            }
            if !nonlinear {
                break;
            }
            for d in 0..n {
                q1[d] = st.q[d] + delta[d];
            }
            let (now, _) = patterns(model, &q1, &q_stiff);
            if now == contact {
                break;
            }
            // Δ keeps the brake term: the next Newton pass recovers the brake-free solution for the
            // new contact pattern and adds the brake torque again.
            contact = now;
        }
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
        Ok(())
    }
}
