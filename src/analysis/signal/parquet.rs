//! Series from Parquet files: `windrive run --out FILE.parquet`, or a table written by pandas, polars
//! or pyarrow with a `time` column and Float64 (DOUBLE) channels, required or nullable (a null reads
//! as NaN, which the row checks then reject with its row number). Only the columns asked for are
//! decoded, one row group at a time, and every row passes the checks a CSV row does
//! ([`super::series`]). Read through the parquet crate's column readers (see `cosim::parquet` for
//! why not its Arrow layer); the codecs are Snappy's and uncompressed, which pandas and pyarrow
//! write by default (another codec, polars' default zstd for one, is refused with a hint).

use super::rows::{CheckedRows, Extent, SeriesError};
use parquet::basic::{Compression, Type as PhysicalType};
use parquet::column::reader::ColumnReader;
use parquet::file::reader::{FileReader, RowGroupReader, SerializedFileReader};
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
    let reader = SerializedFileReader::new(file).map_err(|e| read_error(&e))?;
    let schema = reader.metadata().file_metadata().schema_descr_ptr();
    // the file's top-level columns (a nested column's leaves are not channels)
    let header: Vec<(usize, &str)> = (0..schema.num_columns())
        .map(|i| (i, schema.get_column_root(i)))
        .filter(|(_, root)| root.is_primitive())
        .map(|(i, root)| (i, root.name()))
        .collect();
    let position = |name: &str| {
        header
            .iter()
            .find(|(_, h)| *h == name)
            .map(|&(i, _)| i)
            .ok_or_else(|| SeriesError::UnknownChannel {
                path: p.clone(),
                channel: name.to_string(),
                available: header.iter().map(|(_, h)| *h).collect::<Vec<_>>().join(", "),
            })
    };
    // the time first, then the channels: each slot's leaf column in the file
    let mut names = vec!["time"];
    names.extend_from_slice(channels);
    let columns: Vec<usize> = names.iter().map(|n| position(n)).collect::<Result<_, _>>()?;
    for &c in &columns {
        let column = schema.column(c);
        if column.physical_type() != PhysicalType::DOUBLE || column.max_rep_level() > 0 {
            let logical = column.logical_type_ref().map_or(String::new(), |l| format!(" ({l:?})"));
            return Err(read_error(&format!(
                "column {} is {}{logical}{}, not Float64 (double)",
                column.name(),
                column.physical_type(),
                if column.max_rep_level() > 0 { ", repeated" } else { "" },
            )));
        }
    }
    // each wanted column decoded once, whichever slots ask for it
    let mut wanted = columns.clone();
    wanted.sort_unstable();
    wanted.dedup();
    let slot: Vec<usize> = columns.iter().map(|c| wanted.binary_search(c).unwrap()).collect();
    let mut rows = CheckedRows::new(p.clone(), &names);
    let mut decoded: Vec<Vec<f64>> = vec![Vec::new(); wanted.len()];
    let mut values = vec![0.0; names.len()];
    let mut row = 0;
    for g in 0..reader.num_row_groups() {
        let group = reader.get_row_group(g).map_err(|e| read_error(&e))?;
        let count = usize::try_from(group.metadata().num_rows()).map_err(|e| read_error(&e))?;
        for (&c, out) in wanted.iter().zip(&mut decoded) {
            let at = format!("column {}, row group {g}", schema.column(c).name());
            let codec = group.metadata().column(c).compression();
            if !matches!(codec, Compression::UNCOMPRESSED | Compression::SNAPPY) {
                // the codec's name without its level ("ZSTD", not "ZSTD(ZstdLevel(1))")
                let codec = codec.to_string();
                let codec = codec.split('(').next().unwrap_or_default().to_string();
                return Err(read_error(&format!(
                    "{at}: compressed with {codec}; windrive reads Snappy and uncompressed Parquet, pandas' and \
                     pyarrow's default: write it with compression=\"snappy\", as polars' \
                     write_parquet(path, compression=\"snappy\") does"
                )));
            }
            read_doubles(group.as_ref(), c, count, out).map_err(|e| read_error(&format!("{at}: {e}")))?;
        }
        for r in 0..count {
            row += 1;
            for (v, &s) in values.iter_mut().zip(&slot) {
                *v = decoded[s][r];
            }
            rows.accept(row, &values, &mut sample)?;
        }
    }
    rows.finish()
}

/// The `count` values of DOUBLE column `c` in `group` into `out` (cleared first), a null as NaN.
fn read_doubles(group: &dyn RowGroupReader, c: usize, count: usize, out: &mut Vec<f64>) -> Result<(), String> {
    let ColumnReader::DoubleColumnReader(mut reader) = group.get_column_reader(c).map_err(|e| e.to_string())? else {
        return Err("not a DOUBLE column".into());
    };
    let nullable = group.metadata().column(c).column_descr().max_def_level() > 0;
    out.clear();
    let (mut levels, mut present) = (Vec::new(), Vec::new());
    while out.len() < count {
        let (records, _, _) = reader
            .read_records(
                count - out.len(),
                nullable.then_some(&mut levels),
                None,
                if nullable { &mut present } else { out },
            )
            .map_err(|e| e.to_string())?;
        if records == 0 {
            return Err(format!("{} of {count} values present", out.len()));
        }
        if nullable {
            // a defined value takes the next of those present, in order
            let mut next = present.drain(..);
            out.extend(levels.drain(..).map(|l| {
                if l > 0 {
                    next.next().unwrap_or(f64::NAN)
                } else {
                    f64::NAN
                }
            }));
        }
    }
    Ok(())
}
