//! The full field the rotor's blades sample (wind_sampling = blades): read from wind_file, or generated
//! from the case's own wind (mean, σ, shear, seed), every refusal naming the parameter or file at fault.

use crate::fmi2::fmu::error::{ParameterError, SlaveError, SlaveResult};
use crate::physics::turbulence::Variance;
use crate::physics::wind_field::{FieldSpec, Grid, WindField, bts, generate, steady};
use std::path::{Path, PathBuf};

/// Grid points each way of a generated field: 11 puts a point every 0.22 radii (8.8 m on C's 40 m
/// rotor), finer than the u coherence length at the 3P frequency, and generates 600 s in about 0.6 s
/// (one Cholesky factorisation of the 121-point coherence matrix per frequency is the cost).
const POINTS: usize = 11;
/// The grid's side over the rotor's diameter: the tips inside with 10 % to spare.
const MARGIN: f64 = 1.1;
/// Period of a generated field when turbulence_period is 0: IEC's 10 minutes (the series' 3276.8 s
/// record on 121 points would hold 190 MB).
const DEFAULT_PERIOD: f64 = 600.0;

/// wind_file read: an absolute path, or a name under the FMU's resources/. Returns the field and its
/// name for messages.
pub fn read(name: &str, resources: Option<&Path>) -> SlaveResult<(WindField, String)> {
    let mut path = PathBuf::from(name);
    if path.is_relative()
        && let Some(dir) = resources
    {
        path = dir.join(name);
    }
    let field = bts::read(&path).map_err(|e| SlaveError::new(format!("wind_file: {e}")))?;
    let mean = field.mean_hub;
    if !(mean.is_finite() && mean > 0.0) {
        return Err(SlaveError::new(format!(
            "wind_file: {}: hub-height mean wind {mean} m/s in its header: the rotor needs a positive one (its trim and \
             pitch control start from it)",
            path.display()
        )));
    }
    let grid_ok = field.dy > 0.0 && field.dz > 0.0 && field.ny >= 2 && field.nz >= 2;
    if !grid_ok || !field.z_bottom.is_finite() {
        return Err(SlaveError::new(format!(
            "wind_file: {}: a {} × {} grid with dy = {} m, dz = {} m, bottom {} m cannot hold a rotor disc",
            path.display(),
            field.ny,
            field.nz,
            field.dy,
            field.dz,
            field.z_bottom
        )));
    }
    Ok((field, format!("wind_file {}", path.display())))
}

/// σ of u at the hub point over the field's time steps, m/s (what turbulence_sigma reports for a file).
pub fn hub_sigma(field: &WindField, hub_height: f64) -> f64 {
    let u: Vec<f64> = (0..field.nt)
        .map(|t| field.velocity_at(t as f64 * field.dt, 0.0, hub_height)[0])
        .collect();
    let mean = u.iter().sum::<f64>() / u.len() as f64;
    (u.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / u.len() as f64).sqrt()
}

/// What a generated field is made from: the case's wind as the rotor-averaged series would have it.
pub struct FieldRequest {
    pub mean_wind: f64,
    pub sigma: f64,
    pub hub_height: f64,
    pub radius: f64,
    pub shear_exponent: f64,
    /// turbulence_period, s (0: 600 s)
    pub period: f64,
    /// turbulence_scaling's choice, for a period of its own
    pub variance: Variance,
    pub seed: u64,
}

impl FieldRequest {
    pub fn generate(&self) -> SlaveResult<WindField> {
        let side = 2.0 * MARGIN * self.radius;
        if self.hub_height <= 0.5 * side {
            return Err(ParameterError::Conflict(format!(
                "wind_sampling = blades: hub_height = {} m is too low for a generated field over the rotor (radius {} m): \
                 its grid, {side} m square about the hub, would reach the ground; give a wind_file",
                self.hub_height, self.radius
            ))
            .into());
        }
        let (period, variance) = if self.period > 0.0 {
            (self.period, self.variance)
        } else {
            (DEFAULT_PERIOD, Variance::TenMinute)
        };
        let spec = FieldSpec {
            mean_wind: self.mean_wind,
            sigma: self.sigma,
            hub_height: self.hub_height,
            shear_exponent: self.shear_exponent,
            grid: Grid {
                ny: POINTS,
                nz: POINTS,
                width: side,
                height: side,
            },
            period,
            max_dt: 0.05,
            variance,
            seed: self.seed,
        };
        let made = if self.sigma > 0.0 {
            generate(&spec)
        } else {
            steady(&spec)
        };
        made.map_err(|e| SlaveError::new(format!("wind_sampling = blades, generating the field: {e}")))
    }
}
