//! Writing a blade folder in the format [`Blade::load`](super::Blade::load) reads, from the numbers in
//! the files' own units (degrees, metres), so that nothing is lost on the way: every number is printed
//! as the shortest decimal that reads back as the same `f64`.

use super::BladeError;
use std::path::{Path, PathBuf};

/// One line of `blade.csv`'s node table.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeRow {
    pub span_m: f64,
    pub chord_m: f64,
    pub twist_deg: f64,
    /// The polar's name: its file is `<airfoil>.csv` beside `blade.csv`.
    pub airfoil: String,
}

/// One polar file: angles of attack rising from −180° to 180° with lift and drag coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct PolarTable {
    pub name: String,
    /// Comment lines at the top of the file (without the `#`).
    pub comments: Vec<String>,
    pub alpha_deg: Vec<f64>,
    pub cl: Vec<f64>,
    pub cd: Vec<f64>,
}

/// What a blade folder holds, as written.
#[derive(Debug, Clone, PartialEq)]
pub struct BladeFolder {
    /// Comment lines at the top of `blade.csv` (without the `#`).
    pub comments: Vec<String>,
    pub hub_radius_m: f64,
    /// Written as `tip_radius_m` when given; without it a reader takes hub radius + last span.
    pub tip_radius_m: Option<f64>,
    pub blades: u32,
    pub nodes: Vec<NodeRow>,
    pub polars: Vec<PolarTable>,
}

/// A comment line: one line, whatever the text held.
fn comment(text: &str) -> String {
    format!("# {}\n", text.replace(['\r', '\n'], " "))
}

impl BladeFolder {
    /// `blade.csv`'s text.
    pub fn blade_csv(&self) -> String {
        let mut s: String = self.comments.iter().map(|c| comment(c)).collect();
        s += &format!("hub_radius_m,{}\n", self.hub_radius_m);
        if let Some(tip) = self.tip_radius_m {
            s += &format!("tip_radius_m,{tip}\n");
        }
        s += &format!("blades,{}\nspan_m,chord_m,twist_deg,airfoil\n", self.blades);
        for n in &self.nodes {
            s += &format!("{},{},{},{}\n", n.span_m, n.chord_m, n.twist_deg, n.airfoil);
        }
        s
    }

    /// Writes `blade.csv` and one `<name>.csv` per polar into `dir` (created if missing), replacing
    /// files of those names; returns the paths written.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>, BladeError> {
        std::fs::create_dir_all(dir).map_err(|cause| BladeError::Write {
            path: dir.into(),
            cause,
        })?;
        let mut written = Vec::new();
        let mut put = |path: PathBuf, text: String| {
            std::fs::write(&path, text).map_err(|cause| BladeError::Write {
                path: path.clone(),
                cause,
            })?;
            written.push(path);
            Ok::<_, BladeError>(())
        };
        for p in &self.polars {
            put(dir.join(format!("{}.csv", p.name)), p.csv())?;
        }
        put(dir.join("blade.csv"), self.blade_csv())?;
        Ok(written)
    }
}

impl PolarTable {
    /// The polar file's text.
    pub fn csv(&self) -> String {
        let mut s: String = self.comments.iter().map(|c| comment(c)).collect();
        s += "alpha_deg,cl,cd\n";
        for ((a, l), d) in self.alpha_deg.iter().zip(&self.cl).zip(&self.cd) {
            s += &format!("{a},{l},{d}\n");
        }
        s
    }
}
