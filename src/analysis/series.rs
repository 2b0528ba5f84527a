//! Reading a time series from a CSV file in fmpy's layout: a header `time,<name>,...`, then numbers.

use std::path::Path;

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
}

/// Time and one channel of a CSV file. Rejects NaN/inf, non-numeric cells and time that does not
/// increase, naming the row.
pub fn read_channel(path: &Path, channel: &str) -> Result<(Vec<f64>, Vec<f64>), SeriesError> {
    let p = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SeriesError::Read {
        path: p.clone(),
        message: e.to_string(),
    })?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(|h| h.trim().trim_matches('"'))
        .collect();
    let column = header
        .iter()
        .position(|h| *h == channel)
        .ok_or_else(|| SeriesError::UnknownChannel {
            path: p.clone(),
            channel: channel.into(),
            available: header.join(", "),
        })?;
    let time_column = header.iter().position(|h| *h == "time").unwrap_or(0);
    let (mut t, mut x) = (Vec::new(), Vec::new());
    for (i, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let row = i + 2;
        let cells: Vec<&str> = line.split(',').collect();
        let number = |c: usize| -> Result<f64, SeriesError> {
            let cell = cells.get(c).map(|s| s.trim()).unwrap_or("");
            let v: f64 = cell.parse().map_err(|_| SeriesError::Value {
                path: p.clone(),
                row,
                message: format!("{:?} is not a number in column {}", cell, header[c]),
            })?;
            if !v.is_finite() {
                return Err(SeriesError::Value {
                    path: p.clone(),
                    row,
                    message: format!("{} is {v}", header[c]),
                });
            }
            Ok(v)
        };
        let (ti, xi) = (number(time_column)?, number(column)?);
        if let Some(&prev) = t.last()
            && ti <= prev
        {
            return Err(SeriesError::Value {
                path: p.clone(),
                row,
                message: format!("time {ti} does not increase (previous {prev})"),
            });
        }
        t.push(ti);
        x.push(xi);
    }
    if x.is_empty() {
        return Err(SeriesError::Empty { path: p });
    }
    Ok((t, x))
}
