//! Series from Parquet files: `windrive run --out FILE.parquet`, or a table written by pandas, polars
//! or pyarrow with a `time` column and Float64 channels. Only the columns asked for are decoded, one
//! record batch at a time, and every row passes the checks a CSV row does ([`super::series`]).

use super::rows::{CheckedRows, Extent, SeriesError};
use arrow_array::{Array, Float64Array};
use parquet::arrow::ProjectionMask;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::path::Path;

/// Whether `path` names a Parquet file (by its extension).
pub fn is_parquet(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

/// As [`super::series::stream_channels`] for a Parquet file: `sample` gets the time and the row's
/// values in the order of `channels`. Rows are numbered from 1 as a reader's row index + 1.
pub fn stream_channels(
    path: &Path,
    channels: &[&str],
    mut sample: impl FnMut(f64, &[f64]),
) -> Result<Extent, SeriesError> {
    let p = path.display().to_string();
    let read_error = |e: &dyn std::fmt::Display| SeriesError::Read {
        path: p.clone(),
        message: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(|e| read_error(&e))?;
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).map_err(|e| read_error(&e))?;
    let schema = builder.schema().clone();
    let header: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    let position = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| SeriesError::UnknownChannel {
                path: p.clone(),
                channel: name.to_string(),
                available: header.join(", "),
            })
    };
    // the time first, then the channels: each slot's column in the file
    let mut names = vec!["time"];
    names.extend_from_slice(channels);
    let columns: Vec<usize> = names.iter().map(|n| position(n)).collect::<Result<_, _>>()?;
    for &c in &columns {
        let field = schema.field(c);
        if field.data_type() != &arrow_schema::DataType::Float64 {
            return Err(read_error(&format!(
                "column {} is {}, not Float64 (double)",
                field.name(),
                field.data_type()
            )));
        }
    }
    // the projection keeps the file's column order: where each wanted column lands in a batch
    let mut wanted = columns.clone();
    wanted.sort_unstable();
    wanted.dedup();
    let in_batch: Vec<usize> = columns.iter().map(|c| wanted.binary_search(c).unwrap()).collect();
    let mask = ProjectionMask::roots(builder.parquet_schema(), wanted.iter().copied());
    let reader = builder.with_projection(mask).build().map_err(|e| read_error(&e))?;
    let mut rows = CheckedRows::new(p.clone(), &names);
    let mut values = vec![0.0; names.len()];
    let mut row = 0;
    for batch in reader {
        let batch = batch.map_err(|e| read_error(&e))?;
        let arrays: Vec<&Float64Array> = in_batch
            .iter()
            .map(|&i| {
                batch
                    .column(i)
                    .as_any()
                    .downcast_ref::<Float64Array>()
                    .expect("checked Float64")
            })
            .collect();
        for r in 0..batch.num_rows() {
            row += 1;
            for (v, a) in values.iter_mut().zip(&arrays) {
                *v = if a.is_null(r) { f64::NAN } else { a.value(r) };
            }
            rows.accept(row, &values, &mut sample)?;
        }
    }
    rows.finish()
}
