//! TurbSim's binary full-field format (.bts), as TurbSim writes it and OpenFAST's InflowWind reads it
//! (TurbSim user's guide NREL/TP-500-46198, "binary full-field files"), little-endian:
//!
//! | field | type |
//! |---|---|
//! | ID: 7, or 8 for a periodic field | i16 |
//! | nz, ny, n_tower, nt | 4 × i32 |
//! | dz, dy, dt, u_hub, z_hub, z_bottom | 6 × f32 |
//! | slope and offset of u, v, w | 6 × f32 |
//! | length of the description, the description | i32, ASCII bytes |
//! | per time step: the grid, z slowest, then y, then the component; then the tower points below the grid, each u, v, w | i16 |
//!
//! A velocity is (stored − offset)/slope. The writer spreads each component's range over the whole of
//! i16 (slope 65535/(max − min), as TurbSim does), so a value comes back to within half a count,
//! (max − min)/131070, grid and tower points together. Tower points are kept (a file read and written
//! again loses none) but not sampled: the rotor samples the grid alone.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::WindField;

#[derive(Debug, thiserror::Error)]
pub enum BtsError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: {why}")]
    Format { path: PathBuf, why: String },
}

const HEADER_BYTES: usize = 2 + 4 * 4 + 6 * 4 + 6 * 4 + 4;

/// Reads a .bts file.
pub fn read(path: &Path) -> Result<WindField, BtsError> {
    let io = |source| BtsError::Io {
        path: path.to_path_buf(),
        source,
    };
    let bytes = std::fs::read(path).map_err(io)?;
    parse(&bytes).map_err(|why| BtsError::Format {
        path: path.to_path_buf(),
        why,
    })
}

/// Writes `field` to a .bts file with `description` (ASCII) in its header.
pub fn write(path: &Path, field: &WindField, description: &str) -> Result<(), BtsError> {
    let io = |source| BtsError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io)?;
    let mut out = std::io::BufWriter::new(file);
    encode(field, description, &mut out).map_err(io)?;
    out.flush().map_err(io)
}

/// The field in a .bts file's bytes; the error says what is wrong with them.
pub fn parse(bytes: &[u8]) -> Result<WindField, String> {
    if bytes.len() < HEADER_BYTES {
        return Err(format!(
            "{} bytes: shorter than a .bts header ({HEADER_BYTES})",
            bytes.len()
        ));
    }
    let int = |at: usize| i32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let float = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes")) as f64;
    let id = i16::from_le_bytes([bytes[0], bytes[1]]);
    let [nz, ny, n_tower, nt] = std::array::from_fn(|i| int(2 + 4 * i));
    let [dz, dy, dt, u_hub, z_hub, z_bottom] = std::array::from_fn(|i| float(18 + 4 * i));
    let scaling: [f64; 6] = std::array::from_fn(|i| float(42 + 4 * i));
    let chars = int(66);
    if id != 7 && id != 8 {
        return Err(format!(
            "format ID {id}: a TurbSim full field has 7 (or 8 when periodic)"
        ));
    }
    if nz < 1 || ny < 1 || nt < 1 || n_tower < 0 || chars < 0 {
        return Err(format!(
            "nz = {nz}, ny = {ny}, nt = {nt}, n_tower = {n_tower}, description length {chars}: counts must be positive"
        ));
    }
    if !(dt.is_finite() && dt > 0.0 && dz.is_finite() && dy.is_finite()) {
        return Err(format!(
            "dt = {dt}, dy = {dy}, dz = {dz}: dt must be positive, all finite"
        ));
    }
    let (nz, ny, n_tower, nt) = (nz as usize, ny as usize, n_tower as usize, nt as usize);
    let per_step = 3 * (ny * nz + n_tower);
    let expected = HEADER_BYTES as u128 + chars as u128 + 2 * (per_step as u128) * nt as u128;
    if bytes.len() as u128 != expected {
        return Err(format!(
            "{} bytes where nz = {nz}, ny = {ny}, n_tower = {n_tower}, nt = {nt} make {expected}",
            bytes.len()
        ));
    }
    for c in 0..3 {
        if !(scaling[2 * c].is_finite() && scaling[2 * c] != 0.0 && scaling[2 * c + 1].is_finite()) {
            return Err(format!(
                "{} slope {} offset {}: the slope must be finite and not zero",
                super::COMPONENTS[c],
                scaling[2 * c],
                scaling[2 * c + 1]
            ));
        }
    }
    let data = &bytes[HEADER_BYTES + chars as usize..];
    let points = ny * nz;
    let mut velocity: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(nt * points));
    let mut tower: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(nt * n_tower));
    for step in data.chunks_exact(2 * per_step) {
        // the grid's values, component fastest, then the tower points'
        for (i, count) in step.chunks_exact(2).enumerate() {
            let c = i % 3;
            let stored = i16::from_le_bytes([count[0], count[1]]) as f64;
            let value = (stored - scaling[2 * c + 1]) / scaling[2 * c];
            if i < 3 * points {
                velocity[c].push(value)
            } else {
                tower[c].push(value)
            }
        }
    }
    Ok(WindField {
        ny,
        nz,
        nt,
        dy,
        dz,
        dt,
        z_bottom,
        hub_height: z_hub,
        mean_hub: u_hub,
        periodic: id == 8,
        velocity,
        tower,
    })
}

/// The .bts bytes of `field`, its tower points included.
pub fn encode(field: &WindField, description: &str, out: &mut impl Write) -> std::io::Result<()> {
    let count = |n: usize| i32::try_from(n).map_err(|_| std::io::Error::other(format!("{n} does not fit an i32")));
    out.write_all(&(if field.periodic { 8i16 } else { 7i16 }).to_le_bytes())?;
    let n_tower = field.n_tower();
    for n in [field.nz, field.ny, n_tower, field.nt] {
        out.write_all(&count(n)?.to_le_bytes())?;
    }
    let header = [
        field.dz,
        field.dy,
        field.dt,
        field.mean_hub,
        field.hub_height,
        field.z_bottom,
    ];
    for x in header {
        out.write_all(&(x as f32).to_le_bytes())?;
    }
    // slope and offset in f32 as stored, so the counts are computed with what the reader will use
    let scaling: [(f32, f32); 3] = std::array::from_fn(|c| {
        let values = field.velocity[c].iter().chain(&field.tower[c]);
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
        if hi > lo {
            let slope = 65_535.0 / (hi - lo);
            (slope as f32, (-32_768.0 - slope * lo) as f32)
        } else {
            (1.0, -lo as f32)
        }
    });
    for (slope, offset) in scaling {
        out.write_all(&slope.to_le_bytes())?;
        out.write_all(&offset.to_le_bytes())?;
    }
    let text: Vec<u8> = description
        .bytes()
        .map(|b| if b.is_ascii() { b } else { b'?' })
        .collect();
    out.write_all(&count(text.len())?.to_le_bytes())?;
    out.write_all(&text)?;
    let points = field.ny * field.nz;
    let mut step = Vec::with_capacity(6 * (points + n_tower));
    for t in 0..field.nt {
        step.clear();
        let grid = (0..points).map(|p| (&field.velocity, t * points + p));
        let tower = (0..n_tower).map(|i| (&field.tower, t * n_tower + i));
        for (values, at) in grid.chain(tower) {
            for (c, (slope, offset)) in scaling.iter().enumerate() {
                let x = values[c][at];
                let stored = (x * *slope as f64 + *offset as f64).round().clamp(-32_768.0, 32_767.0) as i16;
                step.extend_from_slice(&stored.to_le_bytes());
            }
        }
        out.write_all(&step)?;
    }
    Ok(())
}
