//! Results as CSV in fmpy's layout: `time,<component>.<variable>,...`, one row per recorded
//! communication point. Rows are written as they come (buffered, flushed on finish and on drop),
//! so a run that fails keeps every row up to its last good step.

use super::master::{MasterError, read_recorded};
use super::system::System;
use std::io::Write;
use std::path::{Path, PathBuf};

pub struct Recorder {
    out: std::io::BufWriter<std::fs::File>,
    path: PathBuf,
    every: u64,
    seen: u64,
    pub rows: u64,
    last_time: f64,
    line: String,
}

impl Recorder {
    /// Creates the file and writes the header. `every` = keep one communication point in `every`
    /// (the last one is always kept by [`Recorder::finish`]).
    pub fn create(path: &Path, system: &System, every: u64) -> std::io::Result<Self> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        let file = std::fs::File::create(path)
            .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
        let mut out = std::io::BufWriter::with_capacity(1 << 16, file);
        let mut header = String::from("time");
        for (name, _, _) in &system.recorded {
            header.push(',');
            header.push_str(name);
        }
        writeln!(out, "{header}")?;
        Ok(Self {
            out,
            path: path.to_path_buf(),
            every: every.max(1),
            seen: 0,
            rows: 0,
            last_time: f64::NAN,
            line: String::new(),
        })
    }

    /// Time of the last row written (NaN before any).
    pub fn last_time(&self) -> f64 {
        self.last_time
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Offers one communication point; reads the recorder-only variables and writes the row if
    /// decimation keeps it.
    pub fn observe(&mut self, time: f64, system: &mut System) -> Result<(), MasterError> {
        let keep = self.seen.is_multiple_of(self.every);
        self.seen += 1;
        if keep {
            read_recorded(system, time)?;
            self.write(time, system)?;
        }
        Ok(())
    }

    fn write(&mut self, time: f64, system: &System) -> std::io::Result<()> {
        // ryu: the shortest text that reads back to the same bits (exponent form for very small
        // and large magnitudes), much faster than core::fmt
        let mut buf = ryu::Buffer::new();
        self.line.clear();
        self.line.push_str(buf.format(time));
        for (_, u, i) in &system.recorded {
            self.line.push(',');
            self.line.push_str(buf.format(system.units[*u].values[*i]));
        }
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes())?;
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
        Ok(self.out.flush()?)
    }

    /// After a failed run: flushes the rows written so far. The units may hold values from the
    /// failed step, so no final row is added.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}
