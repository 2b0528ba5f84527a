//! Signals: series read from CSV, amplitude spectra, error metrics against a reference, and a scene's
//! quantities of interest.

pub mod metrics;
pub mod quantities;
pub mod series;
pub mod spectrum;
