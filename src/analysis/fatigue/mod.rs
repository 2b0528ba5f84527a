//! Fatigue: rainflow counting (ASTM E1049) and its matrices, damage-equivalent loads, load duration
//! distributions, S-N curves with Palmgren–Miner and ISO 281 basic life, operating hours from a wind
//! climate, and a component's lifetime from a normal-operation and a shutdown series.

pub mod campaign;
pub mod damage;
pub mod ldd;
pub mod lifetime;
pub mod matrix;
pub mod operating_hours;
pub mod rainflow;
pub mod sn_curve;
