//! Damage-equivalent load: the constant-amplitude range that, repeated N_eq = f_eq · T times, does the
//! damage of the counted cycles under a Wöhler curve of slope m (Palmgren–Miner):
//! DEL = (Σ n_i S_i^m / N_eq)^(1/m).

use super::rainflow::Cycle;

pub fn damage_equivalent_load(cycles: &[Cycle], m: f64, equivalent_cycles: f64) -> f64 {
    let sum: f64 = cycles.iter().map(|c| c.count * c.range.powf(m)).sum();
    (sum / equivalent_cycles).powf(1.0 / m)
}
