//! The gearbox with each roller set's force taken from its own tangent between exact evaluations.
//!
//! The roller sets are about half of a lamina-bearing step's work, and the later iterations of a step,
//! like the steps of a held gearbox, move them little. A set's force is f₀ + K·Δx + C·Δẋ from the force,
//! stiffness and damping of its last exact evaluation while no lamina's approach can have moved more
//! than `distance` (m) since, nor as far as the nearest kink of the lamina law (a lamina touching or
//! leaving its race, or its damping pulling its load to zero): the linearised force then differs from
//! the exact one by the smooth remainder of q ∝ δ^(10/9) alone, a relative (Δ/δ)²/18 for an approach δ.
//! A set whose tangents go unused (rattling in its clearance, a fast cage) is evaluated exactly without
//! one for a while. docs/PERFORMANCE.md measures what it moves against the exact evaluation and the
//! bench's 0.25 ms reference.
//!
//! The kept evaluations are history no state holds: their owner forgets them wherever it forgets the
//! integrator's factorisations, so a run restored from a state repeats the run that went on from it.
//! The reported loads (the FMU's outputs) are always evaluated exactly.

use super::bearing::SetMemory;
use super::mesh::FlankLoad;
use super::model::Gearbox;
use super::system::Sets;
use crate::solver::system::{Friction, InputLoad, Linearity, Mass, SecondOrderSystem};
use nalgebra::DMatrix;
use std::cell::RefCell;

/// Each roller set's last exact evaluation, owned by whoever steps the model (an FMU instance) and
/// forgotten with its factorisations.
#[derive(Debug, Clone, Default)]
pub struct SetTangents {
    sets: RefCell<Vec<SetMemory>>,
}

impl SetTangents {
    /// Forgets every set's evaluation: the next evaluation of each is exact.
    pub fn forget(&mut self) {
        self.sets.get_mut().clear();
    }

    /// `gearbox` evaluating its roller sets near these tangents within `distance` (m; 0: always
    /// exactly, as the gearbox itself).
    pub fn around<'a>(&'a self, gearbox: &'a Gearbox, distance: f64) -> Near<'a> {
        let mut sets = self.sets.borrow_mut();
        if sets.len() != gearbox.rollers.len() {
            sets.clear();
            sets.resize(gearbox.rollers.len(), SetMemory::Empty);
        }
        Near {
            gearbox,
            tangents: &self.sets,
            distance,
        }
    }
}

/// A gearbox whose roller sets' forces come from their tangents ([`SetTangents::around`]); everything
/// else is the gearbox's own.
pub struct Near<'a> {
    gearbox: &'a Gearbox,
    tangents: &'a RefCell<Vec<SetMemory>>,
    distance: f64,
}

impl SecondOrderSystem for Near<'_> {
    fn dofs(&self) -> usize {
        self.gearbox.dofs()
    }

    fn linearity(&self) -> Linearity {
        self.gearbox.linearity()
    }

    fn mass(&self) -> Mass<'_> {
        self.gearbox.mass()
    }

    fn input_loads(&self) -> &[InputLoad] {
        self.gearbox.input_loads()
    }

    fn internal_forces(&self, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        if self.distance <= 0.0 {
            return self.gearbox.internal_forces(t, q, v, out);
        }
        let mut tangents = self.tangents.borrow_mut();
        let sets = Sets::Near(&mut tangents, self.distance);
        self.gearbox.state_forces(q, v, out, None, sets, |_: [FlankLoad; 2]| {});
        self.gearbox.add_rotor_loads(q, out);
    }

    fn add_tangent(&self, t: f64, q: &[f64], v: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>) {
        self.gearbox.add_tangent(t, q, v, c_c, c_k, j);
    }

    fn factor_key(&self, t: f64, q: &[f64], key: &mut Vec<u64>) {
        self.gearbox.factor_key(t, q, key);
    }

    fn friction(&self, u: &[f64]) -> Option<Friction> {
        self.gearbox.friction(u)
    }

    fn rigid_mode(&self) -> Option<(&[f64], usize)> {
        self.gearbox.rigid_mode()
    }
}
