//! IEC 61400-1 ed. 3 full-field turbulence: u, v and w on a rectangular grid in the rotor plane, as
//! TurbSim's IEC Kaimal model makes them (TurbSim user's guide, NREL/TP-500-46198), reproducible by seed.
//!
//! - Spectra (IEC 61400-1 ed. 3 Annex B.2, [`spectra`]): Kaimal for each component, σ_v = 0.8σ1,
//!   σ_w = 0.5σ1, integral scales L_u = 8.1Λ1, L_v = 2.7Λ1, L_w = 0.66Λ1, the same at every point.
//! - Coherence ([`coherence`]): u between two points r apart, Coh = exp(−12·√((f·r/V)² + (0.12·r/L_c)²)),
//!   L_c = 8.1Λ1; v and w uncorrelated between points, as TurbSim's IEC model leaves them.
//! - Mean: a power law in height on u, V(z) = V_hub·(z/z_hub)^α; v and w have none.
//! - Synthesis ([`synthesis`]): Veers' method (Veers 1988, SAND88-0152). At every frequency the
//!   coherence matrix is factored C = L·Lᵀ (Cholesky) and the points' Fourier coefficients are
//!   √(S(f)·Δf)·L·e^{iφ}, φ independent uniform phases per point; one inverse real FFT per point and
//!   component. The field is periodic over its period and has exactly the mean profile over it.
//! - Variance ([`Variance`], as the rotor-averaged series of [`super::turbulence`]): the spectrum's own,
//!   or σ1 read as IEC's 10-minute standard deviation. Then v and w hold their σ at every point exactly
//!   (a single phase per bin and point), and u, whose points mix phases through L, is scaled by one
//!   factor over the grid so the points' mean variance is what the spectrum holds: TurbSim's
//!   `ScaleIEC = 1` (one factor for all points, the coherence untouched), measured over the grid rather
//!   than at the hub point alone.
//! - Files ([`bts`]): TurbSim's binary full-field format, which OpenFAST's InflowWind reads.
//! - Reading it where a blade element is ([`sample`]): bilinear in space, linear in time, frozen
//!   turbulence carried at the hub's mean speed.

pub mod bts;
pub mod coherence;
pub mod sample;
pub mod spectra;
pub mod synthesis;

pub use synthesis::{generate, steady};

use super::turbulence::Variance;

/// A rectangular grid in the rotor plane centred on the hub: `ny` points across (y, m, positive to
/// the left looking downwind, as TurbSim's), `nz` up, spanning `width` × `height` metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    pub ny: usize,
    pub nz: usize,
    pub width: f64,
    pub height: f64,
}

/// What a full field is generated from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldSpec {
    /// Mean wind at hub height, m/s.
    pub mean_wind: f64,
    /// σ1, the longitudinal standard deviation, m/s.
    pub sigma: f64,
    /// Hub height, m: Λ1 and the shear profile's reference.
    pub hub_height: f64,
    /// Power-law shear exponent α (IEC 61400-1 ed. 3 normal wind profile: 0.2).
    pub shear_exponent: f64,
    pub grid: Grid,
    /// The field repeats after this many seconds.
    pub period: f64,
    /// Largest time step, s: the step is the period over the even sample count that fits.
    pub max_dt: f64,
    pub variance: Variance,
    pub seed: u64,
}

/// The three velocity components of a field.
pub const COMPONENTS: [&str; 3] = ["u", "v", "w"];

/// Velocities on a grid of `ny` × `nz` points at `nt` times, the grid's lateral coordinates centred on
/// zero (y_j = (j − (ny − 1)/2)·dy), its heights z_k = z_bottom + k·dz.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WindField {
    pub ny: usize,
    pub nz: usize,
    pub nt: usize,
    pub dy: f64,
    pub dz: f64,
    pub dt: f64,
    pub z_bottom: f64,
    pub hub_height: f64,
    /// The mean wind at hub height, m/s.
    pub mean_hub: f64,
    /// Whether the series wrap round after nt·dt (TurbSim's ID 8).
    pub periodic: bool,
    /// u, v and w in m/s, mean included, each time-major as TurbSim stores them: index (t·nz + k)·ny + j.
    pub velocity: [Vec<f64>; 3],
    /// A .bts file's tower points below the grid (spaced dz down from z_bottom − dz), u, v and w, index
    /// t·n_tower + i: kept so that a file read and written again loses none; the rotor samples the grid
    /// alone, and a generated field has none.
    pub tower: [Vec<f64>; 3],
}

impl WindField {
    pub fn y(&self, j: usize) -> f64 {
        (j as f64 - 0.5 * (self.ny - 1) as f64) * self.dy
    }

    pub fn z(&self, k: usize) -> f64 {
        self.z_bottom + k as f64 * self.dz
    }

    /// How many tower points each time step carries.
    pub fn n_tower(&self) -> usize {
        self.tower[0].len() / self.nt.max(1)
    }

    /// The index of time step `t`, height `k`, lateral point `j` in [`Self::velocity`]'s vectors.
    pub fn index(&self, t: usize, k: usize, j: usize) -> usize {
        (t * self.nz + k) * self.ny + j
    }

    /// One component's series at grid point (j, k).
    pub fn series(&self, component: usize, j: usize, k: usize) -> impl Iterator<Item = f64> + Clone + '_ {
        (0..self.nt).map(move |t| self.velocity[component][self.index(t, k, j)])
    }

    /// Each grid point's mean and standard deviation of `component` over the field's time, in the
    /// order p = k·ny + j.
    pub fn point_moments(&self, component: usize) -> Vec<(f64, f64)> {
        (0..self.nz)
            .flat_map(|k| (0..self.ny).map(move |j| (j, k)))
            .map(|(j, k)| {
                let mean = self.series(component, j, k).sum::<f64>() / self.nt as f64;
                let variance = self.series(component, j, k).map(|x| (x - mean).powi(2)).sum::<f64>() / self.nt as f64;
                (mean, variance.sqrt())
            })
            .collect()
    }

    /// The duration covered, s: nt·dt (the period of a periodic field).
    pub fn duration(&self) -> f64 {
        self.nt as f64 * self.dt
    }
}

/// A spec that cannot make a field, or a factorisation that failed.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum WindFieldError {
    #[error("{variable} = {value}: {why}")]
    Invalid {
        variable: &'static str,
        value: f64,
        why: &'static str,
    },
    #[error("the u coherence matrix at {frequency_hz} Hz is not positive definite (points too close?)")]
    NotPositiveDefinite { frequency_hz: f64 },
}

#[cfg(test)]
mod tests;
