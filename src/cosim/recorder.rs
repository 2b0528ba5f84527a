//! Results as CSV in fmpy's layout: `time,<component>.<variable>,...`, one row per recorded
//! communication point, or as Parquet with the same columns when the file's name ends in `.parquet`
//! ([`super::parquet`]). CSV rows are written as they come, whole (a row never straddles a buffer
//! flush), and the buffer reaches the file at least every quarter second of wall time, on finish and
//! on drop: a run that fails keeps every row up to its last good step, and a run whose process an
//! FMU crashes loses at most the last quarter second. [`CsvWriter`] is the one writer of
//! that layout; every command that writes a CSV goes through it. A recorder can also keep its rows in
//! memory ([`Recorder::new`] with `in_memory`), for an analysis in the same process that needs no file.

use super::master::{MasterError, read_recorded};
use super::parquet::{ParquetWriter, is_parquet};
use super::system::System;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes a CSV in fmpy's layout: a header `time,<name>,...`, then one row of numbers per call,
/// each in its shortest text that reads back to the same bits.
pub struct CsvWriter {
    out: std::io::BufWriter<std::fs::File>,
    line: String,
    flushed: std::time::Instant,
}

/// How long recorded rows may wait in memory: what a crashing process can cost.
const FLUSH_INTERVAL: std::time::Duration = std::time::Duration::from_millis(250);

impl CsvWriter {
    /// Creates the file (and its folder) and writes the header: `time`, then `columns`.
    pub fn create<'a>(path: &Path, columns: impl IntoIterator<Item = &'a str>) -> std::io::Result<Self> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", dir.display())))?;
        }
        let file = std::fs::File::create(path)
            .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
        let mut out = std::io::BufWriter::with_capacity(1 << 16, file);
        let mut header = String::from("time");
        for name in columns {
            header.push(',');
            header.push_str(name);
        }
        writeln!(out, "{header}")?;
        Ok(Self {
            out,
            line: String::new(),
            flushed: std::time::Instant::now(),
        })
    }

    /// Writes one row: the time, then the values in the header's order.
    pub fn row(&mut self, time: f64, values: impl IntoIterator<Item = f64>) -> std::io::Result<()> {
        // ryu: the shortest text that reads back to the same bits (exponent form for very small
        // and large magnitudes), much faster than core::fmt
        let mut buf = ryu::Buffer::new();
        self.line.clear();
        self.line.push_str(buf.format(time));
        for v in values {
            self.line.push(',');
            self.line.push_str(buf.format(v));
        }
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes())?;
        if self.flushed.elapsed() >= FLUSH_INTERVAL {
            self.flush()?;
        }
        Ok(())
    }

    pub fn flush(&mut self) -> std::io::Result<()> {
        self.flushed = std::time::Instant::now();
        self.out.flush()
    }
}

/// Rows a recorder kept in memory: the time and each recorded variable's values, one per row.
#[derive(Debug, Clone, Default)]
pub struct Series {
    pub time: Vec<f64>,
    pub names: Vec<String>,
    pub columns: Vec<Vec<f64>>,
}

/// Where a recorder writes: the file's format follows its name.
enum Sink {
    Csv(CsvWriter),
    /// Boxed: its column buffers and writer are five times the CSV writer's size.
    Parquet(Box<ParquetWriter>),
}

impl Sink {
    fn create<'a>(path: &Path, columns: impl IntoIterator<Item = &'a str>) -> std::io::Result<Self> {
        Ok(if is_parquet(path) {
            Sink::Parquet(Box::new(ParquetWriter::create(path, columns)?))
        } else {
            Sink::Csv(CsvWriter::create(path, columns)?)
        })
    }

    fn row(&mut self, time: f64, values: &[f64]) -> std::io::Result<()> {
        match self {
            Sink::Csv(w) => w.row(time, values.iter().copied()),
            Sink::Parquet(w) => w.row(time, values),
        }
    }

    /// CSV: the rows so far reach the file. Parquet: the file is completed (its footer written), as
    /// this is called only when the run is over.
    fn finish(&mut self) -> std::io::Result<()> {
        match self {
            Sink::Csv(w) => w.flush(),
            Sink::Parquet(w) => w.close(),
        }
    }
}

pub struct Recorder {
    out: Option<(Sink, PathBuf)>,
    /// With [`Recorder::in_memory`]: the time, then each recorded variable, one value per row kept.
    memory: Option<Series>,
    every: u64,
    seen: u64,
    /// Communication points to skip before the next kept one (`seen` counted down, no division a step).
    skip: u64,
    pub rows: u64,
    last_time: f64,
    /// The recorded columns as runs of consecutive values of one unit: (unit, first index, count).
    runs: Vec<(usize, usize, usize)>,
    /// One row of recorded values, gathered run by run.
    row: Vec<f64>,
}

/// The recorded columns `(unit, index)` grouped into runs of consecutive indices of one unit: a row
/// is gathered as a few slice copies instead of a lookup per column.
fn runs(recorded: &[(String, usize, usize)]) -> Vec<(usize, usize, usize)> {
    let mut runs: Vec<(usize, usize, usize)> = Vec::new();
    for &(_, u, i) in recorded {
        match runs.last_mut() {
            Some((ru, start, n)) if *ru == u && *start + *n == i => *n += 1,
            _ => runs.push((u, i, 1)),
        }
    }
    runs
}

impl Recorder {
    /// Creates the file and writes the header. `every` = keep one communication point in `every`
    /// (the last one is always kept by [`Recorder::finish`]).
    pub fn create(path: &Path, system: &System, every: u64) -> std::io::Result<Self> {
        Self::new(Some(path), false, system, every)
    }

    /// As [`Recorder::create`], writing the CSV only when `path` is given, and keeping every row in
    /// memory too when `in_memory` ([`Recorder::take_series`]).
    pub fn new(path: Option<&Path>, in_memory: bool, system: &System, every: u64) -> std::io::Result<Self> {
        let names = || system.recorded.iter().map(|(name, _, _)| name.as_str());
        let out = match path {
            Some(p) => Some((Sink::create(p, names())?, p.to_path_buf())),
            None => None,
        };
        let memory = in_memory.then(|| Series {
            time: Vec::new(),
            names: names().map(str::to_string).collect(),
            columns: vec![Vec::new(); system.recorded.len()],
        });
        Ok(Self {
            out,
            memory,
            every: every.max(1),
            seen: 0,
            skip: 0,
            rows: 0,
            last_time: f64::NAN,
            runs: runs(&system.recorded),
            row: Vec::with_capacity(system.recorded.len()),
        })
    }

    /// Time of the last row written (NaN before any).
    pub fn last_time(&self) -> f64 {
        self.last_time
    }

    /// The file written, if any.
    pub fn path(&self) -> Option<&Path> {
        self.out.as_ref().map(|(_, p)| p.as_path())
    }

    /// The rows kept in memory ([`Recorder::new`] with `in_memory`), leaving none behind.
    pub fn take_series(&mut self) -> Option<Series> {
        self.memory.take()
    }

    /// Offers one communication point; reads the recorder-only variables and writes the row if
    /// decimation keeps it.
    pub fn observe(&mut self, time: f64, system: &mut System) -> Result<(), MasterError> {
        let keep = self.skip == 0;
        self.skip = if keep { self.every - 1 } else { self.skip - 1 };
        self.seen += 1;
        if keep {
            read_recorded(system, time)?;
            self.write(time, system)?;
        }
        system.record_next = self.skip == 0;
        Ok(())
    }

    fn write(&mut self, time: f64, system: &System) -> std::io::Result<()> {
        if let (None, Some((Sink::Parquet(w), _))) = (&self.memory, &mut self.out) {
            // the runs straight into the writer's buffer
            let parts = self
                .runs
                .iter()
                .map(|&(u, start, n)| &system.units[u].values[start..start + n]);
            w.row_of_parts(time, parts)?;
            self.rows += 1;
            self.last_time = time;
            return Ok(());
        }
        self.row.clear();
        for &(u, start, n) in &self.runs {
            self.row.extend_from_slice(&system.units[u].values[start..start + n]);
        }
        if let Some(m) = &mut self.memory {
            m.time.push(time);
            m.columns.iter_mut().zip(&self.row).for_each(|(c, &v)| c.push(v));
        }
        if let Some((out, _)) = &mut self.out {
            out.row(time, &self.row)?;
        }
        self.rows += 1;
        self.last_time = time;
        Ok(())
    }

    /// After a complete run: writes the final point if decimation skipped it, and flushes.
    pub fn finish(&mut self, time: f64, system: &mut System) -> Result<(), MasterError> {
        if self.seen > 0 && self.last_time != time {
            read_recorded(system, time)?;
            self.write(time, system)?;
        }
        Ok(self.flush()?)
    }

    /// After a failed run: flushes the rows written so far (and completes a Parquet file). The units
    /// may hold values from the failed step, so no final row is added.
    pub fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.out {
            Some((out, _)) => out.finish(),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::runs;

    #[test]
    fn recorded_columns_become_runs_of_consecutive_values() {
        let col = |u: usize, i: usize| (format!("u{u}.v{i}"), u, i);
        let recorded = [
            col(0, 2),
            col(0, 3),
            col(0, 4),
            col(1, 0),
            col(1, 2),
            col(1, 3),
            col(0, 5),
            col(0, 5),
        ];
        assert_eq!(runs(&recorded), [(0, 2, 3), (1, 0, 1), (1, 2, 2), (0, 5, 1), (0, 5, 1)]);
        assert!(runs(&[]).is_empty());
    }
}
