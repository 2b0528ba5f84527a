//! Fatigue and vibration analysis of recorded series: rainflow counting and matrices, damage-equivalent
//! loads, load duration distributions, ISO 6336 gear stresses with their root geometry, S-N curves with
//! Miner's sum, ISO 281 bearing life, Hertz line contact, operating hours from wind distributions,
//! spectra and Campbell diagrams. Everything reads plain series; nothing here needs an FMU.

pub mod bearing_set;
pub mod bode;
pub mod calibration;
pub mod campbell;
pub mod damage;
pub mod gear;
pub mod gear_set;
/// Hertz contact is physics the gearbox model evaluates too; the analysis reads it from there.
pub use crate::physics::hertz;
pub mod ldd;
pub mod life;
pub mod lifetime;
pub mod limits;
pub mod matrix;
pub mod metrics;
pub mod nelder_mead;
pub mod quantities;
pub mod rainflow;
pub mod series;
pub mod shutdown;
pub mod spectrum;
pub mod tooth_root;
pub mod wind;
