//! Gearbox description files: what a user writes to model their own gearbox (TOML, read with serde).
//!
//! A description is a chain, as in `torsional`: an optional rotor, stages (planetary: carrier in, sun
//! out, ring fixed or elastically mounted; parallel: gear in, pinion out), an optional generator, and
//! a shaft from each of them to the next. Units are SI, except gear geometry in mm and angles in
//! degrees, as gear data sheets give them (the field names say so). Unknown fields are errors, so a
//! misspelt key is reported with its line instead of being ignored.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Description {
    pub name: String,
    /// Where the numbers come from, and which are estimates.
    #[serde(default)]
    pub source: String,
    /// Rated power (W) and rotor speed (rpm) of the turbine this gearbox belongs to: the rated torque
    /// the static checks and outputs refer to.
    #[serde(default)]
    pub rated_power: Option<f64>,
    #[serde(default)]
    pub rated_rotor_speed_rpm: Option<f64>,
    #[serde(default)]
    pub model: ModelSettings,
    #[serde(default)]
    pub rotor: Option<Body>,
    #[serde(rename = "stage")]
    pub stages: Vec<Stage>,
    #[serde(default)]
    pub generator: Option<Body>,
}

/// How the contacts are modelled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSettings {
    /// Slices across each face width.
    #[serde(default = "default_slices")]
    pub slices: usize,
    /// `mean` (c_γ, constant) or `varying` (single/double tooth contact as the teeth roll).
    #[serde(default = "default_mesh_stiffness")]
    pub mesh_stiffness: MeshStiffnessModel,
    /// `linear` (slice springs with backlash) or `impact` (F = k·δ^e with damping ramped in).
    #[serde(default)]
    pub force_law: ForceLaw,
    /// Mesh damping ratio where a mesh gives no damping (thesis: 0.1).
    #[serde(default = "default_mesh_damping_ratio")]
    pub mesh_damping_ratio: f64,
    /// Bearing damping where a bearing gives none: c = k·t with this time constant (s).
    #[serde(default = "default_bearing_damping_time")]
    pub bearing_damping_time: f64,
    /// Shaft damping ratio where a shaft gives none (thesis: 0.006).
    #[serde(default = "default_shaft_damping_ratio")]
    pub shaft_damping_ratio: f64,
    /// Gravitational acceleration (m/s²; 0 = none) and the shaft tilt (deg, rotor end up).
    #[serde(default)]
    pub gravity: f64,
    #[serde(default)]
    pub shaft_tilt_deg: f64,
    /// Material density (kg/m³) for bodies that give a density instead of mass and inertia.
    #[serde(default = "default_density")]
    pub density: f64,
    /// `linear` (every bearing a 6×6 spring) or `lamina` (bearings that give `rollers` carry their
    /// radial, tilting and, at a contact angle, axial load by rollers cut into laminae).
    #[serde(default)]
    pub bearings: BearingModel,
}

impl Default for ModelSettings {
    fn default() -> Self {
        ModelSettings {
            slices: default_slices(),
            mesh_stiffness: default_mesh_stiffness(),
            force_law: ForceLaw::default(),
            mesh_damping_ratio: default_mesh_damping_ratio(),
            bearing_damping_time: default_bearing_damping_time(),
            shaft_damping_ratio: default_shaft_damping_ratio(),
            gravity: 0.0,
            shaft_tilt_deg: 0.0,
            density: default_density(),
            bearings: BearingModel::default(),
        }
    }
}

fn default_slices() -> usize {
    35
}
fn default_mesh_stiffness() -> MeshStiffnessModel {
    MeshStiffnessModel::Mean
}
fn default_mesh_damping_ratio() -> f64 {
    0.1
}
fn default_bearing_damping_time() -> f64 {
    1e-4
}
fn default_shaft_damping_ratio() -> f64 {
    0.006
}
fn default_density() -> f64 {
    7850.0
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MeshStiffnessModel {
    Mean,
    Varying,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum BearingModel {
    #[default]
    Linear,
    Lamina,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Contact {
    /// Cylindrical and tapered rollers: lamina load q = c·δ^(10/9).
    #[default]
    Line,
    /// Spherical rollers on a curved race: q = c·δ^1.5.
    Point,
}

/// The rolling elements of a bearing, for the lamina model: geometry in the bearing catalogue's
/// terms. Roller load per lamina q = (c/n)·δ^e, with c from ISO/TS 16281 for line contact
/// (35 948·L_we^(8/9) N/mm^(10/9), both races in series) unless `roller_stiffness` is given.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rollers {
    /// Rollers per row, Z.
    pub count: u32,
    /// Roller diameter D_we, mm.
    pub diameter_mm: f64,
    /// Effective roller length L_we, mm.
    pub length_mm: f64,
    /// Pitch diameter of the roller set d_m, mm.
    pub pitch_diameter_mm: f64,
    /// Contact angle α (0 for cylindrical rollers); its sign says which way a single row carries
    /// axial load (positive: the inner race pushed downwind loads it).
    #[serde(default)]
    pub contact_angle_deg: f64,
    /// 1, or 2 for a double row (spherical roller bearing, a tapered pair) at ±α, `row_spacing_mm`
    /// apart along the axis.
    #[serde(default = "default_rows")]
    pub rows: u32,
    #[serde(default)]
    pub row_spacing_mm: f64,
    /// Diametral radial clearance, µm (negative: preload).
    #[serde(default)]
    pub clearance_um: f64,
    /// Axial clearance of an angular-contact set, µm (negative: preload).
    #[serde(default)]
    pub axial_clearance_um: f64,
    /// Laminae per roller.
    #[serde(default = "default_laminae")]
    pub laminae: u32,
    #[serde(default)]
    pub contact: Contact,
    /// Roller–races stiffness c in q = c·δ^e, N/m^e; for point contact without the profile radii.
    #[serde(default)]
    pub roller_stiffness: Option<f64>,
    /// Point contact (balls, crowned rollers): the roller's radius in its axial plane (a ball's
    /// radius), mm, and the inner and outer raceways' radii in that plane (their grooves, concave,
    /// larger than the roller's), mm. With them the Hertz contact ellipse gives c and the race
    /// pressures. A spherical roller on its raceway conforms so closely that its ellipse outgrows
    /// the roller: give it line contact with the osculation's gap as `crowning_um` instead.
    #[serde(default)]
    pub profile_radius_mm: Option<f64>,
    #[serde(default)]
    pub race_profile_radii_mm: Option<[f64; 2]>,
    /// Profile drop at the roller ends (a parabolic crown), µm.
    #[serde(default)]
    pub crowning_um: f64,
}

impl Rollers {
    /// The effective radii of a roller's contact with the inner and the outer race, m: in the
    /// rolling plane (the races' radii normal to the contact: a tapered race is a cone, its radius
    /// / cos α; the outer race concave), and, for point contact with profile radii, across it (the
    /// convex roller in its concave groove; a flat raceway's radius is infinite).
    pub fn contact_radii(&self) -> ([f64; 2], Option<[f64; 2]>) {
        let mm = 1e-3;
        let (d, dm, cos) = (
            self.diameter_mm * mm,
            self.pitch_diameter_mm * mm,
            self.contact_angle_deg.to_radians().cos(),
        );
        let roller = 0.5 * d;
        let rolling = [
            1.0 / (1.0 / roller + 1.0 / (0.5 * (dm - d * cos) / cos)),
            1.0 / (1.0 / roller - 1.0 / (0.5 * (dm + d * cos) / cos)),
        ];
        let across = match (self.contact, self.profile_radius_mm, self.race_profile_radii_mm) {
            (Contact::Point, Some(p), Some(races)) => {
                Some(races.map(|race| 1.0 / (1.0 / (p * mm) - 1.0 / (race * mm))))
            }
            _ => None,
        };
        (rolling, across)
    }
}

fn default_rows() -> u32 {
    1
}
fn default_laminae() -> u32 {
    10
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum ForceLaw {
    #[default]
    Linear,
    /// F = k·δ^exponent + c(δ)·δ̇, c ramped from 0 to the mesh damping over `penetration` (m)
    /// (paper Table 5: e = 1.5, 0.1 mm); k is the mesh stiffness read as N/m^exponent.
    Impact { exponent: f64, penetration: f64 },
}

/// A rigid body: mass and inertias, or (gears only) a density estimate from the gear blank.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// kg; None = a solid cylinder of the reference diameter and face width (gears only), or from
    /// the polar inertia as a solid cylinder of the reference radius when that is given.
    #[serde(default)]
    pub mass: Option<f64>,
    /// About the shaft axis, kg·m².
    #[serde(default)]
    pub polar_inertia: Option<f64>,
    /// About a transverse axis through the centre, kg·m²; None = solid cylinder estimate.
    #[serde(default)]
    pub transverse_inertia: Option<f64>,
    /// Bearings to the housing (planets: to the carrier pin).
    #[serde(default)]
    pub bearings: Vec<Bearing>,
    /// A full diagonal support at the centre instead of bearing geometry.
    #[serde(default)]
    pub support: Option<Support>,
    /// The shaft (or spline) to the next body downstream.
    #[serde(default)]
    pub shaft: Option<Shaft>,
}

/// Stiffness (and damping) of a support or bearing: radial (isotropic, N/m), axial (N/m), tilting
/// (N·m/rad) and rotational about the shaft axis (N·m/rad, usually 0: the bearing turns freely).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Support {
    #[serde(default)]
    pub radial: f64,
    #[serde(default)]
    pub axial: f64,
    #[serde(default)]
    pub tilting: f64,
    #[serde(default)]
    pub rotational: f64,
    /// Damping in the same four directions; None = stiffness × the model's bearing damping time.
    #[serde(default)]
    pub damping: Option<[f64; 4]>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bearing {
    /// Name in the outputs (`planet_1_uw_radial_load`, `hss_a_radial_load`).
    pub name: String,
    /// Axial position from the body's centre, m (positive downwind, towards the generator).
    #[serde(default)]
    pub position: f64,
    #[serde(default)]
    pub radial: f64,
    #[serde(default)]
    pub axial: f64,
    #[serde(default)]
    pub tilting: f64,
    #[serde(default)]
    pub rotational: f64,
    #[serde(default)]
    pub damping: Option<[f64; 4]>,
    /// Roller geometry for `model.bearings = "lamina"`.
    #[serde(default)]
    pub rollers: Option<Rollers>,
}

impl Bearing {
    pub fn stiffness(&self) -> Support {
        Support {
            radial: self.radial,
            axial: self.axial,
            tilting: self.tilting,
            rotational: self.rotational,
            damping: self.damping,
        }
    }
}

/// A shaft between two bodies: torsional always; a spline carries only torque (and lets the next
/// body float radially); a solid shaft also ties translations and tilts (same rotating frame only).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Shaft {
    pub torsional: f64,
    #[serde(default)]
    pub torsional_damping: Option<f64>,
    #[serde(default)]
    pub radial: f64,
    #[serde(default)]
    pub axial: f64,
    #[serde(default)]
    pub tilting: f64,
    /// A flexible shaft instead of `radial`, `axial` and `tilting`: a Timoshenko beam (bending with
    /// shear in both planes, axial stretch) from geometry; torsion stays `torsional`.
    #[serde(default)]
    pub beam: Option<Beam>,
}

/// A shaft's geometry and steel for its Timoshenko beam (`shaft = { torsional, beam = { … } }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Beam {
    /// Free length between where it leaves the upstream body and enters the downstream one, m.
    pub length_m: f64,
    pub outer_diameter_mm: f64,
    #[serde(default)]
    pub inner_diameter_mm: f64,
    /// Where it leaves the upstream body and enters the downstream one, m along the axis from each
    /// body's centre (positive downwind).
    #[serde(default)]
    pub from_m: f64,
    #[serde(default)]
    pub to_m: f64,
    #[serde(default = "default_youngs_modulus")]
    pub youngs_modulus: f64,
    #[serde(default = "default_shear_modulus")]
    pub shear_modulus: f64,
    /// Elements along the length. One is exact for loads at the ends and massless; two or more put
    /// nodes between them that carry the shaft's mass (`model.density`), so the shaft's own bending
    /// and whirling modes appear.
    #[serde(default = "one_element")]
    pub elements: u32,
}

/// Most elements a shaft may be cut into: a handful resolve its first bending modes; more only add
/// DOFs and stiff modes the step has to resolve.
pub const MAX_BEAM_ELEMENTS: u32 = 10;

fn one_element() -> u32 {
    1
}

fn default_youngs_modulus() -> f64 {
    2.1e11
}
fn default_shear_modulus() -> f64 {
    8.1e10
}

/// `[[stage]]` followed by `[stage.planetary]` or `[stage.parallel]` (externally tagged, so serde
/// keeps the line of every field for its error messages).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    Planetary(Box<Planetary>),
    Parallel(Box<Parallel>),
}

/// The tooth data shared by both stage kinds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Toothing {
    pub module_mm: f64,
    #[serde(default = "default_pressure_angle")]
    pub pressure_angle_deg: f64,
    #[serde(default)]
    pub helix_angle_deg: f64,
    pub face_width_mm: f64,
    /// Addendum and dedendum of the basic rack in modules.
    #[serde(default = "default_addendum")]
    pub addendum: f64,
    #[serde(default = "default_dedendum")]
    pub dedendum: f64,
    /// Normal backlash, µm.
    #[serde(default)]
    pub backlash_um: f64,
    /// Lead crowning height (µm, relief at each end of the face) and lead slope (µm over the face,
    /// positive = more compression at the downwind end): the misalignment a mesh sees.
    #[serde(default)]
    pub crowning_um: f64,
    #[serde(default)]
    pub lead_slope_um: f64,
}

fn default_pressure_angle() -> f64 {
    20.0
}
fn default_addendum() -> f64 {
    1.0
}
fn default_dedendum() -> f64 {
    1.25
}

/// Mesh stiffness and damping: given along the line of action (N/m, N·s/m), given torsionally as
/// `torsional` presets do (N·m/rad referred to the sun's or pinion's base radius), or from ISO 6336-1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct MeshData {
    #[serde(default)]
    pub stiffness: Option<f64>,
    #[serde(default)]
    pub torsional_stiffness: Option<f64>,
    #[serde(default)]
    pub damping: Option<f64>,
    #[serde(default)]
    pub torsional_damping: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanetaryTeeth {
    pub sun: u32,
    pub planet: u32,
    pub ring: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct PlanetaryShift {
    #[serde(default)]
    pub sun: f64,
    #[serde(default)]
    pub planet: f64,
    #[serde(default)]
    pub ring: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Planetary {
    #[serde(default)]
    pub name: Option<String>,
    pub planets: usize,
    pub teeth: PlanetaryTeeth,
    #[serde(default)]
    pub profile_shift: PlanetaryShift,
    pub toothing: Toothing,
    #[serde(default)]
    pub centre_distance_mm: Option<f64>,
    /// Angle of planet 1 from the upward transverse axis (deg); the others follow equally spaced.
    #[serde(default)]
    pub first_planet_deg: f64,
    /// Tangential position error of each planet pin (µm, positive ahead in the rotation sense).
    #[serde(default)]
    pub pin_errors_um: Vec<f64>,
    #[serde(default)]
    pub sun_planet: MeshData,
    #[serde(default)]
    pub ring_planet: MeshData,
    pub carrier: Body,
    /// The carrier as two plates joined by its webs (None: one rigid body). Torque enters the
    /// upwind plate; the downwind plate lags by the webs' twist, tilting every pin about its radial
    /// axis, so a planet's upwind bearing carries more than its downwind one (thesis ch. 7, where a
    /// flexible carrier gives this). Bearings downwind of the carrier's or a planet's centre sit in
    /// the downwind plate.
    #[serde(default)]
    pub carrier_webs: Option<CarrierWebs>,
    pub planet: Body,
    pub sun: Body,
    /// None = rigid to the housing; Some = elastically mounted (give its support).
    #[serde(default)]
    pub ring: Option<Body>,
}

/// Stiffness between a carrier's plates: torsional (N·m/rad), radial and axial (N/m), tilting
/// (N·m/rad), and the downwind plate's share of the carrier's mass and inertia.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarrierWebs {
    pub torsional: f64,
    pub radial: f64,
    pub tilting: f64,
    #[serde(default = "default_downwind_share")]
    pub downwind_share: f64,
}

fn default_downwind_share() -> f64 {
    0.4
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelTeeth {
    pub gear: u32,
    pub pinion: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ParallelShift {
    #[serde(default)]
    pub gear: f64,
    #[serde(default)]
    pub pinion: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Parallel {
    #[serde(default)]
    pub name: Option<String>,
    pub teeth: ParallelTeeth,
    #[serde(default)]
    pub profile_shift: ParallelShift,
    pub toothing: Toothing,
    #[serde(default)]
    pub centre_distance_mm: Option<f64>,
    /// Direction of the pinion's centre from the gear's, deg from the upward transverse axis.
    #[serde(default)]
    pub pinion_direction_deg: f64,
    #[serde(default)]
    pub mesh: MeshData,
    pub gear: Body,
    pub pinion: Body,
}

/// The presets shipped inside the library (each also a file users can copy: `fmus/gearbox6dof/resources/`).
pub const PRESETS: [(&str, &str); 5] = [
    (
        "grc750",
        include_str!("../../../fmus/gearbox6dof/resources/grc750.toml"),
    ),
    (
        "nrel5mw",
        include_str!("../../../fmus/gearbox6dof/resources/nrel5mw.toml"),
    ),
    ("c2mw", include_str!("../../../fmus/gearbox6dof/resources/c2mw.toml")),
    (
        "paper1p5mw",
        include_str!("../../../fmus/gearbox6dof/resources/paper1p5mw.toml"),
    ),
    (
        "planetary-spur",
        include_str!("../../../fmus/gearbox6dof/resources/planetary-spur.toml"),
    ),
];

/// An error reading a description: the file, and serde's line/column/field message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {message}")]
pub struct DescriptionError {
    pub file: String,
    pub message: String,
}

impl Description {
    /// Parses TOML text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Description, DescriptionError> {
        let err = |message: String| DescriptionError {
            file: file.to_string(),
            message,
        };
        let d: Description = toml::from_str(text).map_err(|e| err(e.to_string().trim_end().to_string()))?;
        d.validate().map_err(err)?;
        Ok(d)
    }

    /// A preset by name (case-insensitive) or a path to a TOML file.
    pub fn load(name_or_path: &str) -> Result<Description, DescriptionError> {
        let key = name_or_path.trim().to_ascii_lowercase();
        if let Some((name, text)) = PRESETS.iter().find(|(n, _)| *n == key) {
            return Description::parse(text, &format!("preset {name}"));
        }
        let text = std::fs::read_to_string(name_or_path).map_err(|e| DescriptionError {
            file: name_or_path.to_string(),
            message: format!(
                "cannot read it ({e}); presets are {}",
                PRESETS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
            ),
        })?;
        Description::parse(&text, name_or_path)
    }

    /// Checks serde cannot express; messages name the field as `stage[i].field`.
    fn validate(&self) -> Result<(), String> {
        let m = &self.model;
        if m.slices == 0 || m.slices > 200 {
            return Err(format!("model.slices = {} outside 1..=200", m.slices));
        }
        positive_or_zero("model.gravity", m.gravity)?;
        for (name, v) in [
            ("model.mesh_damping_ratio", m.mesh_damping_ratio),
            ("model.bearing_damping_time", m.bearing_damping_time),
            ("model.shaft_damping_ratio", m.shaft_damping_ratio),
        ] {
            positive_or_zero(name, v)?;
        }
        positive("model.density", m.density)?;
        if let ForceLaw::Impact { exponent, penetration } = m.force_law {
            if !(1.0..=3.0).contains(&exponent) {
                return Err(format!("model.force_law.exponent = {exponent} outside [1, 3]"));
            }
            positive("model.force_law.penetration", penetration)?;
        }
        if self.stages.is_empty() {
            return Err("no [[stage]]: a gearbox needs at least one stage".into());
        }
        for (i, s) in self.stages.iter().enumerate() {
            let at = |f: &str| format!("stage[{}].{f}", i + 1);
            let toothing = match s {
                Stage::Planetary(p) => {
                    if !(2..=7).contains(&p.planets) {
                        return Err(format!("{} = {} outside 2..=7", at("planets"), p.planets));
                    }
                    if !((p.teeth.sun + p.teeth.ring) as usize).is_multiple_of(p.planets) {
                        return Err(format!(
                            "{}: (sun + ring) / planets = ({} + {}) / {} is not an integer: equally spaced planets cannot be assembled",
                            at("teeth"),
                            p.teeth.sun,
                            p.teeth.ring,
                            p.planets
                        ));
                    }
                    if !p.pin_errors_um.is_empty() && p.pin_errors_um.len() != p.planets {
                        return Err(format!(
                            "{} has {} values for {} planets",
                            at("pin_errors_um"),
                            p.pin_errors_um.len(),
                            p.planets
                        ));
                    }
                    for (b, name) in [(&p.carrier, "carrier"), (&p.planet, "planet"), (&p.sun, "sun")] {
                        check_body(b, &at(name))?;
                    }
                    if let Some(w) = &p.carrier_webs {
                        for (f, v) in [("torsional", w.torsional), ("radial", w.radial), ("tilting", w.tilting)] {
                            positive(&at(&format!("carrier_webs.{f}")), v)?;
                        }
                        if !(w.downwind_share > 0.0 && w.downwind_share < 1.0) {
                            return Err(format!(
                                "{} = {} outside (0, 1)",
                                at("carrier_webs.downwind_share"),
                                w.downwind_share
                            ));
                        }
                    }
                    if let Some(r) = &p.ring {
                        check_body(r, &at("ring"))?;
                    }
                    for (md, name) in [(&p.sun_planet, "sun_planet"), (&p.ring_planet, "ring_planet")] {
                        check_mesh(md, &at(name))?;
                    }
                    &p.toothing
                }
                Stage::Parallel(p) => {
                    check_body(&p.gear, &at("gear"))?;
                    check_body(&p.pinion, &at("pinion"))?;
                    check_mesh(&p.mesh, &at("mesh"))?;
                    &p.toothing
                }
            };
            positive(&at("module_mm"), toothing.module_mm)?;
            positive(&at("face_width_mm"), toothing.face_width_mm)?;
            if !(10.0..=35.0).contains(&toothing.pressure_angle_deg) {
                return Err(format!(
                    "{} = {} outside [10, 35]",
                    at("pressure_angle_deg"),
                    toothing.pressure_angle_deg
                ));
            }
            if !(0.0..=45.0).contains(&toothing.helix_angle_deg.abs()) {
                return Err(format!(
                    "{} = {} outside [−45, 45]",
                    at("helix_angle_deg"),
                    toothing.helix_angle_deg
                ));
            }
            positive_or_zero(&at("backlash_um"), toothing.backlash_um)?;
            positive_or_zero(&at("crowning_um"), toothing.crowning_um)?;
            finite(&at("lead_slope_um"), toothing.lead_slope_um)?;
        }
        if let Some(r) = &self.rotor {
            check_body(r, "rotor")?;
        }
        if let Some(g) = &self.generator {
            check_body(g, "generator")?;
        }
        Ok(())
    }
}

fn finite(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(format!("{name} = {v} is not finite"))
    }
}

fn positive(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} = {v} must be positive"))
    }
}

fn positive_or_zero(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(format!("{name} = {v} must be ≥ 0"))
    }
}

fn check_support(s: &Support, at: &str) -> Result<(), String> {
    for (f, v) in [
        ("radial", s.radial),
        ("axial", s.axial),
        ("tilting", s.tilting),
        ("rotational", s.rotational),
    ] {
        positive_or_zero(&format!("{at}.{f}"), v)?;
    }
    if let Some(d) = s.damping {
        for v in d {
            positive_or_zero(&format!("{at}.damping"), v)?;
        }
    }
    Ok(())
}

fn check_body(b: &Body, at: &str) -> Result<(), String> {
    for (f, v) in [
        ("mass", b.mass),
        ("polar_inertia", b.polar_inertia),
        ("transverse_inertia", b.transverse_inertia),
    ] {
        if let Some(v) = v {
            positive(&format!("{at}.{f}"), v)?;
        }
    }
    if b.support.is_some() && !b.bearings.is_empty() {
        return Err(format!("{at}: give either bearings or support, not both"));
    }
    if let Some(s) = &b.support {
        check_support(s, &format!("{at}.support"))?;
    }
    for (k, br) in b.bearings.iter().enumerate() {
        finite(&format!("{at}.bearings[{}].position", k + 1), br.position)?;
        check_support(&br.stiffness(), &format!("{at}.bearings[{}]", k + 1))?;
        if let Some(r) = &br.rollers {
            check_rollers(r, &format!("{at}.bearings[{}].rollers", k + 1))?;
        }
        if br.name.is_empty() || !br.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!(
                "{at}.bearings[{}].name = {:?}: letters, digits and _ only",
                k + 1,
                br.name
            ));
        }
    }
    if let Some(s) = &b.shaft {
        positive(&format!("{at}.shaft.torsional"), s.torsional)?;
        for (f, v) in [("radial", s.radial), ("axial", s.axial), ("tilting", s.tilting)] {
            positive_or_zero(&format!("{at}.shaft.{f}"), v)?;
        }
        if let Some(c) = s.torsional_damping {
            positive_or_zero(&format!("{at}.shaft.torsional_damping"), c)?;
        }
        if let Some(beam) = &s.beam {
            check_beam(beam, s, &format!("{at}.shaft"))?;
        }
    }
    Ok(())
}

fn check_beam(beam: &Beam, s: &Shaft, at: &str) -> Result<(), String> {
    if s.radial > 0.0 || s.axial > 0.0 || s.tilting > 0.0 {
        return Err(format!(
            "{at}: give a beam or radial/axial/tilting stiffness, not both (the beam's come from its geometry)"
        ));
    }
    for (f, v) in [
        ("length_m", beam.length_m),
        ("outer_diameter_mm", beam.outer_diameter_mm),
        ("youngs_modulus", beam.youngs_modulus),
        ("shear_modulus", beam.shear_modulus),
    ] {
        positive(&format!("{at}.beam.{f}"), v)?;
    }
    if !(beam.inner_diameter_mm >= 0.0 && beam.inner_diameter_mm < beam.outer_diameter_mm) {
        return Err(format!(
            "{at}.beam.inner_diameter_mm = {}: 0 or more and below outer_diameter_mm = {}",
            beam.inner_diameter_mm, beam.outer_diameter_mm
        ));
    }
    if !(beam.from_m.is_finite() && beam.to_m.is_finite()) {
        return Err(format!("{at}.beam: from_m and to_m must be numbers"));
    }
    if !(1..=MAX_BEAM_ELEMENTS).contains(&beam.elements) {
        return Err(format!(
            "{at}.beam.elements = {} outside 1..={MAX_BEAM_ELEMENTS}",
            beam.elements
        ));
    }
    Ok(())
}

fn check_rollers(r: &Rollers, at: &str) -> Result<(), String> {
    if !(3..=200).contains(&r.count) {
        return Err(format!("{at}.count = {} outside 3..=200", r.count));
    }
    if !(1..=2).contains(&r.rows) {
        return Err(format!("{at}.rows = {}: 1 or 2", r.rows));
    }
    if !(1..=50).contains(&r.laminae) {
        return Err(format!("{at}.laminae = {} outside 1..=50", r.laminae));
    }
    for (f, v) in [
        ("diameter_mm", r.diameter_mm),
        ("length_mm", r.length_mm),
        ("pitch_diameter_mm", r.pitch_diameter_mm),
    ] {
        positive(&format!("{at}.{f}"), v)?;
    }
    if r.pitch_diameter_mm <= r.diameter_mm {
        return Err(format!(
            "{at}.pitch_diameter_mm = {} must exceed the roller diameter {} mm",
            r.pitch_diameter_mm, r.diameter_mm
        ));
    }
    if r.contact_angle_deg.is_nan() || r.contact_angle_deg.abs() >= 60.0 {
        return Err(format!(
            "{at}.contact_angle_deg = {} outside (−60, 60)",
            r.contact_angle_deg
        ));
    }
    positive_or_zero(&format!("{at}.row_spacing_mm"), r.row_spacing_mm)?;
    positive_or_zero(&format!("{at}.crowning_um"), r.crowning_um)?;
    finite(&format!("{at}.clearance_um"), r.clearance_um)?;
    finite(&format!("{at}.axial_clearance_um"), r.axial_clearance_um)?;
    let profile = match (r.profile_radius_mm, r.race_profile_radii_mm) {
        (None, None) => false,
        (Some(roller), Some(races)) => {
            if r.contact != Contact::Point {
                return Err(format!(
                    "{at}: profile_radius_mm and race_profile_radii_mm describe point contact: give contact = \"point\""
                ));
            }
            positive(&format!("{at}.profile_radius_mm"), roller)?;
            for (name, race) in ["inner", "outer"].into_iter().zip(races) {
                // a flat raceway (inf in TOML) is allowed: a crowned roller on a cylinder
                if race.is_nan() || race <= roller {
                    return Err(format!(
                        "{at}.race_profile_radii_mm: the {name} raceway's radius {race} mm must exceed the roller's \
                         profile_radius_mm = {roller} (a concave groove around a convex roller)"
                    ));
                }
            }
            if r.roller_stiffness.is_some() {
                return Err(format!(
                    "{at}: give roller_stiffness or the profile radii, not both (the radii give the stiffness)"
                ));
            }
            if r.crowning_um != 0.0 {
                return Err(format!(
                    "{at}.crowning_um: the profile radii describe the roller's crown already; leave crowning_um out"
                ));
            }
            let (rolling, across) = r.contact_radii();
            for (k, name) in ["inner", "outer"].into_iter().enumerate() {
                let across = across.map_or(f64::NAN, |a| a[k]);
                // the ellipse's shape does not depend on the modulus
                if crate::physics::hertz::EllipticContact::new(rolling[k], across, 1.0).is_none() {
                    return Err(format!(
                        "{at}: the roller and the {name} raceway conform so closely that the contact ellipse would be \
                         a million times longer than wide: give line contact with the osculation's gap as crowning_um"
                    ));
                }
            }
            true
        }
        _ => {
            return Err(format!(
                "{at}: give profile_radius_mm and race_profile_radii_mm = [inner, outer] together"
            ));
        }
    };
    match (r.contact, r.roller_stiffness) {
        (_, Some(c)) => positive(&format!("{at}.roller_stiffness"), c)?,
        (Contact::Point, None) if !profile => {
            return Err(format!(
                "{at}: point contact needs profile_radius_mm and race_profile_radii_mm, or roller_stiffness (N/m^1.5): \
                 ISO/TS 16281's line-contact constant does not apply"
            ));
        }
        _ => {}
    }
    Ok(())
}

fn check_mesh(m: &MeshData, at: &str) -> Result<(), String> {
    if m.stiffness.is_some() && m.torsional_stiffness.is_some() {
        return Err(format!("{at}: give stiffness or torsional_stiffness, not both"));
    }
    if m.damping.is_some() && m.torsional_damping.is_some() {
        return Err(format!("{at}: give damping or torsional_damping, not both"));
    }
    for (f, v) in [
        ("stiffness", m.stiffness),
        ("torsional_stiffness", m.torsional_stiffness),
        ("damping", m.damping),
        ("torsional_damping", m.torsional_damping),
    ] {
        if let Some(v) = v {
            positive_or_zero(&format!("{at}.{f}"), v)?;
        }
    }
    Ok(())
}
