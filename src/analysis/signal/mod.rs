//! Signals: series read from CSV or Parquet, amplitude spectra, error metrics against a reference, and a scene's
//! quantities of interest.

pub mod metrics;
#[cfg(feature = "cli")]
pub mod parquet;
pub mod quantities;
pub mod rows;
pub mod series;
pub mod spectrum;
