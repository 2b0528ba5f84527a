//! Fatigue and vibration analysis of recorded series. So far: rainflow cycle counting,
//! damage-equivalent loads, S-N curves with Miner's sum, ISO 281 bearing life, Hertz line contact and
//! operating hours from wind distributions (issue 4 has the rest: LDD, ISO 6336 stresses, spectra,
//! Campbell).

pub mod campbell;
pub mod damage;
pub mod gear;
pub mod hertz;
pub mod ldd;
pub mod life;
pub mod limits;
pub mod matrix;
pub mod rainflow;
pub mod series;
pub mod spectrum;
pub mod wind;
