//! Fatigue and vibration analysis of recorded series. So far: rainflow cycle counting and
//! damage-equivalent loads (issue 4 has the rest: LDD, S-N/Miner, ISO 6336, Hertz, ISO 281, spectra).

pub mod damage;
pub mod rainflow;
pub mod series;
