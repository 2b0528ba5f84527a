//! Each station's BEM solution tabulated once, so a step of the sampled rotor interpolates instead of
//! solving 3 × stations momentum balances (the solve costs ~1.4 µs a station, the budget is
//! 10 µs for the whole rotor).
//!
//! Why two dimensions suffice: a station's residual R(φ) = V_y·sin φ/(1 − a) − V_x·cos φ·(1 − κ') is
//! linear in (V_x, V_y), so its root φ depends only on the direction θ = atan2(V_x, V_y) of the local
//! inflow (and the pitch), and the relative wind W on its magnitude. The loads per unit span, ∝ W², are
//! therefore (V_x² + V_y²)·g(θ, pitch) exactly (no Reynolds number in the polars). g is tabulated on a
//! regular grid of θ over [0, π] (wind from ahead, any blade speed, forward or reverse) and pitch over
//! the controller's range, and read bilinearly. Outside it (wind from behind, a pitch beyond the
//! range) the station is solved as it is: slower, never wrong.

use crate::physics::bem::BemRotor;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// θ spacing, rad (0.5°): the loads follow the angle of attack, which moves one for one with θ.
pub const THETA_STEP: f64 = PI / 360.0;
/// Pitch spacing, rad (1°): the same sensitivity as θ, but a table per degree of pitch doubles nothing
/// the tests could see (the interpolation error, src/physics/blades/tests.rs).
pub const PITCH_STEP: f64 = PI / 180.0;

/// The per-station tables of one rotor.
#[derive(Debug, Clone)]
pub struct LoadTable {
    grid: TableGrid,
    /// (N', T') / (V_x² + V_y²), kg/m² (N/m per (m/s)²): column station·n_pitch + pitch, entry θ; each
    /// column solved when first read (shared by the clones of a model through its `Arc`).
    columns: Vec<OnceLock<Box<[[f64; 2]]>>>,
}

/// A table's grid: all an FMU state keeps of it (the columns are solved again when read).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
struct TableGrid {
    n_theta: usize,
    pitch_lo: f64,
    n_pitch: usize,
    stations: usize,
}

impl PartialEq for LoadTable {
    /// Every column is a function of the grid and the rotor: two tables over the same grid are equal
    /// whichever columns each has solved so far.
    fn eq(&self, other: &Self) -> bool {
        self.grid == other.grid
    }
}

impl Serialize for LoadTable {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.grid.serialize(s)
    }
}

impl<'de> Deserialize<'de> for LoadTable {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        TableGrid::deserialize(d).map(Self::on)
    }
}

/// The pitch columns read this step and the weight of the upper one (None: outside the table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PitchColumns {
    pitch: f64,
    column: Option<(usize, f64)>,
}

impl LoadTable {
    /// Tables of `bem`'s stations for pitch from `pitch_lo` to `pitch_hi`, rad (no column solved yet).
    pub fn new(bem: &BemRotor, pitch_lo: f64, pitch_hi: f64) -> Self {
        let n_theta = (PI / THETA_STEP).round() as usize + 1;
        let n_pitch = ((pitch_hi - pitch_lo) / PITCH_STEP).ceil().max(1.0) as usize + 1;
        let stations = bem.stations.len();
        Self::on(TableGrid {
            n_theta,
            pitch_lo,
            n_pitch,
            stations,
        })
    }

    fn on(grid: TableGrid) -> Self {
        Self {
            columns: (0..grid.stations * grid.n_pitch).map(|_| OnceLock::new()).collect(),
            grid,
        }
    }

    /// Station `i`'s column at pitch index `p`, solved if no step has read it yet.
    #[inline]
    fn column(&self, bem: &BemRotor, i: usize, p: usize) -> &[[f64; 2]] {
        self.columns[i * self.grid.n_pitch + p].get_or_init(|| self.solve_column(bem, i, p))
    }

    #[cold]
    fn solve_column(&self, bem: &BemRotor, i: usize, p: usize) -> Box<[[f64; 2]]> {
        let pitch = self.grid.pitch_lo + p as f64 * PITCH_STEP;
        (0..self.grid.n_theta)
            .map(|k| {
                // unit magnitude: the loads are g(θ, pitch) themselves
                let (vx, vy) = (k as f64 * THETA_STEP).sin_cos();
                let e = bem.element_in(i, vx.max(0.0), vy, pitch);
                [e.normal_n_per_m, e.tangential_n_per_m]
            })
            .collect()
    }

    /// The columns that hold `pitch`, rad: found once a step, read for every element.
    pub fn columns(&self, pitch: f64) -> PitchColumns {
        let x = (pitch - self.grid.pitch_lo) / PITCH_STEP;
        let top = (self.grid.n_pitch - 1) as f64;
        // a hair beyond the last column (rounding of pitch_max) still reads the table
        let column = if x >= 0.0 && x <= top + 1e-9 {
            let p = (x.floor() as usize).min(self.grid.n_pitch - 2);
            Some((p, (x - p as f64).min(1.0)))
        } else {
            None
        };
        PitchColumns { pitch, column }
    }

    /// Normal and tangential load per unit span (N/m) of station `i` in local inflow (`vx`, `vy`), m/s
    /// (see [`BemRotor::element_in`]).
    #[inline]
    pub fn loads(&self, bem: &BemRotor, i: usize, vx: f64, vy: f64, columns: PitchColumns) -> (f64, f64) {
        let Some((p, wp)) = columns.column.filter(|_| vx >= 0.0 && i < self.grid.stations) else {
            let e = bem.element_in(i, vx, vy, columns.pitch);
            return (e.normal_n_per_m, e.tangential_n_per_m);
        };
        let speed2 = vx * vx + vy * vy;
        let x = vx.atan2(vy) / THETA_STEP;
        let k = (x as usize).min(self.grid.n_theta - 2);
        let wk = x - k as f64;
        let (lower, upper) = (self.column(bem, i, p), self.column(bem, i, p + 1));
        let g = |c: usize| {
            let low = lower[k][c] + wk * (lower[k + 1][c] - lower[k][c]);
            let high = upper[k][c] + wk * (upper[k + 1][c] - upper[k][c]);
            low + wp * (high - low)
        };
        (speed2 * g(0), speed2 * g(1))
    }
}
