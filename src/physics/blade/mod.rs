//! Blade geometry and airfoil polars of the blade-element momentum rotor, read from CSV files.
//!
//! A blade is a folder: `blade.csv` (`hub_radius_m,<m>`, optionally `tip_radius_m,<m>`, and
//! `blades,<n>` lines, then the header `span_m,chord_m,twist_deg,airfoil` and one line per node, span
//! measured from the blade root) and one `<airfoil>.csv` per airfoil named there (header
//! `alpha_deg,cl,cd`, angles of attack rising and covering −180…180°). Lines starting with `#` are
//! comments. Without `tip_radius_m` the tip is the last node (hub radius + its span), as in files
//! written before the field existed. Every error names the file and the line.
//!
//! `aerodyn` reads OpenFAST AeroDyn v15 blade and airfoil files into such a folder, `write` writes one.

pub mod aerodyn;
pub mod write;

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// A blade or polar file that cannot be used, naming the file and (where there is one) the line.
#[derive(Debug, thiserror::Error)]
pub enum BladeError {
    /// (The I/O error is part of the message, not a `source`, so an error chain prints it once.)
    #[error("blade data {}: {cause}", path.display())]
    Read { path: PathBuf, cause: std::io::Error },
    #[error("blade data {} line {line}: {what}", path.display())]
    Line { path: PathBuf, line: usize, what: String },
    #[error("blade data {}: {what}", path.display())]
    File { path: PathBuf, what: String },
    #[error("blade data {}: cannot write: {cause}", path.display())]
    Write { path: PathBuf, cause: std::io::Error },
}

/// Lift and drag coefficients over the angle of attack, interpolated linearly (as AeroDyn's
/// `InterpOrd = 1`; a spline would add wiggles between the coarse post-stall points).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Polar {
    pub name: String,
    /// Angles of attack, rad, strictly rising, from −π to π.
    pub alpha: Vec<f64>,
    pub cl: Vec<f64>,
    pub cd: Vec<f64>,
}

impl Polar {
    /// The table segment [i, i + 1] that holds `alpha` (wrapped into [−π, π]) and the weight of i + 1.
    fn segment(&self, alpha: f64) -> (usize, f64) {
        let a = wrap(alpha);
        let i = self.alpha.partition_point(|&x| x <= a).clamp(1, self.alpha.len() - 1) - 1;
        let (a0, a1) = (self.alpha[i], self.alpha[i + 1]);
        (i, ((a - a0) / (a1 - a0)).clamp(0.0, 1.0))
    }

    /// (C_l, C_d) at `alpha` (rad).
    pub fn at(&self, alpha: f64) -> (f64, f64) {
        let (i, w) = self.segment(alpha);
        (
            self.cl[i] + w * (self.cl[i + 1] - self.cl[i]),
            self.cd[i] + w * (self.cd[i + 1] - self.cd[i]),
        )
    }

    /// Slope dC_l/dα (1/rad) of the table segment that holds `alpha` (rad).
    pub fn lift_slope(&self, alpha: f64) -> f64 {
        let (i, _) = self.segment(alpha);
        (self.cl[i + 1] - self.cl[i]) / (self.alpha[i + 1] - self.alpha[i])
    }
}

/// Angle in [−π, π).
fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(2.0 * PI) - PI
}

/// One blade node: span from the root, chord and twist (positive twist lowers the angle of attack),
/// and the index of its polar.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub span: f64,
    pub chord: f64,
    /// rad
    pub twist: f64,
    pub airfoil: usize,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Blade {
    pub name: String,
    pub hub_radius: f64,
    /// Tip radius as blade.csv's `tip_radius_m` gives it, m; None: the last node's radius.
    pub tip: Option<f64>,
    pub blades: u32,
    pub nodes: Vec<Node>,
    pub polars: Vec<Polar>,
}

/// Where a BEM evaluates the blade: radius from the rotor axis, and the node's chord, twist, polar.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Station {
    pub radius: f64,
    pub chord: f64,
    pub twist: f64,
    pub airfoil: usize,
}

/// A node within this fraction of the tip radius from it is at the tip (a `tip_radius_m` written with
/// fewer digits than hub radius + span carries).
const AT_TIP: f64 = 1e-9;

impl Blade {
    /// Tip radius: `tip_radius_m` when the file gives it, otherwise hub radius plus the span of the
    /// last node.
    pub fn tip_radius(&self) -> f64 {
        self.tip
            .unwrap_or_else(|| self.hub_radius + self.nodes.last().map_or(0.0, |n| n.span))
    }

    /// The same blade scaled geometrically to tip radius `radius`: hub radius, spans and chords by
    /// one factor; twist and airfoils unchanged, so C_p(λ, β) is the reference blade's.
    pub fn scaled(&self, radius: f64) -> Blade {
        let s = radius / self.tip_radius();
        Blade {
            name: format!("{} scaled to R = {radius} m", self.name),
            hub_radius: self.hub_radius * s,
            tip: self.tip.map(|_| radius),
            nodes: self
                .nodes
                .iter()
                .map(|n| Node {
                    span: n.span * s,
                    chord: n.chord * s,
                    ..*n
                })
                .collect(),
            ..self.clone()
        }
    }

    /// Stations at the nodes. A node at the hub or the tip has a vanishing Prandtl loss factor, which
    /// makes the momentum balance degenerate there, so such an end node is moved inward, keeping its
    /// chord and twist, by CCBlade's rule (wisdem 4.2.9, `ccblade.py`, `CCBlade.__init__`): with
    /// x = (r − r_first)/(r_last − r_first) each node's place on the first-to-last-node distance, a
    /// first node at the hub radius moves to x = min(0.01, x₂/2), a last node at the tip radius to
    /// x = max(0.99, (x_{n−1} + 1)/2), both measured from the first node over that same distance.
    /// (CCBlade tests the ends for exact equality; here the tip within `AT_TIP`·R.) The two models thus
    /// see the same stations, with or without a node at the hub. Loads fall to zero at the hub and
    /// tip radii.
    pub fn stations(&self) -> Vec<Station> {
        let (hub, tip) = (self.hub_radius, self.tip_radius());
        let n = self.nodes.len();
        let mut r: Vec<f64> = self.nodes.iter().map(|nd| hub + nd.span).collect();
        if n >= 2 {
            let (first, last) = (r[0], r[n - 1]);
            let length = last - first;
            // spans rather than radii: the same numbers to the last bit for a blade whose first node
            // is at the root (span 0), as before this rule was CCBlade's
            let x = |i: usize| (self.nodes[i].span - self.nodes[0].span) / length;
            let at = |xi: f64| first + xi * length;
            if self.nodes[0].span <= 0.0 {
                r[0] = at(0.01f64.min(0.5 * (x(0) + x(1))));
            }
            if (last - tip).abs() <= AT_TIP * tip {
                r[n - 1] = at(0.99f64.max(0.5 * (x(n - 2) + x(n - 1))));
            }
        }
        self.nodes
            .iter()
            .zip(r)
            .map(|(nd, radius)| Station {
                radius,
                chord: nd.chord,
                twist: nd.twist,
                airfoil: nd.airfoil,
            })
            .collect()
    }

    /// Reads a blade folder (see the module documentation).
    pub fn load(dir: &Path) -> Result<Blade, BladeError> {
        let path = dir.join("blade.csv");
        let text = read(&path)?;
        let err = |line: usize, what: String| BladeError::Line {
            path: path.clone(),
            line,
            what,
        };
        let (mut hub_radius, mut tip, mut blades, mut header) = (None, None, None, false);
        let mut nodes = Vec::new();
        let mut names: Vec<String> = Vec::new();
        for (k, fields) in data_lines(&text) {
            if !header {
                match fields.as_slice() {
                    ["hub_radius_m", v] => hub_radius = Some(number(v, "hub_radius_m").map_err(|w| err(k, w))?),
                    ["tip_radius_m", v] => tip = Some((k, number(v, "tip_radius_m").map_err(|w| err(k, w))?)),
                    ["blades", v] => {
                        blades = Some(
                            v.parse::<u32>()
                                .ok()
                                .filter(|&b| b >= 1)
                                .ok_or_else(|| err(k, format!("blades = {v:?}: expected a whole number ≥ 1")))?,
                        )
                    }
                    ["span_m", "chord_m", "twist_deg", "airfoil"] => header = true,
                    _ => {
                        return Err(err(
                            k,
                            "expected hub_radius_m,<m>, tip_radius_m,<m>, blades,<n> or the header \
                             span_m,chord_m,twist_deg,airfoil"
                                .into(),
                        ));
                    }
                }
                continue;
            }
            let [span, chord, twist, airfoil] = fields.as_slice() else {
                return Err(err(
                    k,
                    format!(
                        "expected 4 fields span_m,chord_m,twist_deg,airfoil, found {}",
                        fields.len()
                    ),
                ));
            };
            let span = number(span, "span_m").map_err(|w| err(k, w))?;
            let chord = number(chord, "chord_m").map_err(|w| err(k, w))?;
            let twist = number(twist, "twist_deg").map_err(|w| err(k, w))?.to_radians();
            if chord <= 0.0 || span < 0.0 {
                return Err(err(k, "span must be ≥ 0 and chord > 0".into()));
            }
            if nodes.last().is_some_and(|n: &Node| span <= n.span) {
                return Err(err(k, format!("span {span} m does not increase")));
            }
            if airfoil.is_empty() || airfoil.contains(['/', '\\']) {
                return Err(err(
                    k,
                    format!("airfoil {airfoil:?}: expected a file name without folder"),
                ));
            }
            let index = match names.iter().position(|n| n == airfoil) {
                Some(i) => i,
                None => {
                    names.push(airfoil.to_string());
                    names.len() - 1
                }
            };
            nodes.push(Node {
                span,
                chord,
                twist,
                airfoil: index,
            });
        }
        let file = |what: &str| BladeError::File {
            path: path.clone(),
            what: what.into(),
        };
        let hub_radius = hub_radius.ok_or_else(|| file("no hub_radius_m line"))?;
        let blades = blades.ok_or_else(|| file("no blades line"))?;
        if nodes.len() < 2 {
            return Err(file("fewer than two blade nodes"));
        }
        if hub_radius < 0.0 {
            return Err(file("hub_radius_m must be ≥ 0"));
        }
        let last = hub_radius + nodes[nodes.len() - 1].span;
        if let Some((k, r)) = tip
            && r < last * (1.0 - AT_TIP)
        {
            return Err(err(
                k,
                format!("tip_radius_m = {r} m lies inside the last node (hub radius + span = {last} m)"),
            ));
        }
        let polars = names
            .iter()
            .map(|n| load_polar(&dir.join(format!("{n}.csv")), n))
            .collect::<Result<_, _>>()?;
        let name = dir
            .file_name()
            .map_or_else(|| dir.display().to_string(), |n| n.to_string_lossy().into());
        Ok(Blade {
            name,
            hub_radius,
            tip: tip.map(|(_, r)| r),
            blades,
            nodes,
            polars,
        })
    }
}

fn read(path: &Path) -> Result<String, BladeError> {
    std::fs::read_to_string(path).map_err(|cause| BladeError::Read {
        path: path.into(),
        cause,
    })
}

/// Non-empty, non-comment lines as (1-based line number, trimmed comma-separated fields).
fn data_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(k, line)| {
        let t = line.trim();
        (!t.is_empty() && !t.starts_with('#')).then(|| (k + 1, t.split(',').map(str::trim).collect()))
    })
}

fn number(s: &str, what: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("{what} = {s:?} is not a number"))
}

/// Reads one polar file (header `alpha_deg,cl,cd`).
pub fn load_polar(path: &Path, name: &str) -> Result<Polar, BladeError> {
    let text = read(path)?;
    let err = |line: usize, what: String| BladeError::Line {
        path: path.into(),
        line,
        what,
    };
    let (mut alpha, mut cl, mut cd) = (Vec::new(), Vec::new(), Vec::new());
    let mut header = false;
    for (k, fields) in data_lines(&text) {
        if !header {
            if fields.as_slice() != ["alpha_deg", "cl", "cd"] {
                return Err(err(k, "expected the header alpha_deg,cl,cd".into()));
            }
            header = true;
            continue;
        }
        let [a, l, d] = fields.as_slice() else {
            return Err(err(
                k,
                format!("expected 3 fields alpha_deg,cl,cd, found {}", fields.len()),
            ));
        };
        let a = number(a, "alpha_deg").map_err(|w| err(k, w))?;
        if alpha.last().is_some_and(|&p: &f64| a.to_radians() <= p) {
            return Err(err(k, format!("alpha {a} deg does not increase")));
        }
        alpha.push(a.to_radians());
        cl.push(number(l, "cl").map_err(|w| err(k, w))?);
        cd.push(number(d, "cd").map_err(|w| err(k, w))?);
    }
    // the BEM meets every angle of attack (a parked or reversing rotor), so the table must cover them
    let covers = alpha.len() >= 2 && alpha[0] <= -PI + 1e-9 && alpha[alpha.len() - 1] >= PI - 1e-9;
    if !covers {
        return Err(BladeError::File {
            path: path.into(),
            what: "the polar must cover alpha from -180 to 180 deg".into(),
        });
    }
    Ok(Polar {
        name: name.into(),
        alpha,
        cl,
        cd,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("windrive-blade-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    const POLAR: &str = "alpha_deg,cl,cd\n-180,0,0.5\n0,1,0.01\n180,0,0.5\n";

    #[test]
    fn polar_interpolates_linearly_and_wraps() {
        let d = dir("polar");
        std::fs::write(d.join("p.csv"), POLAR).unwrap();
        let p = load_polar(&d.join("p.csv"), "p").unwrap();
        let (cl, cd) = p.at(90f64.to_radians());
        assert!((cl - 0.5).abs() < 1e-12 && (cd - 0.255).abs() < 1e-12);
        // 270° is −90°
        assert!((p.at(270f64.to_radians()).0 - 0.5).abs() < 1e-12);
        assert!((p.lift_slope(0.1) + 1.0 / PI).abs() < 1e-12);
    }

    #[test]
    fn errors_name_file_and_line() {
        let d = dir("bad");
        std::fs::write(d.join("p.csv"), "alpha_deg,cl,cd\n-180,0,0.5\n10,x,0.1\n180,0,0.5\n").unwrap();
        let e = load_polar(&d.join("p.csv"), "p").unwrap_err().to_string();
        assert!(e.contains("p.csv line 3") && e.contains("cl = \"x\""), "{e}");
        std::fs::write(d.join("p.csv"), "alpha_deg,cl,cd\n-10,0,0.5\n10,1,0.1\n").unwrap();
        let e = load_polar(&d.join("p.csv"), "p").unwrap_err().to_string();
        assert!(e.contains("-180 to 180"), "{e}");
        std::fs::write(
            d.join("blade.csv"),
            "# c\nhub_radius_m,1\nblades,3\nspan_m,chord_m,twist_deg,airfoil\n0,1,5,p\n10,1\n",
        )
        .unwrap();
        let e = Blade::load(&d).unwrap_err().to_string();
        assert!(e.contains("blade.csv line 6") && e.contains("found 2"), "{e}");
        std::fs::write(
            d.join("blade.csv"),
            "hub_radius_m,1\nblades,3\nspan_m,chord_m,twist_deg,airfoil\n0,1,5,p\n10,1,0,missing\n",
        )
        .unwrap();
        std::fs::write(d.join("p.csv"), POLAR).unwrap();
        let e = Blade::load(&d).unwrap_err().to_string();
        assert!(e.contains("missing.csv"), "{e}");
    }

    #[test]
    fn scaling_keeps_proportions_and_stations_avoid_the_ends() {
        let d = dir("scale");
        std::fs::write(d.join("p.csv"), POLAR).unwrap();
        std::fs::write(
            d.join("blade.csv"),
            "hub_radius_m,2\nblades,3\nspan_m,chord_m,twist_deg,airfoil\n0,2,10,p\n4,1.5,5,p\n8,1,0,p\n",
        )
        .unwrap();
        let b = Blade::load(&d).unwrap();
        assert_eq!(b.tip_radius(), 10.0);
        let s = b.scaled(20.0);
        assert_eq!((s.hub_radius, s.tip_radius(), s.nodes[1].chord), (4.0, 20.0, 3.0));
        let st = b.stations();
        // 1 % and 99 % of the 8 m span
        assert!((st[0].radius - 2.08).abs() < 1e-12 && (st[2].radius - 9.92).abs() < 1e-12);
        assert_eq!(st[1].radius, 6.0);
    }

    #[test]
    fn tip_radius_field_is_optional_and_checked() {
        let d = dir("tip");
        std::fs::write(d.join("p.csv"), POLAR).unwrap();
        let blade = |tip: &str| {
            std::fs::write(
                d.join("blade.csv"),
                format!(
                    "hub_radius_m,2\n{tip}blades,3\nspan_m,chord_m,twist_deg,airfoil\n0,2,10,p\n4,1.5,5,p\n8,1,0,p\n"
                ),
            )
            .unwrap();
            Blade::load(&d)
        };
        let b = blade("tip_radius_m,12\n").unwrap();
        assert_eq!((b.tip, b.tip_radius()), (Some(12.0), 12.0));
        // the last node is 2 m short of the tip: it stays where it is
        assert_eq!(b.stations()[2].radius, 10.0);
        let s = b.scaled(24.0);
        assert_eq!((s.tip_radius(), s.hub_radius, s.nodes[2].span), (24.0, 4.0, 16.0));
        assert_eq!(blade("").unwrap().tip_radius(), 10.0);
        let e = blade("tip_radius_m,9.5\n").unwrap_err().to_string();
        assert!(
            e.contains("blade.csv line 2") && e.contains("inside the last node"),
            "{e}"
        );
    }

    /// CCBlade's rule: the end nodes move over the first-to-last-node distance, so a blade without a
    /// node at the hub keeps its first node and moves its tip node to first + 0.99·(last − first).
    #[test]
    fn end_stations_follow_ccblade_without_a_hub_node() {
        let d = dir("nohub");
        std::fs::write(d.join("p.csv"), POLAR).unwrap();
        std::fs::write(
            d.join("blade.csv"),
            "hub_radius_m,2\nblades,3\nspan_m,chord_m,twist_deg,airfoil\n1,2,10,p\n4,1.5,5,p\n8,1,0,p\n",
        )
        .unwrap();
        let st = Blade::load(&d).unwrap().stations();
        assert_eq!(st[0].radius, 3.0);
        // 3 + 0.99·7, not the hub-to-tip 2 + 0.99·8 = 9.92
        assert!((st[2].radius - 9.93).abs() < 1e-12, "{}", st[2].radius);
    }

    /// The rule before it was CCBlade's (hub-to-tip distance), which every shipped blade was run with.
    fn hub_to_tip_stations(b: &Blade) -> Vec<f64> {
        let (r0, r1) = (b.hub_radius, b.tip_radius());
        let n = b.nodes.len();
        let x: Vec<f64> = b.nodes.iter().map(|nd| nd.span / (r1 - r0)).collect();
        let mut r: Vec<f64> = b.nodes.iter().map(|nd| r0 + nd.span).collect();
        let at = |xi: f64| r0 + xi * (r1 - r0);
        if x[0] <= 0.0 {
            r[0] = at(0.01f64.min(0.5 * (x[0] + x[1])));
        }
        if x[n - 1] >= 1.0 {
            r[n - 1] = at(0.99f64.max(0.5 * (x[n - 2] + x[n - 1])));
        }
        r
    }

    /// On a blade with nodes at the hub and the tip the two rules agree to the last bit: the WindPACT
    /// blade as shipped and scaled to every preset's radius keeps its stations.
    #[test]
    fn windpact_stations_are_unchanged_to_the_bit() {
        use crate::physics::drivetrain::Drivetrain;
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fmus/rotor/resources/blades/windpact-1.5mw");
        let b = Blade::load(&dir).unwrap();
        let mut radii = vec![b.tip_radius()];
        for p in ["A", "B", "C", "D", "P"] {
            radii.push(crate::physics::rotor::preset_rotor(&Drivetrain::preset(p).unwrap(), p).0);
        }
        for radius in radii {
            let s = b.scaled(radius);
            let now: Vec<f64> = s.stations().iter().map(|st| st.radius).collect();
            assert_eq!(now, hub_to_tip_stations(&s), "R = {radius}");
        }
    }
}
