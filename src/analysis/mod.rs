//! Analysis of recorded series, by kind: [`signal`] (reading series, spectra, error metrics, a scene's
//! quantities of interest), [`fatigue`] (rainflow counting and matrices, damage-equivalent loads, load
//! duration distributions, S-N curves with Miner's sum, operating hours, lifetime assembly) and
//! [`rating`] (ISO 6336 gear and ISO 281 bearing ratings of a gearbox with their limits), plus the
//! shutdown summary a drivetrain engineer reads after a run, and [`case`]: everything a load-case
//! campaign asks of one case's series, in one pass. Everything reads plain series; nothing
//! here needs an FMU. Linear (modal and frequency-domain) analysis of the models is in
//! [`crate::linear`].

pub mod case;
pub mod fatigue;
pub mod rating;
pub mod shutdown;
pub mod signal;
