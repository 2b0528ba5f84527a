//! Reading a time series from a CSV file in fmpy's layout: a header `time,<name>,...`, then numbers,
//! or from a Parquet file with the same columns (`windrive run --out FILE.parquet`; [`super::parquet`]).
//! CSV files are read line by line, so a channel of a recording larger than memory can be streamed
//! through a counter ([`stream_channel`]) without holding the file or the series.

use super::rows::CheckedRows;
pub use super::rows::{Extent, SeriesError};
use std::io::BufRead;
use std::path::Path;

/// Hands every (time, value) of one column to `sample`, in file order, reading one line at a time.
/// Rejects NaN/inf, non-numeric or missing cells and time that does not increase, naming the row;
/// an unknown column names the columns there are; a file without data rows is an error.
pub fn stream_channel(path: &Path, channel: &str, mut sample: impl FnMut(f64, f64)) -> Result<Extent, SeriesError> {
    stream_channels(path, &[channel], |t, x| sample(t, x[0]))
}

/// As [`stream_channel`] for several columns in one pass: `sample` gets the time and the row's values
/// in the order of `channels`.
pub fn stream_channels(
    path: &Path,
    channels: &[&str],
    mut sample: impl FnMut(f64, &[f64]),
) -> Result<Extent, SeriesError> {
    #[cfg(feature = "cli")]
    if super::parquet::is_parquet(path) {
        return super::parquet::stream_channels(path, channels, sample);
    }
    let p = path.display().to_string();
    let read_error = |e: std::io::Error| SeriesError::Read {
        path: p.clone(),
        message: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(read_error)?;
    let mut reader = std::io::BufReader::with_capacity(1 << 16, file);
    let mut line = String::new();
    reader.read_line(&mut line).map_err(read_error)?;
    let header: Vec<String> = line
        .trim_end_matches(['\r', '\n'])
        .split(',')
        .map(|h| h.trim().trim_matches('"').to_string())
        .collect();
    // column of each slot: the time first, then the channels
    let mut columns = vec![header.iter().position(|h| h == "time").unwrap_or(0)];
    for channel in channels {
        columns.push(
            header
                .iter()
                .position(|h| h == channel)
                .ok_or_else(|| SeriesError::UnknownChannel {
                    path: p.clone(),
                    channel: channel.to_string(),
                    available: header.join(", "),
                })?,
        );
    }
    let last_needed = columns.iter().copied().max().unwrap_or(0);
    let names: Vec<&str> = columns.iter().map(|&c| header[c].as_str()).collect();
    let mut rows = CheckedRows::new(p.clone(), &names);
    // byte span of each slot's cell in the current line (empty when the row is short) and its value
    let mut spans = vec![(0usize, 0usize); columns.len()];
    let mut values = vec![0.0; columns.len()];
    let mut row = 1;
    loop {
        line.clear();
        if reader.read_line(&mut line).map_err(read_error)? == 0 {
            break;
        }
        row += 1;
        if line.trim().is_empty() {
            continue;
        }
        spans.fill((0, 0));
        let mut start = 0;
        for (c, cell) in line.split(',').take(last_needed + 1).enumerate() {
            for (span, _) in spans.iter_mut().zip(&columns).filter(|(_, col)| **col == c) {
                *span = (start, start + cell.len());
            }
            start += cell.len() + 1;
        }
        for ((value, &(from, to)), &c) in values.iter_mut().zip(&spans).zip(&columns) {
            let cell = line[from..to].trim();
            *value = cell.parse().map_err(|_| SeriesError::Value {
                path: p.clone(),
                row,
                message: format!("{:?} is not a number in column {}", cell, header[c]),
            })?;
        }
        rows.accept(row, &values, &mut sample)?;
    }
    rows.finish()
}

/// Time and several channels of a CSV file read in one pass, with the checks of [`stream_channel`].
pub fn read_channels(path: &Path, channels: &[&str]) -> Result<(Vec<f64>, Vec<Vec<f64>>), SeriesError> {
    let (mut t, mut x) = (Vec::new(), vec![Vec::new(); channels.len()]);
    stream_channels(path, channels, |ti, row| {
        t.push(ti);
        x.iter_mut().zip(row).for_each(|(column, v)| column.push(*v));
    })?;
    Ok((t, x))
}

/// Time and several channels of a CSV file from `transient` seconds on, read in one pass; at least two
/// samples and some time must remain.
pub fn read_after(path: &Path, channels: &[&str], transient: f64) -> Result<(Vec<f64>, Vec<Vec<f64>>), SeriesError> {
    let (mut t, mut columns) = read_channels(path, channels)?;
    let first = t.partition_point(|&ti| ti < transient);
    let seconds = t
        .last()
        .map_or(0.0, |last| last - t.get(first).copied().unwrap_or(*last));
    if t.len() < first + 2 || seconds <= 0.0 {
        return Err(SeriesError::TooShort {
            path: path.display().to_string(),
            seconds,
            transient,
        });
    }
    t.drain(..first);
    columns.iter_mut().for_each(|c| {
        c.drain(..first);
    });
    Ok((t, columns))
}

/// Time and one channel of a CSV file, with the checks of [`stream_channel`].
pub fn read_channel(path: &Path, channel: &str) -> Result<(Vec<f64>, Vec<f64>), SeriesError> {
    let (t, mut x) = read_channels(path, &[channel])?;
    Ok((t, x.pop().unwrap_or_default()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(name: &str, text: &str) -> std::path::PathBuf {
        let path = std::env::temp_dir().join(format!("windrive-series-{}-{name}.csv", std::process::id()));
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn streams_one_column_with_its_extent() {
        let path = file("ok", "\"time\",a,b\r\n0,1,2\r\n\r\n0.5,3,4\n1.5,5,6");
        let mut seen = Vec::new();
        let extent = stream_channel(&path, "b", |t, x| seen.push((t, x))).unwrap();
        assert_eq!(seen, vec![(0.0, 2.0), (0.5, 4.0), (1.5, 6.0)]);
        assert_eq!(extent.samples, 3);
        assert_eq!(extent.duration(), 1.5);
        assert_eq!(read_channel(&path, "a").unwrap().1, vec![1.0, 3.0, 5.0]);
        let (t, x) = read_channels(&path, &["b", "time", "a"]).unwrap();
        assert_eq!(t, vec![0.0, 0.5, 1.5]);
        assert_eq!(x, vec![vec![2.0, 4.0, 6.0], vec![0.0, 0.5, 1.5], vec![1.0, 3.0, 5.0]]);
    }

    #[test]
    fn bad_files_name_the_row_or_column() {
        let cases = [
            ("nan", "time,a\n0,1\n1,nan\n", "row 3: a is NaN"),
            ("text", "time,a\n0,x\n", "row 2: \"x\" is not a number in column a"),
            ("short", "time,a,b\n0,1\n", "row 2: \"\" is not a number in column b"),
            ("back", "time,a\n0,1\n1,1\n1,2\n", "row 4: time 1 does not increase"),
            ("empty", "time,a\n", "the series is empty"),
        ];
        for (name, text, message) in cases {
            let column = if name == "short" { "b" } else { "a" };
            let err = read_channel(&file(name, text), column).unwrap_err().to_string();
            assert!(err.contains(message), "{name}: {err}");
        }
        let err = read_channel(&file("unknown", "time,a\n0,1\n"), "z")
            .unwrap_err()
            .to_string();
        assert!(err.contains("no column \"z\"; columns: time, a"), "{err}");
        let err = read_channel(Path::new("/nonexistent/x.csv"), "a")
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("/nonexistent/x.csv: "), "{err}");
    }
}
