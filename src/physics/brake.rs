//! The HSS friction brake: a caliper on a disk, Coulomb friction with stiction. Its command
//! (0–1, the caliper's deployment) scales the kinetic torque; a disk at rest holds up to
//! `static_ratio` times that. The integrators solve stick and slip exactly
//! ([`crate::solver::system::Friction`]).

use crate::solver::system::Friction;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct DiskBrake {
    /// Kinetic torque at full command, N·m (0: no brake).
    pub torque_max: f64,
    /// Static over kinetic friction coefficient, ≥ 1 for real pads.
    pub static_ratio: f64,
}

impl DiskBrake {
    /// The friction contact on DOF `dof` for a command, clamped to [0, 1] (None when released).
    pub fn friction(&self, dof: usize, command: f64) -> Option<Friction> {
        let kinetic = command.clamp(0.0, 1.0) * self.torque_max;
        (kinetic > 0.0).then_some(Friction {
            dof,
            kinetic,
            holding: kinetic * self.static_ratio,
        })
    }
}
