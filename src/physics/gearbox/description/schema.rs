//! The description format: what a user writes in a gearbox TOML file, as serde reads it, with the
//! defaults of every optional field. Unknown fields are errors (`deny_unknown_fields`).

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
    /// The lamina model with each roller's sums over its laminae by table (line contact without
    /// crowning; its sums within 2e-10 of `lamina`'s).
    #[serde(rename = "lamina-table")]
    LaminaTable,
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
