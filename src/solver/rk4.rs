//! Classical explicit RK4. Stable only for h·ω_max ≤ 2.785 (the RK4 stability interval on the
//! imaginary axis), which the gear-mesh modes of a full-fidelity drivetrain push to a fraction of
//! a millisecond; a larger step is refused with the limit named instead of returning garbage.
//!
//! The brake slips with ±capacity; when the generator speed crosses zero within a step it is set to
//! rest and held while the holding torque stays within the static capacity (first-order event
//! location: the implicit integrator solves stick–slip exactly and is the default).

use super::{DynState, Loads, brake_at_rest_or_slip, external_forces, internal_forces};
use crate::physics::torsional::TorsionalModel;

/// Largest stable RK4 step for angular frequency ω_max (undamped limit 2√2 ≈ 2.785 / ω).
pub const STABILITY_BOUND: f64 = 2.785;

pub fn stability_limit(omega_max: f64) -> f64 {
    STABILITY_BOUND / omega_max
}

/// Accelerations at (q, v) and the brake torque used (positive opposing rotation).
fn accelerations(model: &TorsionalModel, q: &[f64], v: &[f64], loads: &Loads, locked: bool, out: &mut [f64]) -> f64 {
    let n = model.dofs();
    let mut f = vec![0.0; n];
    let mut fi = vec![0.0; n];
    external_forces(model, loads, &mut f);
    internal_forces(model, q, v, q, &mut fi);
    for d in 0..n {
        out[d] = (f[d] - fi[d]) / model.mass[d];
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

pub fn step(model: &TorsionalModel, st: &mut DynState, h: f64, loads: &Loads, static_ratio: f64) {
    let n = model.dofs();
    let g = model.generator;
    // a locked brake lets go when the torque to hold it exceeds the static capacity
    if st.locked {
        let mut a = vec![0.0; n];
        let hold = accelerations(model, &st.q, &st.v, loads, true, &mut a);
        let (_, still) = brake_at_rest_or_slip(0.0, hold, loads.brake_capacity, true, static_ratio);
        st.locked = still;
    }
    let locked = st.locked;
    let (q0, v0) = (st.q.clone(), st.v.clone());
    let mut k_q = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let mut k_v = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let mut q = q0.clone();
    let mut v = v0.clone();
    let mut brake = 0.0;
    for stage in 0..4 {
        if stage > 0 {
            let c = if stage == 3 { h } else { 0.5 * h };
            for d in 0..n {
                q[d] = q0[d] + c * k_q[stage - 1][d];
                v[d] = v0[d] + c * k_v[stage - 1][d];
            }
        }
        k_q[stage].copy_from_slice(&v);
        let t = accelerations(model, &q, &v, loads, locked, &mut k_v[stage]);
        if stage == 0 {
            brake = t;
        }
    }
    for d in 0..n {
        st.q[d] = q0[d] + h / 6.0 * (k_q[0][d] + 2.0 * k_q[1][d] + 2.0 * k_q[2][d] + k_q[3][d]);
        st.v[d] = v0[d] + h / 6.0 * (k_v[0][d] + 2.0 * k_v[1][d] + 2.0 * k_v[2][d] + k_v[3][d]);
    }
    if locked {
        st.v[g] = 0.0;
        st.q[g] = q0[g];
    } else if loads.brake_capacity > 0.0 && v0[g] * st.v[g] <= 0.0 && v0[g] != 0.0 {
        // the brake would reverse the disk: it stops instead (as OpenFAST's FixHSSBrTq)
        st.v[g] = 0.0;
        st.locked = true;
    }
    st.brake_torque = brake;
    let mut a = vec![0.0; n];
    accelerations(model, &st.q, &st.v, loads, st.locked, &mut a);
    st.a = a;
}
