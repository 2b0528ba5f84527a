//! Results as Parquet: the same columns as the CSV (`time`, then `<component>.<variable>`), each a
//! Float64 column, Snappy-compressed, readable as is by pandas, polars and pyarrow. Numbers are stored
//! as their bits, so nothing is spent on float text and nothing is lost to it.
//!
//! Rows are kept in column buffers and written as one row group per [`ROW_GROUP_ROWS`] rows. Parquet
//! places its index (the footer) at the end of the file: the file is complete once the run ends,
//! fails or is stopped and the recorder is finished, flushed or dropped. A process killed outright
//! (SIGKILL, a crashing FMU without `--isolate`) leaves a file no reader opens; CSV keeps the rows
//! up to its last quarter-second flush there.

use arrow_array::{ArrayRef, Float64Array, RecordBatch};
use arrow_schema::{DataType, Field, Schema};
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::properties::WriterProperties;
use std::path::Path;
use std::sync::Arc;

/// Rows per row group: 65 536 rows of 67 channels is 35 MB of buffered columns, and a reader that
/// needs a time range skips whole groups.
pub const ROW_GROUP_ROWS: usize = 1 << 16;

/// Writes a Parquet file with a `time` column and one Float64 column per name.
pub struct ParquetWriter {
    /// None once closed.
    writer: Option<ArrowWriter<std::fs::File>>,
    schema: Arc<Schema>,
    /// The time, then each named column: the rows not yet written.
    columns: Vec<Vec<f64>>,
    path: String,
}

fn io_error(path: &str, e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(format!("{path}: {e}"))
}

impl ParquetWriter {
    /// Creates the file (and its folder) for `time`, then `columns`.
    pub fn create<'a>(path: &Path, columns: impl IntoIterator<Item = &'a str>) -> std::io::Result<Self> {
        let shown = path.display().to_string();
        let mut fields = vec![Field::new("time", DataType::Float64, false)];
        for name in columns {
            if name == "time" {
                return Err(io_error(
                    &shown,
                    "a recorded variable is named \"time\", the time column's name",
                ));
            }
            fields.push(Field::new(name, DataType::Float64, false));
        }
        let schema = Arc::new(Schema::new(fields));
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", dir.display())))?;
        }
        let file = std::fs::File::create(path).map_err(|e| std::io::Error::new(e.kind(), format!("{shown}: {e}")))?;
        // Dictionary encoding finds nothing to share in simulated floats and costs a hash per value.
        let properties = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_dictionary_enabled(false)
            .build();
        let writer = ArrowWriter::try_new(file, schema.clone(), Some(properties)).map_err(|e| io_error(&shown, e))?;
        Ok(Self {
            writer: Some(writer),
            columns: vec![Vec::with_capacity(1024); schema.fields().len()],
            schema,
            path: shown,
        })
    }

    /// Adds one row: the time, then the values in the columns' order.
    pub fn row(&mut self, time: f64, values: impl IntoIterator<Item = f64>) -> std::io::Result<()> {
        let (first, rest) = self.columns.split_first_mut().expect("the time column");
        first.push(time);
        let mut count = 0;
        for (column, v) in rest.iter_mut().zip(values) {
            column.push(v);
            count += 1;
        }
        if count != rest.len() {
            return Err(io_error(
                &self.path,
                format!("a row of {count} values for {} columns", rest.len()),
            ));
        }
        if first.len() >= ROW_GROUP_ROWS {
            self.write_buffered()?;
        }
        Ok(())
    }

    /// Writes the buffered rows as a row group.
    fn write_buffered(&mut self) -> std::io::Result<()> {
        let Some(writer) = &mut self.writer else {
            return Err(io_error(&self.path, "written after it was closed"));
        };
        if self.columns[0].is_empty() {
            return Ok(());
        }
        let capacity = self.columns[0].len();
        let arrays: Vec<ArrayRef> = self
            .columns
            .iter_mut()
            .map(|c| Arc::new(Float64Array::from(std::mem::replace(c, Vec::with_capacity(capacity)))) as ArrayRef)
            .collect();
        let batch = RecordBatch::try_new(self.schema.clone(), arrays).map_err(|e| io_error(&self.path, e))?;
        writer.write(&batch).map_err(|e| io_error(&self.path, e))?;
        writer.flush().map_err(|e| io_error(&self.path, e))
    }

    /// Writes the buffered rows and the footer: the file is complete. Closing twice does nothing.
    pub fn close(&mut self) -> std::io::Result<()> {
        if self.writer.is_none() {
            return Ok(());
        }
        let written = self.write_buffered();
        let writer = self.writer.take().expect("checked above");
        let closed = writer.close().map(|_| ()).map_err(|e| io_error(&self.path, e));
        written.and(closed)
    }
}

impl Drop for ParquetWriter {
    /// A recorder dropped on an error path still leaves a readable file with every row it was given.
    fn drop(&mut self) {
        let _ = self.close();
    }
}

/// Whether `path` names a Parquet file (by its extension).
pub fn is_parquet(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}
