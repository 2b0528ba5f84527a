//! Classical explicit RK4. Stable only for h·ω_max ≤ 2.785 (the RK4 stability interval on the
//! imaginary axis), which the gear-mesh modes of a full-fidelity drivetrain push to a fraction of
//! a millisecond; a larger step is refused with the limit named instead of returning garbage.
//!
//! The brake slips with ±capacity; when the generator speed crosses zero within a step it is set to
//! rest and held while the holding torque stays within the static capacity (first-order event
//! location: the implicit integrator solves stick–slip exactly and is the default).

use super::{DynState, Loads, Scratch, brake_at_rest_or_slip, external_forces, internal_forces};
use crate::physics::torsional::TorsionalModel;

/// Largest stable RK4 step is STABILITY_BOUND / ω_max (2√2 on the imaginary axis).
pub const STABILITY_BOUND: f64 = 2.785;

pub fn stability_limit(omega_max: f64) -> f64 {
    STABILITY_BOUND / omega_max
}

/// Scratch memory for one RK4 integrator.
#[derive(Debug, Clone, Default)]
pub struct Rk4 {
    k_q: [Vec<f64>; 4],
    k_v: [Vec<f64>; 4],
    q: Vec<f64>,
    v: Vec<f64>,
    q0: Vec<f64>,
    v0: Vec<f64>,
    s: Scratch,
}

/// Accelerations at (q, v) and the brake torque used (positive opposing rotation).
fn accelerations(
    model: &TorsionalModel,
    q: &[f64],
    v: &[f64],
    loads: &Loads,
    locked: bool,
    s: &mut Scratch,
    out: &mut [f64],
) -> f64 {
    let n = model.dofs();
    external_forces(model, loads, &mut s.f);
    internal_forces(model, q, v, q, &mut s.fi);
    for d in 0..n {
        out[d] = (s.f[d] - s.fi[d]) / model.mass[d];
    }
    let g = model.generator;
    if locked {
        let hold = model.mass[g] * out[g];
        out[g] = 0.0;
        hold
    } else if loads.brake_capacity > 0.0 && v[g] != 0.0 {
        let t = loads.brake_capacity * v[g].signum();
        out[g] -= t / model.mass[g];
        t
    } else {
        0.0
    }
}

impl Rk4 {
    fn fit(&mut self, n: usize) {
        if self.q.len() != n {
            let z = vec![0.0; n];
            self.k_q = std::array::from_fn(|_| z.clone());
            self.k_v = std::array::from_fn(|_| z.clone());
            self.q = z.clone();
            self.v = z.clone();
            self.q0 = z.clone();
            self.v0 = z;
            self.s.fit(n);
        }
    }

    pub fn step(&mut self, model: &TorsionalModel, st: &mut DynState, h: f64, loads: &Loads, static_ratio: f64) {
        let n = model.dofs();
        let g = model.generator;
        self.fit(n);
        let w = self;
        // a locked brake lets go when the torque to hold it exceeds the static capacity
        if st.locked {
            let hold = accelerations(model, &st.q, &st.v, loads, true, &mut w.s, &mut w.k_v[0]);
            st.locked = brake_at_rest_or_slip(0.0, hold, loads.brake_capacity, true, static_ratio).1;
        }
        let locked = st.locked;
        w.q0.copy_from_slice(&st.q);
        w.v0.copy_from_slice(&st.v);
        w.q.copy_from_slice(&st.q);
        w.v.copy_from_slice(&st.v);
        let mut brake = 0.0;
        for stage in 0..4 {
            if stage > 0 {
                let c = if stage == 3 { h } else { 0.5 * h };
                for d in 0..n {
                    w.q[d] = w.q0[d] + c * w.k_q[stage - 1][d];
                    w.v[d] = w.v0[d] + c * w.k_v[stage - 1][d];
                }
            }
            w.k_q[stage].copy_from_slice(&w.v);
            let t = accelerations(model, &w.q, &w.v, loads, locked, &mut w.s, &mut w.k_v[stage]);
            if stage == 0 {
                brake = t;
            }
        }
        for d in 0..n {
            st.q[d] = w.q0[d] + h / 6.0 * (w.k_q[0][d] + 2.0 * w.k_q[1][d] + 2.0 * w.k_q[2][d] + w.k_q[3][d]);
            st.v[d] = w.v0[d] + h / 6.0 * (w.k_v[0][d] + 2.0 * w.k_v[1][d] + 2.0 * w.k_v[2][d] + w.k_v[3][d]);
        }
        if locked {
            st.v[g] = 0.0;
            st.q[g] = w.q0[g];
        } else if loads.brake_capacity > 0.0 && w.v0[g] * st.v[g] <= 0.0 && w.v0[g] != 0.0 {
            // the brake would reverse the disk: it stops instead (as OpenFAST's FixHSSBrTq)
            st.v[g] = 0.0;
            st.locked = true;
        }
        st.brake_torque = brake;
        // RK4 keeps no accelerations: the next step recomputes them from the loads
        st.applied = None;
    }
}
