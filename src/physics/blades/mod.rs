//! The rotationally sampled rotor: every blade element reads the full wind field where it is as the
//! blades turn, so the rotor's torque and thrust carry what a rotor-averaged series cannot: the blade
//! passing (3P for three blades) through shear and through the turbulence's structure across the disc,
//! and out-of-plane tilt and yaw moments from the uneven thrust.
//!
//! Geometry (x downwind, y to the left looking downwind as TurbSim's grid, z up; no tilt, cone or
//! yaw): blade b sits at azimuth ψ_b = ψ + 2πb/B, ψ = 0 pointing up, turning clockwise looking
//! downwind (OpenFAST's sense), so an element at radius r is at y = −r·sin ψ_b, z = z_hub + r·cos ψ_b
//! and moves along (−cos ψ_b, −sin ψ_b). It sees V_x = u along the axis and, in the plane,
//! V_y = ω·r + v·cos ψ_b + w·sin ψ_b (the blade speed plus the wind it runs into); the radial part of
//! (v, w) is left out, as a BEM has no spanwise flow. Each element is a quasi-steady BEM station in
//! that inflow ([`BemRotor::element_in`], read from [`table::LoadTable`]): no dynamic inflow or wake
//! skew, the induction of each element its own annulus's (as AeroDyn's BEM per blade node).
//!
//! The disc may move out of its plane ([`DiscMotion`]: the main shaft's tilt and yaw rates, from the
//! gearbox that carries the rotor): an element then moves downwind at Ω_tilt·(z − z_hub) + Ω_yaw·r·sin ψ_b
//! and sees that much less V_x. That is the rotor's aerodynamic damping of its tilt and yaw motion (a
//! disc tilting its top downwind loses thrust above the hub); FAST gets the same from the structural
//! velocities ElastoDyn hands to AeroDyn.
//!
//! Totals with the BEM's trapezoidal span weights w_i: torque Σ w_i·r·T', thrust Σ w_i·N', and the
//! moments of the thrust about the hub, tilt Σ w_i·N'·(z − z_hub) (positive when the thrust acts above
//! the hub, the sign of the rotor's `pitching_moment`) and yaw Σ w_i·N'·r·sin ψ_b (right-handed about
//! the vertical: positive when the thrust acts on the right half looking downwind).

pub mod table;

#[cfg(test)]
mod tests;

use super::bem::BemRotor;
use super::wind_field::WindField;
use serde::{Deserialize, Serialize};
use table::LoadTable;

/// A rotor's aerodynamic loads from the sampled field.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BladeLoads {
    /// N·m, positive driving.
    pub torque: f64,
    /// N
    pub thrust: f64,
    /// N·m: thrust's moment about the hub's lateral axis, positive above the hub.
    pub tilt: f64,
    /// N·m: thrust's moment about the vertical through the hub, positive on the right half.
    pub yaw: f64,
    /// Longitudinal wind at the hub point, m/s.
    pub hub_wind: f64,
}

/// The disc's angular velocity out of its plane, rad/s, in the hub's non-rotating frame (x to the left
/// looking downwind, y up, z downwind: gearbox6dof's housing frame): `tilt_rate` about x, positive when
/// the top of the disc moves downwind (the sense of a positive tilt moment), `yaw_rate` about y, positive
/// when its right half moves downwind (the sense of a positive yaw moment).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DiscMotion {
    pub tilt_rate: f64,
    pub yaw_rate: f64,
}

/// A full field and what the blades need to read it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BladeSampling {
    pub field: WindField,
    pub table: LoadTable,
    /// Height of the rotor's centre in the field's coordinates, m.
    pub hub_height: f64,
    /// Trapezoidal weight of each station along the span, m.
    weights: Vec<f64>,
    radii: Vec<f64>,
    blades: usize,
}

/// The field does not reach every blade element.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error(
    "the wind field's grid ({extent}) is too small for the rotor: its blades sweep a disc of radius {radius} m about \
     the hub at {hub_height} m"
)]
pub struct GridTooSmall {
    pub extent: String,
    pub radius: f64,
    pub hub_height: f64,
}

impl BladeSampling {
    /// The blades of `bem` in `field` with the hub at `hub_height` (m), the loads tabulated for pitch
    /// from `pitch_lo` to `pitch_hi` (rad).
    pub fn new(
        bem: &BemRotor,
        field: WindField,
        hub_height: f64,
        pitch_lo: f64,
        pitch_hi: f64,
    ) -> Result<Self, GridTooSmall> {
        let radius = bem.radius();
        if !field.covers(radius, hub_height) {
            return Err(GridTooSmall {
                extent: field.extent(),
                radius,
                hub_height,
            });
        }
        Ok(Self {
            field,
            table: LoadTable::new(bem, pitch_lo, pitch_hi),
            hub_height,
            weights: bem.span_weights(),
            radii: bem.stations.iter().map(|s| s.radius).collect(),
            blades: bem.blade.blades as usize,
        })
    }

    /// Loads at time `t` (s) with blade 1 at azimuth `azimuth` (rad), rotor speed `omega` (rad/s),
    /// pitch (rad) and the disc moving out of its plane as `disc`, the stations read from the table.
    pub fn loads(&self, bem: &BemRotor, t: f64, azimuth: f64, omega: f64, pitch: f64, disc: DiscMotion) -> BladeLoads {
        let columns = self.table.columns(pitch);
        self.sum(t, azimuth, omega, disc, |i, vx, vy| {
            self.table.loads(bem, i, vx, vy, columns)
        })
    }

    /// The same with every station solved (the reference the table is checked against; 3 × stations
    /// momentum balances a call).
    pub fn loads_solved(
        &self,
        bem: &BemRotor,
        t: f64,
        azimuth: f64,
        omega: f64,
        pitch: f64,
        disc: DiscMotion,
    ) -> BladeLoads {
        self.sum(t, azimuth, omega, disc, |i, vx, vy| {
            let e = bem.element_in(i, vx, vy, pitch);
            (e.normal_n_per_m, e.tangential_n_per_m)
        })
    }

    fn sum(
        &self,
        t: f64,
        azimuth: f64,
        omega: f64,
        disc: DiscMotion,
        element: impl Fn(usize, f64, f64) -> (f64, f64),
    ) -> BladeLoads {
        let field = &self.field;
        let frame = field.frame(t);
        let mut out = BladeLoads {
            hub_wind: field.at(frame, field.cell(0.0, self.hub_height))[0],
            ..BladeLoads::default()
        };
        let pitch_between = std::f64::consts::TAU / self.blades as f64;
        for b in 0..self.blades {
            let (sin, cos) = (azimuth + b as f64 * pitch_between).sin_cos();
            for (i, (&r, &w)) in self.radii.iter().zip(&self.weights).enumerate() {
                let (y, dz) = (-r * sin, r * cos);
                let [u, v, wz] = field.at(frame, field.cell(y, self.hub_height + dz));
                // the element's own speed downwind as the disc tilts and yaws (0 on a fixed disc)
                let downwind = disc.tilt_rate * dz + disc.yaw_rate * r * sin;
                let (normal, tangential) = element(i, u - downwind, omega * r + v * cos + wz * sin);
                out.torque += w * r * tangential;
                out.thrust += w * normal;
                out.tilt += w * normal * dz;
                out.yaw += w * normal * r * sin;
            }
        }
        out
    }
}
