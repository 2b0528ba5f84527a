//! Results as Parquet: the same columns as the CSV (`time`, then `<component>.<variable>`), each a
//! required DOUBLE column (Float64 to pandas, polars and pyarrow, which read the file as it is),
//! Snappy-compressed. Numbers are stored as their bits, so nothing is spent on float text and nothing
//! is lost to it.
//!
//! Written through the parquet crate's column writers, not its Arrow layer: a row group is a column
//! of f64 after another, which is all a results file is, and the Arrow layer with the arrow-* crates
//! it pulls in was the longest compilation of the build (parquet's `arrow` feature: 250 s of CPU of a
//! 470 s release build on 2 cores, measured 2026-11-29 with `cargo build --timings`).
//!
//! Rows are kept as they come, one after the other in a small buffer (a row costs one copy, not a push
//! per column), and every [`CHUNK_ROWS`] rows the buffer goes to a writer thread, which transposes it
//! and encodes and compresses it into the open row group's columns (each chunk a page of every column)
//! while the simulation fills the next; the buffers go back and forth and are filled again. Every
//! [`ROW_GROUP_ROWS`] rows the thread closes the group and appends its columns to the file. The
//! thread moves the writer's work off the simulation's path, it does not remove it (a campaign running
//! a case per core pays it all the same), and closing the file waits for one chunk, not a group.
//! Parquet places its index (the footer) at the end of the file: the file is complete once the run
//! ends, fails or is stopped and the recorder is finished, flushed or dropped.
//! A process killed outright (SIGKILL, a crashing FMU without `--isolate`) leaves a file no reader
//! opens; CSV keeps the rows up to its last quarter-second flush there.

use parquet::basic::{Compression, Repetition, Type as PhysicalType};
use parquet::column::writer::{ColumnWriterImpl, get_column_writer, get_typed_column_writer};
use parquet::data_type::DoubleType;
use parquet::file::properties::{EnabledStatistics, WriterProperties, WriterPropertiesPtr};
use parquet::file::writer::{SerializedFileWriter, SerializedPageWriter, TrackedWrite};
use parquet::schema::types::{ColumnDescPtr, ColumnPath, Type};
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender};

/// Rows per row group: a reader that needs a time range skips whole groups (its time column has page
/// statistics besides).
pub const ROW_GROUP_ROWS: usize = 1 << 13;

/// Rows per hand-over to the writer thread and per page. Measured on c-shutdown-spring, every output
/// at every step (2026-12-01, docs/PERFORMANCE.md): handing the thread a whole group at once, the
/// simulation filled 4.4 MB of fresh pages per group and completing the file waited for the last
/// group's encoding; in chunks the full recording's wall time fell from 1.98 to 1.79 times the
/// simulation's (medians of 21 paired runs), for 9 % more instructions in the writer thread (eight
/// pages a column chunk instead of one) and a file 0.7 % larger.
pub const CHUNK_ROWS: usize = 1 << 10;

/// The file's write buffer: a row group's columns are appended through it.
const WRITE_BUFFER_BYTES: usize = 1 << 20;

/// Chunks handed over and not yet written: the simulation runs at most this far ahead of the file.
const CHUNKS_AHEAD: usize = 4;

/// Writes a Parquet file with a `time` column and one DOUBLE column per name.
pub struct ParquetWriter {
    /// The rows not yet handed to the writer thread, row after row: the time, then each named
    /// column's value.
    rows: Vec<f64>,
    /// Full buffers to the writer thread (an empty one: the last chunk was sent, finish the file);
    /// None once closed.
    to_thread: Option<std::sync::mpsc::SyncSender<Vec<f64>>>,
    /// Written buffers back from the thread, to be filled again.
    from_thread: std::sync::mpsc::Receiver<Vec<f64>>,
    /// The writer thread; its result is the file's (the first error, or the file complete).
    thread: Option<std::thread::JoinHandle<std::io::Result<()>>>,
    /// Values per row: the time and the named columns.
    width: usize,
    path: String,
}

fn io_error(path: &str, e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(format!("{path}: {e}"))
}

impl ParquetWriter {
    /// Creates the file (and its folder) for `time`, then `columns`.
    pub fn create<'a>(path: &Path, columns: impl IntoIterator<Item = &'a str>) -> std::io::Result<Self> {
        let shown = path.display().to_string();
        let double = |name: &str| {
            Type::primitive_type_builder(name, PhysicalType::DOUBLE)
                .with_repetition(Repetition::REQUIRED)
                .build()
                .map(Arc::new)
                .map_err(|e| io_error(&shown, e))
        };
        let mut fields = vec![double("time")?];
        for name in columns {
            if name == "time" {
                return Err(io_error(
                    &shown,
                    "a recorded variable is named \"time\", the time column's name",
                ));
            }
            fields.push(double(name)?);
        }
        let width = fields.len();
        let schema = Type::group_type_builder("schema")
            .with_fields(fields)
            .build()
            .map_err(|e| io_error(&shown, e))?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", dir.display())))?;
        }
        let file = std::fs::File::create(path).map_err(|e| std::io::Error::new(e.kind(), format!("{shown}: {e}")))?;
        // Dictionary encoding finds nothing to share in simulated floats and costs a hash per value.
        // Min/max statistics only for the time column, where they let a reader skip pages and row
        // groups outside a time range; a channel's cost a comparison pair per value (a quarter of the
        // writer's work, callgrind) for a filter no analysis asks. A page per chunk: each is compressed
        // as it comes instead of all of a group's when it closes.
        let properties = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_dictionary_enabled(false)
            .set_statistics_enabled(EnabledStatistics::None)
            .set_column_statistics_enabled(ColumnPath::from("time"), EnabledStatistics::Page)
            .set_write_batch_size(CHUNK_ROWS)
            .set_data_page_row_count_limit(CHUNK_ROWS)
            .build();
        // A row group's column chunks reach the file through this buffer, copied in pieces of its size:
        // 8 kB (the default) made the 11 MB file of the 30 s bench scene 1 490 write(2) calls, and
        // completing the file (the last group, the footer) waited 1.6-2.0 ms; with 1 MB, 11 calls and
        // 1.45-1.55 ms (six runs each, a timer around `close`, 2026-12-04).
        let buffered = BufWriter::with_capacity(WRITE_BUFFER_BYTES, file);
        let writer = SerializedFileWriter::new(buffered, Arc::new(schema), Arc::new(properties))
            .map_err(|e| io_error(&shown, e))?;
        let (to_thread, chunks) = std::sync::mpsc::sync_channel::<Vec<f64>>(CHUNKS_AHEAD);
        let (give_back, from_thread) = std::sync::mpsc::channel();
        let file = GroupWriter {
            descriptors: writer.schema_descr().columns().to_vec(),
            properties: Arc::clone(writer.properties()),
            writer,
            columns: vec![Vec::new(); width],
            path: shown.clone(),
        };
        let thread = std::thread::Builder::new()
            .name("parquet-writer".into())
            .spawn(move || file.run(chunks, give_back))
            .map_err(|e| io_error(&shown, e))?;
        Ok(Self {
            rows: Vec::new(),
            to_thread: Some(to_thread),
            from_thread,
            thread: Some(thread),
            width,
            path: shown,
        })
    }

    /// Adds one row: the time, then the values in the columns' order.
    pub fn row(&mut self, time: f64, values: &[f64]) -> std::io::Result<()> {
        self.row_of_parts(time, std::iter::once(values))
    }

    /// Adds one row: the time, then the values of `parts` one after the other in the columns' order
    /// (a recorder's row gathered straight into the buffer, without a copy of its own). A row of the
    /// wrong width is refused and left out.
    pub fn row_of_parts<'a>(&mut self, time: f64, parts: impl IntoIterator<Item = &'a [f64]>) -> std::io::Result<()> {
        if self.rows.capacity() == 0 {
            // the whole chunk at once: growing it would copy every row kept so far, repeatedly;
            // a buffer the writer thread has written comes back with its capacity
            self.rows = self
                .from_thread
                .try_recv()
                .unwrap_or_else(|_| Vec::with_capacity(CHUNK_ROWS * self.width));
        }
        let start = self.rows.len();
        self.rows.push(time);
        for part in parts {
            self.rows.extend_from_slice(part);
        }
        let width = self.rows.len() - start;
        if width != self.width {
            self.rows.truncate(start);
            return Err(io_error(
                &self.path,
                format!("a row of {} values for {} columns", width - 1, self.width - 1),
            ));
        }
        if self.rows.len() >= CHUNK_ROWS * self.width {
            self.send_buffered()?;
        }
        Ok(())
    }

    /// Hands the buffered rows to the writer thread; a thread that stopped on an error answers with it.
    fn send_buffered(&mut self) -> std::io::Result<()> {
        let Some(to_thread) = &self.to_thread else {
            return Err(io_error(&self.path, "written after it was closed"));
        };
        if self.rows.is_empty() {
            return Ok(());
        }
        let rows = std::mem::take(&mut self.rows);
        if to_thread.send(rows).is_err() {
            // the thread returned early: its error is the answer
            return self.close();
        }
        Ok(())
    }

    /// Writes the buffered rows and the footer and waits for the writer thread: the file is
    /// complete. Closing twice does nothing.
    pub fn close(&mut self) -> std::io::Result<()> {
        let Some(to_thread) = self.to_thread.take() else {
            return Ok(());
        };
        let rows = std::mem::take(&mut self.rows);
        // a thread that stopped early cannot take them; its error is reported below
        if !rows.is_empty() {
            let _ = to_thread.send(rows);
        }
        let _ = to_thread.send(Vec::new());
        drop(to_thread);
        match self.thread.take().map(std::thread::JoinHandle::join) {
            Some(Ok(result)) => result,
            Some(Err(_)) => Err(io_error(&self.path, "the Parquet writer thread panicked")),
            None => Ok(()),
        }
    }
}

impl Drop for ParquetWriter {
    /// A recorder dropped on an error path still leaves a readable file with every row it was given.
    fn drop(&mut self) {
        let _ = self.close();
    }
}

/// The writer thread's side: the file, what a column writer is made of, and the columns a chunk is
/// transposed into.
struct GroupWriter {
    writer: SerializedFileWriter<BufWriter<std::fs::File>>,
    descriptors: Vec<ColumnDescPtr>,
    properties: WriterPropertiesPtr,
    /// A chunk's rows as columns, reused chunk after chunk.
    columns: Vec<Vec<f64>>,
    path: String,
}

impl GroupWriter {
    /// Writes the chunks as they come, [`ROW_GROUP_ROWS`] rows a group, until an empty chunk or a
    /// closed channel ends the file; each chunk's buffer goes back, emptied.
    fn run(mut self, chunks: Receiver<Vec<f64>>, give_back: Sender<Vec<f64>>) -> std::io::Result<()> {
        let path = self.path.clone();
        let fail = |e: parquet::errors::ParquetError| io_error(&path, e);
        let mut ended = false;
        while !ended {
            // the open group's columns, encoded into memory (room for a group's values uncompressed:
            // no reallocation as the pages come) and appended to the file when the group closes
            let mut sinks: Vec<TrackedWrite<Vec<u8>>> = self
                .descriptors
                .iter()
                .map(|_| TrackedWrite::new(Vec::with_capacity(ROW_GROUP_ROWS * size_of::<f64>() + 4096)))
                .collect();
            let mut columns: Vec<ColumnWriterImpl<'_, DoubleType>> = self
                .descriptors
                .iter()
                .zip(sinks.iter_mut())
                .map(|(d, sink)| {
                    let pages = Box::new(SerializedPageWriter::new(sink));
                    get_typed_column_writer(get_column_writer(Arc::clone(d), Arc::clone(&self.properties), pages))
                })
                .collect();
            let mut rows = 0;
            while rows < ROW_GROUP_ROWS {
                let mut chunk = match chunks.recv() {
                    Ok(chunk) if !chunk.is_empty() => chunk,
                    _ => {
                        ended = true;
                        break;
                    }
                };
                transpose(&chunk, &mut self.columns);
                for (column, values) in columns.iter_mut().zip(&self.columns) {
                    column.write_batch(values, None, None).map_err(fail)?;
                }
                rows += chunk.len() / self.columns.len();
                chunk.clear();
                // the simulation may have finished meanwhile: nobody to give it back to
                let _ = give_back.send(chunk);
            }
            let closed = columns
                .into_iter()
                .map(ColumnWriterImpl::close)
                .collect::<Result<Vec<_>, _>>()
                .map_err(fail)?;
            if rows == 0 {
                continue;
            }
            let mut group = self.writer.next_row_group().map_err(fail)?;
            for (sink, close) in sinks.into_iter().zip(closed) {
                let bytes = bytes::Bytes::from(sink.into_inner().map_err(fail)?);
                group.append_column(&bytes, close).map_err(fail)?;
            }
            group.close().map_err(fail)?;
        }
        let mut file = self.writer.into_inner().map_err(fail)?;
        file.flush().map_err(|e| io_error(&path, e))
    }
}

/// Rows of `columns.len()` values, one after the other, into those columns (cleared first). By
/// blocks of rows that stay in the cache while every column takes its share: a column at a time
/// over the whole buffer would read it from memory once per column.
fn transpose(rows: &[f64], columns: &mut [Vec<f64>]) {
    const BLOCK_ROWS: usize = 64;
    let width = columns.len();
    if width == 0 {
        return;
    }
    let n = rows.len() / width;
    for column in columns.iter_mut() {
        column.clear();
        column.resize(n, 0.0);
    }
    // each value copied by index: a stepping iterator cost as much as the column's Snappy compression
    // (perf, the writer thread, 2026-12-01)
    for (b, block) in rows[..n * width].chunks(BLOCK_ROWS * width).enumerate() {
        let start = b * BLOCK_ROWS;
        for (j, column) in columns.iter_mut().enumerate() {
            let out = &mut column[start..start + block.len() / width];
            for (value, row) in out.iter_mut().zip(block.chunks_exact(width)) {
                *value = row[j];
            }
        }
    }
}

/// Whether `path` names a Parquet file (by its extension).
pub fn is_parquet(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

#[cfg(test)]
mod tests {
    use super::{CHUNK_ROWS, ParquetWriter, ROW_GROUP_ROWS, transpose};
    use crate::analysis::signal::series::read_channels;

    /// Rows across several chunks and groups handed to the writer thread, the last ones partial, come
    /// back in order to the bit, in whole groups but the last, whether the file is closed or only
    /// dropped; a wrong row is refused at once.
    #[test]
    fn every_row_reaches_the_file_through_the_writer_thread() {
        let dir = std::env::temp_dir().join(format!("windrive-parquet-{}", std::process::id()));
        let value = |i: usize, j: usize| (i as f64).sin() * 1e3 + j as f64;
        for (rows, close) in [
            (2 * ROW_GROUP_ROWS + 17, true),
            (ROW_GROUP_ROWS + 1, false),
            (ROW_GROUP_ROWS, true),
            (CHUNK_ROWS + 1, true),
            (CHUNK_ROWS, false),
            (3, false),
            (0, true),
        ] {
            let path = dir.join(format!("{rows}-{close}.parquet"));
            let mut w = ParquetWriter::create(&path, ["a", "b"]).unwrap();
            for i in 0..rows {
                let (t, a, b) = (i as f64 * 1e-3, value(i, 0), value(i, 1));
                // every other row gathered from parts, as a recorder hands them over
                if i % 2 == 0 {
                    w.row(t, &[a, b]).unwrap();
                } else {
                    w.row_of_parts(t, [&[a][..], &[], &[b]]).unwrap();
                }
            }
            // rows of the wrong width are refused and left out (the values read back below)
            let refused = w.row(1.0, &[1.0]).unwrap_err().to_string();
            assert!(refused.contains("a row of 1 values for 2 columns"), "{refused}");
            let refused = w.row_of_parts(1.0, [&[1.0, 2.0][..], &[3.0]]).unwrap_err().to_string();
            assert!(refused.contains("a row of 3 values for 2 columns"), "{refused}");
            if close {
                w.close().unwrap();
                w.close().unwrap();
            }
            drop(w);
            if rows == 0 {
                assert!(std::fs::metadata(&path).unwrap().len() > 0);
                continue;
            }
            // whole groups but the last
            let file = std::fs::File::open(&path).unwrap();
            let metadata = parquet::file::reader::SerializedFileReader::new(file).unwrap();
            let groups: Vec<i64> = parquet::file::reader::FileReader::metadata(&metadata)
                .row_groups()
                .iter()
                .map(|g| g.num_rows())
                .collect();
            let expected: Vec<i64> = (0..rows.div_ceil(ROW_GROUP_ROWS))
                .map(|g| (rows - g * ROW_GROUP_ROWS).min(ROW_GROUP_ROWS) as i64)
                .collect();
            assert_eq!(groups, expected, "{rows} rows");
            let (t, x) = read_channels(&path, &["a", "b"]).unwrap();
            assert_eq!(t.len(), rows);
            for i in 0..rows {
                assert_eq!(t[i].to_bits(), (i as f64 * 1e-3).to_bits(), "row {i}");
                assert_eq!(x[0][i].to_bits(), value(i, 0).to_bits(), "row {i}");
                assert_eq!(x[1][i].to_bits(), value(i, 1).to_bits(), "row {i}");
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn rows_become_columns_across_block_boundaries() {
        let mut columns = Vec::new();
        for (n, width) in [(0, 3), (1, 1), (5, 3), (64, 2), (65, 2), (200, 7), (3, 7)] {
            let rows: Vec<f64> = (0..n * width).map(|k| k as f64).collect();
            // reused, as the writer reuses them: leftovers of the previous shape must go
            columns.resize(width, vec![-1.0]);
            transpose(&rows, &mut columns);
            for (j, c) in columns.iter().enumerate() {
                let expected: Vec<f64> = (0..n).map(|i| (i * width + j) as f64).collect();
                assert_eq!(c, &expected, "n {n}, width {width}, column {j}");
            }
        }
    }
}
