//! AeroDyn v15 input files read into a blade folder (`windrive blade import`): the blade file, its
//! airfoil ("AirfoilInfo" v1) files, and where they are named, AeroDyn's and ElastoDyn's primary files.
//!
//! The formats as the OpenFAST AeroDyn user documentation describes them (docs/SOURCES.md §Public sources,
//! "AeroDyn input files"):
//!
//! - **Blade file**: two free header lines, a section line, `NumBlNds`, a line of column names, a line
//!   of units, then NumBlNds rows. Columns are found by their names, as AeroDyn finds them: `BlSpn`,
//!   `BlCrvAC`, `BlSwpAC`, `BlTwist`, `BlChord`, `BlAFID` are required, `BlCrvAng` may be left out,
//!   any other column (`t_c`, `BlCb`, ...) is passed over. BlSpn starts at 0 and rises; the blade's
//!   tip is its last node. `BlAFID` k names the k-th airfoil file of the primary file's `AFNames`.
//! - **Airfoil file**: lines `value label [description]`; a line whose first non-blank character is
//!   `!` is a comment, one starting with `@` includes another file (the airfoil's shape coordinates:
//!   not followed, the shape is not used). Read: `InterpOrd`, `NumTabs`, and of the first table `Re`,
//!   `NumAlf` and the NumAlf rows that follow it; every value between `InclUAdata` and `NumAlf` is an
//!   unsteady-aerodynamics constant and is dropped, as are tables 2… (what AeroDyn does with
//!   `AFTabMod = 1`) and the columns besides angle of attack, C_l and C_d (C_m, C_pmin).
//! - **AeroDyn primary file**: `InCol_Alfa`, `InCol_Cl`, `InCol_Cd` (the table columns; 1, 2, 3 when
//!   absent), `NumAFfiles` and the file names on the lines after it, relative to the primary file.
//! - **ElastoDyn primary file**: `HubRad` and `NumBl` (AeroDyn's blade file has no hub radius).
//!
//! Every error names the file, and where there is one the line and the field.

mod read;
#[cfg(test)]
mod samples;

pub use read::{
    AeroDynBlade, AeroDynError, AeroDynNode, AeroDynPrimary, Airfoil, Columns, ElastoDynRotor, read_airfoil,
    read_blade, read_elastodyn, read_primary,
};

use super::write::{BladeFolder, NodeRow, PolarTable};
use std::path::{Path, PathBuf};

/// A blade folder imported, and what the import changed or left out, one sentence each.
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    pub folder: BladeFolder,
    pub notes: Vec<String>,
}

/// A polar's name from its file: the file name without its extension, usable as `<name>.csv` and in
/// blade.csv's airfoil column.
fn polar_name(path: &Path) -> Result<String, AeroDynError> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    if stem.is_empty() || stem.starts_with(['#', '.']) || stem.contains([',', '/', '\\']) {
        return Err(AeroDynError::File {
            path: path.into(),
            what: format!("{stem:?} cannot name a polar file (empty, or with ',' or a leading '#' or '.')"),
        });
    }
    Ok(stem)
}

fn largest(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, |m, v| m.max(v.abs()))
}

/// The blade folder of an AeroDyn blade and its airfoils (`airfoils[k − 1]` is BlAFID k), on a hub of
/// radius `hub_radius_m` with `blades` blades. Spans, chords, twists and the polars' rows are copied
/// unchanged; the tip radius is written explicitly, hub radius + the last BlSpn (AeroDyn's tip).
pub fn import(
    blade: &AeroDynBlade,
    airfoils: &[Airfoil],
    hub_radius_m: f64,
    blades: u32,
) -> Result<Imported, AeroDynError> {
    if !(hub_radius_m.is_finite() && hub_radius_m >= 0.0) || blades == 0 {
        return Err(AeroDynError::File {
            path: blade.path.clone(),
            what: format!("hub radius {hub_radius_m} m and {blades} blades: need a radius ≥ 0 and at least one blade"),
        });
    }
    // the airfoils in the order the nodes first use them, each once
    let mut used: Vec<usize> = Vec::new();
    for n in &blade.nodes {
        if n.airfoil_id > airfoils.len() {
            return Err(AeroDynError::Field {
                path: blade.path.clone(),
                line: n.line,
                field: "BlAFID".into(),
                what: format!("airfoil {} of {} airfoil files", n.airfoil_id, airfoils.len()),
            });
        }
        if !used.contains(&n.airfoil_id) {
            used.push(n.airfoil_id);
        }
    }
    used.sort_unstable();
    let mut names: Vec<(usize, String)> = Vec::new();
    for &id in &used {
        let name = polar_name(&airfoils[id - 1].path)?;
        if let Some((other, _)) = names.iter().find(|(_, n)| *n == name) {
            return Err(AeroDynError::File {
                path: airfoils[id - 1].path.clone(),
                what: format!("airfoils {other} and {id} would both be written as {name}.csv"),
            });
        }
        names.push((id, name));
    }
    let name_of = |id: usize| {
        names
            .iter()
            .find(|(i, _)| *i == id)
            .map(|(_, n)| n.clone())
            .unwrap_or_default()
    };
    let nodes: Vec<NodeRow> = blade
        .nodes
        .iter()
        .map(|n| NodeRow {
            span_m: n.span_m,
            chord_m: n.chord_m,
            twist_deg: n.twist_deg,
            airfoil: name_of(n.airfoil_id),
        })
        .collect();
    let last_span = blade.nodes.last().map_or(0.0, |n| n.span_m);
    let tip_radius_m = hub_radius_m + last_span;

    let mut notes = Vec::new();
    let (curve, sweep) = (
        largest(blade.nodes.iter().map(|n| n.curve_ac_m)),
        largest(blade.nodes.iter().map(|n| n.sweep_ac_m)),
    );
    let angle = largest(blade.nodes.iter().filter_map(|n| n.curve_angle_deg));
    let shape: Vec<String> = [
        ("BlCrvAC", curve, "m"),
        ("BlSwpAC", sweep, "m"),
        ("BlCrvAng", angle, "deg"),
    ]
    .iter()
    .filter(|(_, v, _)| *v > 0.0)
    .map(|(name, v, unit)| format!("{name} (up to {v} {unit})"))
    .collect();
    if !shape.is_empty() {
        notes.push(format!("not used, the BEM's blade is straight: {}", shape.join(", ")));
    }
    let unused: Vec<String> = (1..=airfoils.len())
        .filter(|id| !used.contains(id))
        .map(|id| format!("{id} ({})", airfoils[id - 1].path.display()))
        .collect();
    if !unused.is_empty() {
        notes.push(format!("airfoils no node uses, not written: {}", unused.join(", ")));
    }
    let polars = names
        .iter()
        .map(|(id, name)| {
            let af = &airfoils[id - 1];
            let mut comments = vec![format!(
                "{name} airfoil polar, imported by windrive blade import from the AeroDyn airfoil file {}",
                af.path.display()
            )];
            comments.extend(af.description.iter().map(|d| format!("source: {d}")));
            let mut dropped = Vec::new();
            if af.tables > 1 {
                dropped.push(format!(
                    "tables 2 to {} (AeroDyn's AFTabMod = 1 uses the first)",
                    af.tables
                ));
                notes.push(format!("{name}: table 1 of {} imported", af.tables));
            }
            if af.unsteady_values > 0 {
                dropped.push(format!("{} unsteady-aerodynamics values", af.unsteady_values));
            }
            if af.extra_columns > 0 {
                let s = if af.extra_columns == 1 { "" } else { "s" };
                dropped.push(format!("{} more table column{s} (Cm, Cpmin)", af.extra_columns));
            }
            if af.interp_order != 1 {
                notes.push(format!(
                    "{name}: InterpOrd = {} (AeroDyn would use cubic splines); the BEM interpolates linearly",
                    af.interp_order
                ));
            }
            let re = af
                .reynolds_millions
                .map_or(String::new(), |re| format!(" (Re = {re} million)"));
            comments.push(format!(
                "Alpha, Cl, Cd of table 1{re} from line {}, unchanged{}",
                af.first_row_line,
                if dropped.is_empty() {
                    String::new()
                } else {
                    format!("; left out: {}", dropped.join(", "))
                }
            ));
            PolarTable {
                name: name.clone(),
                comments,
                alpha_deg: af.alpha_deg.clone(),
                cl: af.cl.clone(),
                cd: af.cd.clone(),
            }
        })
        .collect();
    let mut comments = vec![format!(
        "Imported by windrive blade import from the AeroDyn v15 blade file {}",
        blade.path.display()
    )];
    if !blade.title.is_empty() {
        comments.push(format!("source: {}", blade.title));
    }
    comments.push(format!(
        "BlSpn, BlChord, BlTwist unchanged; BlAFID named after the airfoil files: {}",
        names
            .iter()
            .map(|(id, n)| format!("{id} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    comments.push(format!(
        "Tip radius = hub radius + last BlSpn ({hub_radius_m} + {last_span} m), AeroDyn's blade tip"
    ));
    comments.extend(notes.iter().cloned());
    Ok(Imported {
        folder: BladeFolder {
            comments,
            hub_radius_m,
            tip_radius_m: Some(tip_radius_m),
            blades,
            nodes,
            polars,
        },
        notes,
    })
}

/// Where the airfoil files come from.
#[derive(Debug, Clone, PartialEq)]
pub enum AirfoilSource {
    /// An AeroDyn primary input file: its AFNames and table columns.
    Primary(PathBuf),
    /// The files in BlAFID order (the table columns AeroDyn's defaults, 1, 2, 3).
    Files(Vec<PathBuf>),
}

/// Reads a blade file and its airfoils and imports them (see [`import`]). With `polars`, the airfoil
/// files are looked up in that folder by file name (a primary file's paths may point elsewhere).
pub fn import_files(
    blade_file: &Path,
    airfoils: &AirfoilSource,
    polars: Option<&Path>,
    hub_radius_m: f64,
    blades: u32,
) -> Result<Imported, AeroDynError> {
    let blade = read_blade(blade_file)?;
    let (files, columns) = match airfoils {
        AirfoilSource::Primary(p) => {
            let primary = read_primary(p)?;
            (primary.airfoil_files, primary.columns)
        }
        AirfoilSource::Files(f) => (f.clone(), Columns::default()),
    };
    let files: Vec<PathBuf> = match polars {
        Some(dir) => files
            .iter()
            .map(|f| f.file_name().map_or_else(|| f.clone(), |n| dir.join(n)))
            .collect(),
        None => files,
    };
    // every file is read, as AeroDyn reads every AFNames entry
    let read: Vec<Airfoil> = files
        .iter()
        .map(|f| read_airfoil(f, columns))
        .collect::<Result<_, _>>()?;
    import(&blade, &read, hub_radius_m, blades)
}

#[cfg(test)]
mod tests {
    use super::samples::{AIRFOIL, BLADE, dir, put};
    use super::*;
    use crate::physics::blade::Blade;

    /// Import, write, read back as the rotor reads it: every number the same double.
    #[test]
    fn import_write_load_round_trip() {
        let d = dir("roundtrip");
        let blade = read_blade(&put(&d, "blade.dat", BLADE)).unwrap();
        let a = read_airfoil(&put(&d, "af/one.dat", AIRFOIL), Columns::default()).unwrap();
        let b = Airfoil {
            path: d.join("af/two.dat"),
            cl: a.cl.iter().map(|c| c * 1.1).collect(),
            ..a.clone()
        };
        let imported = import(&blade, &[a.clone(), b.clone()], 1.25, 3).unwrap();
        let f = &imported.folder;
        assert_eq!(f.tip_radius_m, Some(11.25));
        assert!(
            imported.notes.iter().any(|n| n.contains("BlCrvAC (up to 0.2 m)")),
            "{:?}",
            imported.notes
        );
        let out = d.join("out");
        f.write(&out).unwrap();
        let loaded = Blade::load(&out).unwrap();
        assert_eq!(
            (loaded.hub_radius, loaded.tip_radius(), loaded.blades),
            (1.25, 11.25, 3)
        );
        for (n, src) in loaded.nodes.iter().zip(&blade.nodes) {
            assert_eq!(
                (n.span, n.chord, n.twist),
                (src.span_m, src.chord_m, src.twist_deg.to_radians())
            );
            assert_eq!(loaded.polars[n.airfoil].name, ["one", "two"][src.airfoil_id - 1]);
        }
        for (p, src) in loaded.polars.iter().zip([&a, &b]) {
            let alpha: Vec<f64> = src.alpha_deg.iter().map(|x| x.to_radians()).collect();
            assert_eq!((&p.alpha, &p.cl, &p.cd), (&alpha, &src.cl, &src.cd));
        }
        let text = std::fs::read_to_string(out.join("one.csv")).unwrap();
        assert!(
            text.contains("left out: tables 2 to 2") && text.contains("3 unsteady-aerodynamics values"),
            "{text}"
        );
    }

    #[test]
    fn airfoil_numbers_beyond_the_files_are_named() {
        let d = dir("afid");
        let blade = read_blade(&put(&d, "blade.dat", BLADE)).unwrap();
        let a = read_airfoil(&put(&d, "one.dat", AIRFOIL), Columns::default()).unwrap();
        let e = import(&blade, &[a], 1.0, 3).unwrap_err().to_string();
        assert!(
            e.contains("blade.dat line 8, BlAFID: airfoil 2 of 1 airfoil files"),
            "{e}"
        );
    }

    /// The OpenFAST NREL 5 MW blade and its airfoils (tests/data/nrel-5mw-aerodyn/, README there).
    #[test]
    fn nrel_5mw_blade_imports() {
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/nrel-5mw-aerodyn");
        let imported = import_files(
            &data.join("5MW_Baseline/NRELOffshrBsline5MW_AeroDyn_blade.dat"),
            &AirfoilSource::Primary(data.join("onshore/AeroDyn.dat")),
            None,
            1.5,
            3,
        )
        .unwrap();
        let f = &imported.folder;
        assert_eq!(f.nodes.len(), 19);
        assert_eq!(f.tip_radius_m, Some(1.5 + 61.4999));
        let names: Vec<&str> = f.polars.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "Cylinder1",
                "Cylinder2",
                "DU40_A17",
                "DU35_A17",
                "DU30_A17",
                "DU25_A17",
                "DU21_A17",
                "NACA64_A17"
            ]
        );
        assert_eq!(
            (f.nodes[4].airfoil.as_str(), f.nodes[4].chord_m, f.nodes[4].twist_deg),
            ("DU40_A17", 4.557, 13.308)
        );
        assert_eq!(
            f.polars.iter().map(|p| p.alpha_deg.len()).sum::<usize>(),
            3 + 3 + 136 + 135 + 143 + 140 + 142 + 127
        );
        // the same through --polars: the primary file's paths ignored, its file names looked up there
        let again = import_files(
            &data.join("5MW_Baseline/NRELOffshrBsline5MW_AeroDyn_blade.dat"),
            &AirfoilSource::Primary(data.join("onshore/AeroDyn.dat")),
            Some(&data.join("5MW_Baseline/Airfoils")),
            1.5,
            3,
        )
        .unwrap();
        for (p, q) in again.folder.polars.iter().zip(&f.polars) {
            assert_eq!(
                (&p.name, &p.alpha_deg, &p.cl, &p.cd),
                (&q.name, &q.alpha_deg, &q.cl, &q.cd)
            );
        }
    }
}
