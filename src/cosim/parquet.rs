//! Results as Parquet: the same columns as the CSV (`time`, then `<component>.<variable>`), each a
//! Float64 column, Snappy-compressed, readable as is by pandas, polars and pyarrow. Numbers are stored
//! as their bits, so nothing is spent on float text and nothing is lost to it.
//!
//! Rows are kept as they come, one after the other in one buffer, and handed to the Parquet encoder
//! as columns every [`BATCH_ROWS`] rows (a row costs one copy, not a push per column; the buffer is
//! reused and stays in the cache); the encoder cuts a row group every [`ROW_GROUP_ROWS`] rows. Parquet
//! places its index (the footer) at the end of the file: the file is complete once the run ends,
//! fails or is stopped and the recorder is finished, flushed or dropped. A process killed outright
//! (SIGKILL, a crashing FMU without `--isolate`) leaves a file no reader opens; CSV keeps the rows
//! up to its last quarter-second flush there.

use arrow_array::{ArrayRef, Float64Array, RecordBatch};
use arrow_schema::{DataType, Field, Schema};
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::properties::{EnabledStatistics, WriterProperties};
use parquet::schema::types::ColumnPath;
use std::path::Path;
use std::sync::Arc;

/// Rows per row group: a reader that needs a time range skips whole groups. The encoder holds a
/// group's pages until it is complete: 8192 rows of 67 channels are 4.4 MB, which the allocator
/// largely hands back for the next group (c-shutdown-spring, every row: 4 900 page faults against
/// 6 400 with 65 536-row groups and 1 550 without recording).
pub const ROW_GROUP_ROWS: usize = 1 << 13;

/// Rows buffered before they are encoded: 4096 rows of 67 channels are 2.2 MB, reused for the next.
pub const BATCH_ROWS: usize = 1 << 12;

/// Writes a Parquet file with a `time` column and one Float64 column per name.
pub struct ParquetWriter {
    /// None once closed.
    writer: Option<ArrowWriter<std::fs::File>>,
    schema: Arc<Schema>,
    /// The rows not yet written, row after row: the time, then each named column's value.
    rows: Vec<f64>,
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
        // Min/max statistics only for the time column, where they let a reader skip row groups
        // outside a time range; a channel's cost a comparison pair per value (a quarter of the
        // writer's work, callgrind) for a filter no analysis asks.
        let properties = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_dictionary_enabled(false)
            .set_statistics_enabled(EnabledStatistics::None)
            .set_column_statistics_enabled(ColumnPath::from("time"), EnabledStatistics::Page)
            .set_max_row_group_row_count(Some(ROW_GROUP_ROWS))
            .build();
        let writer = ArrowWriter::try_new(file, schema.clone(), Some(properties)).map_err(|e| io_error(&shown, e))?;
        let width = schema.fields().len();
        Ok(Self {
            writer: Some(writer),
            rows: Vec::new(),
            width,
            schema,
            path: shown,
        })
    }

    /// Adds one row: the time, then the values in the columns' order.
    pub fn row(&mut self, time: f64, values: impl IntoIterator<Item = f64>) -> std::io::Result<()> {
        let start = self.rows.len();
        if start == 0 {
            // the whole batch at once: growing it would copy every row kept so far, repeatedly
            self.rows.reserve_exact(BATCH_ROWS * self.width);
        }
        self.rows.push(time);
        self.rows.extend(values.into_iter().take(self.width - 1));
        let count = self.rows.len() - start - 1;
        if count != self.width - 1 {
            self.rows.truncate(start);
            return Err(io_error(
                &self.path,
                format!("a row of {count} values for {} columns", self.width - 1),
            ));
        }
        if self.rows.len() >= BATCH_ROWS * self.width {
            self.write_buffered()?;
        }
        Ok(())
    }

    /// Hands the buffered rows to the encoder, which writes a row group each time it has
    /// [`ROW_GROUP_ROWS`].
    fn write_buffered(&mut self) -> std::io::Result<()> {
        let Some(writer) = &mut self.writer else {
            return Err(io_error(&self.path, "written after it was closed"));
        };
        if self.rows.is_empty() {
            return Ok(());
        }
        let columns = transpose(&self.rows, self.width);
        self.rows.clear();
        let arrays: Vec<ArrayRef> = columns
            .into_iter()
            .map(|c| Arc::new(Float64Array::from(c)) as ArrayRef)
            .collect();
        let batch = RecordBatch::try_new(self.schema.clone(), arrays).map_err(|e| io_error(&self.path, e))?;
        writer.write(&batch).map_err(|e| io_error(&self.path, e))
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

/// Rows of `width` values, one after the other, as `width` columns. By blocks of rows that stay in
/// the cache while every column takes its share: a column at a time over the whole buffer would read
/// it from memory once per column.
fn transpose(rows: &[f64], width: usize) -> Vec<Vec<f64>> {
    const BLOCK_ROWS: usize = 64;
    let n = rows.len() / width;
    let mut columns: Vec<Vec<f64>> = (0..width).map(|_| Vec::with_capacity(n)).collect();
    for block in rows.chunks(BLOCK_ROWS * width) {
        for (j, column) in columns.iter_mut().enumerate() {
            column.extend(block.iter().skip(j).step_by(width));
        }
    }
    columns
}

/// Whether `path` names a Parquet file (by its extension).
pub fn is_parquet(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

#[cfg(test)]
mod tests {
    use super::transpose;

    #[test]
    fn rows_become_columns_across_block_boundaries() {
        for (n, width) in [(0, 3), (1, 1), (5, 3), (64, 2), (65, 2), (200, 7)] {
            let rows: Vec<f64> = (0..n * width).map(|k| k as f64).collect();
            let columns = transpose(&rows, width);
            assert_eq!(columns.len(), width);
            for (j, c) in columns.iter().enumerate() {
                let expected: Vec<f64> = (0..n).map(|i| (i * width + j) as f64).collect();
                assert_eq!(c, &expected, "n {n}, width {width}, column {j}");
            }
        }
    }
}
