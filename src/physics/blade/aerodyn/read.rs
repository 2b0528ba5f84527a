//! The AeroDyn, AirfoilInfo and ElastoDyn files as they are written (see the parent module for the
//! formats): each reader returns the file's numbers, every error naming the file, line and field.

use std::path::{Path, PathBuf};

/// An AeroDyn input file that cannot be imported.
#[derive(Debug, thiserror::Error)]
pub enum AeroDynError {
    #[error("{}: {cause}", path.display())]
    Read { path: PathBuf, cause: std::io::Error },
    #[error("{} line {line}, {field}: {what}", path.display())]
    Field {
        path: PathBuf,
        line: usize,
        field: String,
        what: String,
    },
    #[error("{}: {what}", path.display())]
    File { path: PathBuf, what: String },
}

/// One row of an AeroDyn blade file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AeroDynNode {
    /// Line of the file (1-based).
    pub line: usize,
    /// BlSpn: span from the blade root along the pitch axis, m.
    pub span_m: f64,
    /// BlCrvAC: out-of-plane offset of the aerodynamic centre (precurve), m.
    pub curve_ac_m: f64,
    /// BlSwpAC: in-plane offset of the aerodynamic centre (sweep), m.
    pub sweep_ac_m: f64,
    /// BlCrvAng: curvature angle, deg (None when the column is absent).
    pub curve_angle_deg: Option<f64>,
    /// BlTwist, deg, positive to feather.
    pub twist_deg: f64,
    /// BlChord, m.
    pub chord_m: f64,
    /// BlAFID: 1-based place of the node's airfoil in the primary file's AFNames.
    pub airfoil_id: usize,
}

/// An AeroDyn v15 blade file.
#[derive(Debug, Clone, PartialEq)]
pub struct AeroDynBlade {
    pub path: PathBuf,
    /// The second header line (the first is the file type's banner).
    pub title: String,
    pub nodes: Vec<AeroDynNode>,
}

/// Which columns (1-based) of an airfoil table hold the angle of attack, C_l and C_d (the primary
/// file's InCol_Alfa, InCol_Cl, InCol_Cd).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Columns {
    pub alpha: usize,
    pub cl: usize,
    pub cd: usize,
}

impl Default for Columns {
    fn default() -> Self {
        Self { alpha: 1, cl: 2, cd: 3 }
    }
}

/// The first table of an airfoil file, and what the import leaves out of the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Airfoil {
    pub path: PathBuf,
    /// The comment lines before the first value (the file's description), without the `!`.
    pub description: Vec<String>,
    /// InterpOrd (1 linear, 3 cubic; `DEFAULT` is 1).
    pub interp_order: u32,
    /// NumTabs.
    pub tables: usize,
    /// Re of the first table, millions.
    pub reynolds_millions: Option<f64>,
    /// Unsteady-aerodynamics values of the first table that were dropped.
    pub unsteady_values: usize,
    /// Table columns besides the three kept (C_m, C_pmin, ...).
    pub extra_columns: usize,
    /// Line of the first table row.
    pub first_row_line: usize,
    pub alpha_deg: Vec<f64>,
    pub cl: Vec<f64>,
    pub cd: Vec<f64>,
}

/// What an AeroDyn primary input file says about airfoils.
#[derive(Debug, Clone, PartialEq)]
pub struct AeroDynPrimary {
    pub path: PathBuf,
    pub columns: Columns,
    /// AFNames in order, resolved against the primary file's folder.
    pub airfoil_files: Vec<PathBuf>,
}

/// The rotor numbers of an ElastoDyn primary file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElastoDynRotor {
    /// HubRad, m.
    pub hub_radius_m: f64,
    /// NumBl.
    pub blades: u32,
}

fn read(path: &Path) -> Result<String, AeroDynError> {
    std::fs::read_to_string(path).map_err(|cause| AeroDynError::Read {
        path: path.into(),
        cause,
    })
}

/// Whitespace-separated tokens of a line, a double-quoted token kept whole without its quotes; a
/// token starting with `!` ends the line (a trailing comment).
fn tokens(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line.trim_start();
    while !rest.is_empty() && !rest.starts_with('!') {
        let (token, tail) = if let Some(quoted) = rest.strip_prefix('"') {
            match quoted.find('"') {
                Some(end) => (&quoted[..end], &quoted[end + 1..]),
                None => (quoted, ""),
            }
        } else {
            let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
            (&rest[..end], &rest[end..])
        };
        out.push(token.to_string());
        rest = tail.trim_start();
    }
    out
}

/// A line that holds nothing to read: blank, or a `!` comment.
fn is_comment(line: &str) -> bool {
    let t = line.trim_start();
    t.is_empty() || t.starts_with('!')
}

/// A number as Fortran list input writes it (`1.5`, `1.5E+01`, `1.5D+01`).
fn number(s: &str) -> Option<f64> {
    s.parse::<f64>()
        .ok()
        .or_else(|| s.replace(['D', 'd'], "E").parse().ok())
        .filter(|x: &f64| x.is_finite())
}

/// The lines of one file with the error constructors that name it.
struct Source {
    path: PathBuf,
    lines: Vec<String>,
}

impl Source {
    fn open(path: &Path) -> Result<Self, AeroDynError> {
        Ok(Self {
            path: path.into(),
            lines: read(path)?.lines().map(str::to_string).collect(),
        })
    }

    fn field(&self, line: usize, field: &str, what: impl Into<String>) -> AeroDynError {
        AeroDynError::Field {
            path: self.path.clone(),
            line,
            field: field.into(),
            what: what.into(),
        }
    }

    fn file(&self, what: impl Into<String>) -> AeroDynError {
        AeroDynError::File {
            path: self.path.clone(),
            what: what.into(),
        }
    }

    /// The first `value label` line at or after index `from` whose label is `label` (any case):
    /// (its index, its value).
    fn find(&self, from: usize, label: &str) -> Option<(usize, String)> {
        (from..self.lines.len()).find_map(|i| {
            let line = &self.lines[i];
            if is_comment(line) || line.trim_start().starts_with('@') {
                return None;
            }
            let t = tokens(line);
            (t.len() >= 2 && t[1].eq_ignore_ascii_case(label)).then(|| (i, t[0].clone()))
        })
    }

    /// Like `find`, an error naming the label when there is none.
    fn require(&self, from: usize, label: &str) -> Result<(usize, String), AeroDynError> {
        self.find(from, label)
            .ok_or_else(|| self.file(format!("no {label} line (a line `value {label}`)")))
    }

    fn number(&self, i: usize, field: &str, value: &str) -> Result<f64, AeroDynError> {
        number(value).ok_or_else(|| self.field(i + 1, field, format!("{value:?} is not a number")))
    }

    /// A whole number ≥ `min`.
    fn count(&self, i: usize, field: &str, value: &str, min: usize) -> Result<usize, AeroDynError> {
        value
            .parse::<usize>()
            .ok()
            .filter(|&n| n >= min)
            .ok_or_else(|| self.field(i + 1, field, format!("{value:?} is not a whole number ≥ {min}")))
    }

    /// Indices of the next `n` lines after index `from` that are neither blank nor comments.
    fn rows(&self, from: usize, n: usize, what: &str) -> Result<Vec<usize>, AeroDynError> {
        let rows: Vec<usize> = (from..self.lines.len())
            .filter(|&i| !is_comment(&self.lines[i]))
            .take(n)
            .collect();
        if rows.len() < n {
            return Err(self.file(format!("{what}: expected {n} rows, the file ends after {}", rows.len())));
        }
        Ok(rows)
    }
}

/// Reads an AeroDyn v15 blade file.
pub fn read_blade(path: &Path) -> Result<AeroDynBlade, AeroDynError> {
    let src = Source::open(path)?;
    let title = src.lines.get(1).map_or("", |l| l.trim()).to_string();
    let (at, value) = src.require(2, "NumBlNds")?;
    let count = src.count(at, "NumBlNds", &value, 2)?;
    let names_at = at + 1;
    let names = src
        .lines
        .get(names_at)
        .map(|l| tokens(l))
        .ok_or_else(|| src.file("no line of column names after NumBlNds"))?;
    let column = |name: &str| names.iter().position(|n| n.eq_ignore_ascii_case(name));
    let required = ["BlSpn", "BlCrvAC", "BlSwpAC", "BlTwist", "BlChord", "BlAFID"];
    let mut index = [0; 6];
    for (k, name) in required.iter().enumerate() {
        index[k] = column(name).ok_or_else(|| {
            src.field(
                names_at + 1,
                name,
                format!("no such column among the names {}", names.join(" ")),
            )
        })?;
    }
    let [span, curve, sweep, twist, chord, afid] = index;
    let angle = column("BlCrvAng");
    let mut nodes: Vec<AeroDynNode> = Vec::with_capacity(count);
    for i in src.rows(names_at + 2, count, &format!("NumBlNds = {count}"))? {
        let fields = tokens(&src.lines[i]);
        let get = |k: usize, name: &str| -> Result<f64, AeroDynError> {
            let v = fields.get(k).ok_or_else(|| {
                src.field(
                    i + 1,
                    name,
                    format!(
                        "missing: the row has {} fields, {name} is column {}",
                        fields.len(),
                        k + 1
                    ),
                )
            })?;
            src.number(i, name, v)
        };
        let node = AeroDynNode {
            line: i + 1,
            span_m: get(span, "BlSpn")?,
            curve_ac_m: get(curve, "BlCrvAC")?,
            sweep_ac_m: get(sweep, "BlSwpAC")?,
            curve_angle_deg: angle.map(|k| get(k, "BlCrvAng")).transpose()?,
            twist_deg: get(twist, "BlTwist")?,
            chord_m: get(chord, "BlChord")?,
            airfoil_id: {
                let v = get(afid, "BlAFID")?;
                if v.fract() != 0.0 || v < 1.0 {
                    return Err(src.field(i + 1, "BlAFID", format!("{v} is not an airfoil number ≥ 1")));
                }
                v as usize
            },
        };
        match nodes.last() {
            None if node.span_m != 0.0 => {
                return Err(src.field(
                    i + 1,
                    "BlSpn",
                    format!("{} m: the first node must be at the root, 0", node.span_m),
                ));
            }
            Some(prev) if node.span_m <= prev.span_m => {
                return Err(src.field(
                    i + 1,
                    "BlSpn",
                    format!("{} m does not increase (previous node {} m)", node.span_m, prev.span_m),
                ));
            }
            _ => {}
        }
        if node.chord_m <= 0.0 {
            return Err(src.field(i + 1, "BlChord", format!("{} m: must be positive", node.chord_m)));
        }
        nodes.push(node);
    }
    Ok(AeroDynBlade {
        path: path.into(),
        title,
        nodes,
    })
}

/// Reads the first table of an AeroDyn airfoil ("AirfoilInfo" v1) file, its columns as `columns` says.
pub fn read_airfoil(path: &Path, columns: Columns) -> Result<Airfoil, AeroDynError> {
    let src = Source::open(path)?;
    let first_value = src.lines.iter().position(|l| !is_comment(l)).unwrap_or(src.lines.len());
    let description = src.lines[..first_value]
        .iter()
        .map(|l| l.trim().trim_start_matches('!').trim().to_string())
        .filter(|l| !l.is_empty() && !l.chars().all(|c| c == '-' || c == '.' || c == '='))
        .collect();
    let (tabs_at, tabs) = src.require(0, "NumTabs")?;
    let tables = src.count(tabs_at, "NumTabs", &tabs, 1)?;
    let interp_order = match src.find(0, "InterpOrd").filter(|(i, _)| *i < tabs_at) {
        None => 1,
        Some((_, v)) if v.eq_ignore_ascii_case("default") => 1,
        Some((i, v)) => match v.as_str() {
            "1" => 1,
            "3" => 3,
            _ => return Err(src.field(i + 1, "InterpOrd", format!("{v:?}: expected 1, 3 or DEFAULT"))),
        },
    };
    let (alf_at, alf) = src.require(tabs_at + 1, "NumAlf")?;
    let rows = src.count(alf_at, "NumAlf", &alf, 1)?;
    let table_head = tabs_at + 1..alf_at;
    let reynolds_millions = match src.find(tabs_at + 1, "Re").filter(|(i, _)| table_head.contains(i)) {
        Some((i, v)) => Some(src.number(i, "Re", &v)?),
        None => None,
    };
    let unsteady_values = match src
        .find(tabs_at + 1, "InclUAdata")
        .filter(|(i, _)| table_head.contains(i))
    {
        Some((i, _)) => (i + 1..alf_at)
            .filter(|&k| !is_comment(&src.lines[k]) && tokens(&src.lines[k]).len() >= 2)
            .count(),
        None => 0,
    };
    let width = columns.alpha.max(columns.cl).max(columns.cd);
    let (mut alpha_deg, mut cl, mut cd) = (Vec::new(), Vec::new(), Vec::new());
    let mut extra_columns = 0;
    let row_lines = src.rows(alf_at + 1, rows, &format!("NumAlf = {rows}"))?;
    for &i in &row_lines {
        let fields = tokens(&src.lines[i]);
        let get = |k: usize, name: &str| -> Result<f64, AeroDynError> {
            let v = fields.get(k - 1).ok_or_else(|| {
                src.field(
                    i + 1,
                    name,
                    format!("missing: the row has {} fields, {name} is column {k}", fields.len()),
                )
            })?;
            src.number(i, name, v)
        };
        let a = get(columns.alpha, "Alpha")?;
        if alpha_deg.last().is_some_and(|&p| a <= p) {
            return Err(src.field(i + 1, "Alpha", format!("{a} deg does not increase")));
        }
        alpha_deg.push(a);
        cl.push(get(columns.cl, "Cl")?);
        cd.push(get(columns.cd, "Cd")?);
        extra_columns = extra_columns.max(fields.len().saturating_sub(width));
    }
    let first_row_line = row_lines[0] + 1;
    if rows == 1 {
        // constant coefficients (AeroDyn ignores the angle): the same values at both ends
        alpha_deg = vec![-180.0, 180.0];
        cl = vec![cl[0]; 2];
        cd = vec![cd[0]; 2];
    } else if alpha_deg[0] != -180.0 || alpha_deg[rows - 1] != 180.0 {
        return Err(src.field(
            first_row_line,
            "Alpha",
            format!(
                "the table runs from {} to {} deg; AeroDyn's tables (and the BEM, which meets every angle) need -180 to 180",
                alpha_deg[0],
                alpha_deg[rows - 1]
            ),
        ));
    }
    Ok(Airfoil {
        path: path.into(),
        description,
        interp_order,
        tables,
        reynolds_millions,
        unsteady_values,
        extra_columns,
        first_row_line,
        alpha_deg,
        cl,
        cd,
    })
}

/// Reads the airfoil part of an AeroDyn primary input file.
pub fn read_primary(path: &Path) -> Result<AeroDynPrimary, AeroDynError> {
    let src = Source::open(path)?;
    let column = |label: &str, default: usize| -> Result<usize, AeroDynError> {
        match src.find(0, label) {
            Some((i, v)) => src.count(i, label, &v, 1),
            None => Ok(default),
        }
    };
    let columns = Columns {
        alpha: column("InCol_Alfa", 1)?,
        cl: column("InCol_Cl", 2)?,
        cd: column("InCol_Cd", 3)?,
    };
    let (at, n) = src.require(0, "NumAFfiles")?;
    let n = src.count(at, "NumAFfiles", &n, 1)?;
    let folder = path.parent().unwrap_or(Path::new(""));
    let airfoil_files = src
        .rows(at + 1, n, &format!("NumAFfiles = {n}"))?
        .into_iter()
        .map(|i| {
            let name = tokens(&src.lines[i]).into_iter().next().unwrap_or_default();
            // AeroDyn's own files are written on Windows too
            folder.join(name.replace('\\', "/"))
        })
        .collect();
    Ok(AeroDynPrimary {
        path: path.into(),
        columns,
        airfoil_files,
    })
}

/// Reads HubRad and NumBl of an ElastoDyn primary input file.
pub fn read_elastodyn(path: &Path) -> Result<ElastoDynRotor, AeroDynError> {
    let src = Source::open(path)?;
    let (i, v) = src.require(0, "HubRad")?;
    let hub_radius_m = src.number(i, "HubRad", &v)?;
    if hub_radius_m < 0.0 {
        return Err(src.field(i + 1, "HubRad", format!("{hub_radius_m} m: must be ≥ 0")));
    }
    let (i, v) = src.require(0, "NumBl")?;
    let blades = src.count(i, "NumBl", &v, 1)? as u32;
    Ok(ElastoDynRotor { hub_radius_m, blades })
}

#[cfg(test)]
mod tests {
    use super::super::samples::{AIRFOIL, BLADE, dir, put};
    use super::*;

    #[test]
    fn blade_columns_are_found_by_name() {
        let d = dir("names");
        let b = read_blade(&put(&d, "blade.dat", BLADE)).unwrap();
        assert_eq!(b.title, "A test blade");
        assert_eq!(b.nodes.len(), 3);
        let n = b.nodes[2];
        assert_eq!(
            (
                n.line,
                n.span_m,
                n.curve_ac_m,
                n.sweep_ac_m,
                n.curve_angle_deg,
                n.twist_deg,
                n.chord_m,
                n.airfoil_id
            ),
            (9, 10.0, -0.2, 0.05, Some(-1.5), 0.0, 1.0, 2)
        );
        assert_eq!(b.nodes[0].twist_deg, 13.308);
        // another order, without BlCrvAng, and Fortran's D exponent
        let text = "x\ny\nz\n 2 NumBlNds\nBlAFID BlChord BlTwist BlSwpAC BlCrvAC BlSpn\n(-) (m) (deg) (m) (m) (m)\n\
                    1 2.0 7.0 0 0 0\n1 1.0 1.0 0 0 2.5D+01\n";
        let b = read_blade(&put(&d, "other.dat", text)).unwrap();
        assert_eq!(
            (b.nodes[1].span_m, b.nodes[1].twist_deg, b.nodes[1].curve_angle_deg),
            (25.0, 1.0, None)
        );
    }

    #[test]
    fn airfoil_keeps_the_first_table_and_drops_the_rest() {
        let d = dir("airfoil");
        let a = read_airfoil(&put(&d, "af.dat", AIRFOIL), Columns::default()).unwrap();
        assert_eq!((a.interp_order, a.tables, a.reynolds_millions), (1, 2, Some(0.75)));
        assert_eq!((a.unsteady_values, a.extra_columns, a.first_row_line), (3, 1, 17));
        assert_eq!(a.alpha_deg, [-180.0, 0.0, 10.0, 180.0]);
        assert_eq!((a.cl[2], a.cd[2]), (1.2, 0.02));
        assert_eq!(
            a.description,
            [
                "------------ AirfoilInfo v1.01.x Input File ------",
                "A test airfoil, two tables"
            ]
        );
        // the primary file's columns: C_d before C_l
        let swapped = read_airfoil(&d.join("af.dat"), Columns { alpha: 1, cl: 3, cd: 2 }).unwrap();
        assert_eq!((swapped.cl[2], swapped.cd[2]), (0.02, 1.2));
    }

    #[test]
    fn primary_and_elastodyn_files() {
        let d = dir("primary");
        let text = "------- AERODYN v15 INPUT FILE ----\ntitle\n          1   InCol_Alfa   - alpha column\n\
                    3   InCol_Cl\n          2   InCol_Cd\n          2   NumAFfiles   - Number of airfoil files\n\
                    \"af\\a.dat\"    AFNames            - names\n! a comment between\n\"b.dat\"\n";
        let p = read_primary(&put(&d, "AeroDyn.dat", text)).unwrap();
        assert_eq!(p.columns, Columns { alpha: 1, cl: 3, cd: 2 });
        assert_eq!(p.airfoil_files, [d.join("af/a.dat"), d.join("b.dat")]);
        let e = read_elastodyn(&put(
            &d,
            "ElastoDyn.dat",
            "x\n          3   NumBl  - blades\n       1.5   HubRad - m\n",
        ))
        .unwrap();
        assert_eq!(
            e,
            ElastoDynRotor {
                hub_radius_m: 1.5,
                blades: 3
            }
        );
    }

    #[test]
    fn errors_name_file_line_and_field() {
        let d = dir("errors");
        let bad = |name: &str, text: String| read_blade(&put(&d, name, &text)).unwrap_err().to_string();
        let e = bad("chord.dat", BLADE.replace("1.5            2", "1.5x           2"));
        assert!(e.contains("chord.dat line 8, BlChord: \"1.5x\" is not a number"), "{e}");
        let e = bad("twist.dat", BLADE.replace("BlTwist", "Twist"));
        assert!(e.contains("twist.dat line 5, BlTwist: no such column"), "{e}");
        let e = bad("root.dat", BLADE.replace("0.0000000E+00  0.0", "0.5  0.0"));
        assert!(
            e.contains("root.dat line 7, BlSpn: 0.5 m: the first node must be at the root"),
            "{e}"
        );
        let e = bad("short.dat", BLADE.replace("  3   NumBlNds", "  4   NumBlNds"));
        assert!(
            e.contains("short.dat: NumBlNds = 4: expected 4 rows, the file ends after 3"),
            "{e}"
        );
        let e = bad("afid.dat", BLADE.replace("1.0            2", "1.0            0"));
        assert!(e.contains("afid.dat line 9, BlAFID: 0 is not an airfoil number"), "{e}");

        let bad = |name: &str, text: String| {
            read_airfoil(&put(&d, name, &text), Columns::default())
                .unwrap_err()
                .to_string()
        };
        let e = bad(
            "rising.dat",
            AIRFOIL.replace("     10.00    1.200", "     -1.00    1.200"),
        );
        assert!(e.contains("rising.dat line 19, Alpha: -1 deg does not increase"), "{e}");
        let e = bad("cd.dat", AIRFOIL.replace("0.0200  -0.0600", "-  -0.0600"));
        assert!(e.contains("cd.dat line 19, Cd: \"-\" is not a number"), "{e}");
        let e = bad(
            "range.dat",
            AIRFOIL.replace(
                "    180.00    0.000   0.5000   0.0000\n! data",
                "     90.00    0.000   0.5000   0.0000\n! data",
            ),
        );
        assert!(
            e.contains("range.dat line 17, Alpha: the table runs from -180 to 90 deg"),
            "{e}"
        );
        let e = bad("tabs.dat", AIRFOIL.replace("NumTabs", "NumTables"));
        assert!(e.contains("tabs.dat: no NumTabs line"), "{e}");
        let e = bad(
            "interp.dat",
            AIRFOIL.replace("\"DEFAULT\"     InterpOrd", "2   InterpOrd"),
        );
        assert!(
            e.contains("interp.dat line 4, InterpOrd: \"2\": expected 1, 3 or DEFAULT"),
            "{e}"
        );
    }
}
