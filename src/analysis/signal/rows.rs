//! What a series is made of, whatever its file format: the errors of reading one, the extent of what
//! was read, and the checks every row passes (finite values, increasing time). The CSV reader
//! ([`super::series`]) and the Parquet reader ([`super::parquet`]) share them.

#[derive(Debug, thiserror::Error)]
pub enum SeriesError {
    #[error("{path}: {message}")]
    Read { path: String, message: String },
    #[error("{path}: no column {channel:?}; columns: {available}")]
    UnknownChannel {
        path: String,
        channel: String,
        available: String,
    },
    #[error("{path}: row {row}: {message}")]
    Value { path: String, row: usize, message: String },
    #[error("{path}: the series is empty")]
    Empty { path: String },
    #[error("{path}: {seconds} s after the transient of {transient} s; nothing to rate")]
    TooShort { path: String, seconds: f64, transient: f64 },
}

/// What a streamed channel covered: sample count and first and last time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    pub samples: usize,
    pub first_time: f64,
    pub last_time: f64,
}

impl Extent {
    /// Last time − first time (0 for a single sample).
    pub fn duration(&self) -> f64 {
        self.last_time - self.first_time
    }
}

/// The checks every row of a series passes, whatever its file format: finite values, increasing
/// time; and the extent of the rows accepted.
pub(crate) struct CheckedRows<'a> {
    path: String,
    /// The time's column name, then the channels'.
    names: &'a [&'a str],
    extent: Extent,
}

impl<'a> CheckedRows<'a> {
    pub(crate) fn new(path: String, names: &'a [&'a str]) -> Self {
        Self {
            path,
            names,
            extent: Extent {
                samples: 0,
                first_time: f64::NAN,
                last_time: f64::NAN,
            },
        }
    }

    /// Checks row `row` (numbered as the file shows it) of `values` (the time, then the channels) and
    /// hands it to `sample`.
    pub(crate) fn accept(
        &mut self,
        row: usize,
        values: &[f64],
        sample: &mut impl FnMut(f64, &[f64]),
    ) -> Result<(), SeriesError> {
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(SeriesError::Value {
                path: self.path.clone(),
                row,
                message: format!("{} is {}", self.names[i], values[i]),
            });
        }
        let t = values[0];
        let extent = &mut self.extent;
        if extent.samples > 0 && t <= extent.last_time {
            return Err(SeriesError::Value {
                path: self.path.clone(),
                row,
                message: format!("time {t} does not increase (previous {})", extent.last_time),
            });
        }
        if extent.samples == 0 {
            extent.first_time = t;
        }
        extent.last_time = t;
        extent.samples += 1;
        sample(t, &values[1..]);
        Ok(())
    }

    /// The extent of the rows accepted; none is an error.
    pub(crate) fn finish(self) -> Result<Extent, SeriesError> {
        if self.extent.samples == 0 {
            return Err(SeriesError::Empty { path: self.path });
        }
        Ok(self.extent)
    }
}
