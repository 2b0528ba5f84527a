//! Time integration of a [`TorsionalModel`] inside an FMU step: the implicit Newmark average-
//! acceleration (trapezoidal) scheme, and explicit RK4. Both handle the HSS friction brake with
//! stiction; the implicit one also handles backlash exactly (active-set Newton). Integrators keep
//! their scratch memory, so a step allocates nothing.

pub mod newmark;
pub mod rk4;

use crate::physics::torsional::TorsionalModel;
use serde::{Deserialize, Serialize};

/// External loads at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Loads {
    /// On the rotor, positive driving.
    pub rotor_torque: f64,
    /// Electromagnetic, on the generator, positive opposing rotation.
    pub generator_torque: f64,
    /// Kinetic friction torque the brake applies while slipping (command × maximum), ≥ 0.
    pub brake_capacity: f64,
}

/// The dynamic state both integrators advance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DynState {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    /// Accelerations consistent with the loads at the start of the next step.
    pub a: Vec<f64>,
    /// The brake holds the generator DOF at standstill.
    pub locked: bool,
    /// Brake torque on the generator DOF, positive opposing positive rotation.
    pub brake_torque: f64,
    /// The external loads `a` is consistent with (None: not yet computed).
    pub applied: Option<(f64, f64)>,
}

impl DynState {
    pub fn new(q: Vec<f64>, v: Vec<f64>) -> Self {
        let n = q.len();
        Self {
            q,
            v,
            a: vec![0.0; n],
            locked: false,
            brake_torque: 0.0,
            applied: None,
        }
    }
}

/// Σ g F over all elements with the stiffness of each element taken at `q_stiff`.
pub(crate) fn internal_forces(model: &TorsionalModel, q: &[f64], v: &[f64], q_stiff: &[f64], out: &mut [f64]) {
    out.iter_mut().for_each(|x| *x = 0.0);
    for e in &model.elements {
        let k = e.stiffness_at(q_stiff);
        let f = e.force(k, e.deflection(q), e.deflection(v));
        for &(d, g) in &e.coeffs {
            out[d] += g * f;
        }
    }
}

/// External torques on each DOF (without the brake).
pub(crate) fn external_forces(model: &TorsionalModel, loads: &Loads, out: &mut [f64]) {
    out.iter_mut().for_each(|x| *x = 0.0);
    out[model.rotor] += loads.rotor_torque;
    out[model.generator] -= loads.generator_torque;
}

/// Reusable buffers of length n.
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    pub(crate) f: Vec<f64>,
    pub(crate) fi: Vec<f64>,
}

impl Scratch {
    pub(crate) fn fit(&mut self, n: usize) {
        if self.f.len() != n {
            self.f = vec![0.0; n];
            self.fi = vec![0.0; n];
        }
    }
}

/// Sets the accelerations from the equations of motion at the start of a step, so input jumps at a
/// communication point act from that point on (zero-order hold), brake included.
///
/// For a linear model the state's accelerations already satisfy the equations of motion for the
/// previously applied loads (Newmark enforces them at every step end), so only the two loaded DOFs
/// change: an O(1) update instead of a sweep over all elements. Nonlinear models (backlash, time-
/// varying stiffness) recompute everything.
pub fn consistent_acceleration(
    model: &TorsionalModel,
    st: &mut DynState,
    loads: &Loads,
    static_ratio: f64,
    s: &mut Scratch,
) {
    let n = model.dofs();
    let g = model.generator;
    let m = model.mass[g];
    let linear = !model.has_backlash() && !model.has_stiffness_variation();
    match st.applied {
        Some((rotor, generator)) if linear => {
            st.a[model.rotor] += (loads.rotor_torque - rotor) / model.mass[model.rotor];
            // undo the previous brake torque, apply the new generator torque
            st.a[g] += (st.brake_torque - (loads.generator_torque - generator)) / m;
        }
        _ => {
            s.fit(n);
            external_forces(model, loads, &mut s.f);
            internal_forces(model, &st.q, &st.v, &st.q, &mut s.fi);
            for d in 0..n {
                st.a[d] = (s.f[d] - s.fi[d]) / model.mass[d];
            }
        }
    }
    let (torque, locked) = brake_at_rest_or_slip(st.v[g], m * st.a[g], loads.brake_capacity, st.locked, static_ratio);
    st.a[g] -= torque / m;
    st.brake_torque = torque;
    st.locked = locked;
    st.applied = Some((loads.rotor_torque, loads.generator_torque));
}

/// Brake torque (positive opposing rotation) for speed `w` when the other torques on the generator
/// DOF sum to `net`: slipping → ±capacity; at rest → whatever holds it, up to the static capacity.
pub(crate) fn brake_at_rest_or_slip(w: f64, net: f64, cap: f64, was_locked: bool, static_ratio: f64) -> (f64, bool) {
    if cap <= 0.0 {
        return (0.0, false);
    }
    if w != 0.0 {
        return (cap * w.signum(), false);
    }
    let hold = if was_locked { cap * static_ratio } else { cap };
    if net.abs() <= hold {
        (net, true)
    } else {
        (cap * net.signum(), false)
    }
}

/// Kinetic energy plus elastic energy of every element in contact, J.
pub fn stored_energy(model: &TorsionalModel, q: &[f64], v: &[f64]) -> f64 {
    let kinetic: f64 = model.mass.iter().zip(v).map(|(m, w)| 0.5 * m * w * w).sum();
    let elastic: f64 = model
        .elements
        .iter()
        .map(|e| {
            let (x, _) = e.contact(e.deflection(q));
            0.5 * e.stiffness_at(q) * x * x
        })
        .sum();
    kinetic + elastic
}
