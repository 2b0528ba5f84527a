//! Lumped torsional drivetrain assembled from a [`Drivetrain`](crate::physics::drivetrain::Drivetrain) description at one of three fidelities.
//!
//! Every body has one rotational DOF, its angle positive in its own running direction. Shafts are
//! spring–dampers between two bodies; a gear mesh is a spring–damper along the line of action whose
//! deflection is δ = Σ g_d θ_d (metres, g = signed base radii), with optional backlash and a
//! time-varying (single/double tooth contact) stiffness. The reduced fidelities come from the full
//! model: `Five` makes every mesh rigid (one DOF per stage, thesis Eq. 4.8–4.21) and `Two` also
//! lumps all stages into the generator side with the shafts in series, so all three agree on the
//! static torque distribution and the low modes.
//!
//! One job a file: this one the model's types; `assembly` the full model from the description,
//! `reduction` the asked fidelity from it ([`TorsionalModel::new`]), `section` the model cut in its
//! LSS, `linear` its matrices and statics, `system` the solver's view of it.

use super::brake::DiskBrake;
use crate::solver::system::InputLoad;
use serde::{Deserialize, Serialize};

mod assembly;
mod element_table;
pub use element_table::ElementTable;
mod linear;
mod reduction;
mod section;
mod system;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Fidelity {
    Two,
    Five,
    Full,
}

impl Fidelity {
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "2" | "two" => Some(Self::Two),
            "5" | "five" => Some(Self::Five),
            "full" | "11" => Some(Self::Full),
            _ => None,
        }
    }
}

/// Options that shape the model beyond the drivetrain description.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ModelOptions {
    pub shaft_damping_ratio: f64,
    pub mesh_damping_ratio: f64,
    pub damping_scale: f64,
    /// Total backlash per mesh along the line of action, m.
    pub mesh_backlash: f64,
    /// (k_double − k_single) / k_mean; 0 = constant mesh stiffness.
    pub mesh_stiffness_variation: f64,
    pub contact_ratio: f64,
    /// How the reduced (2- and 5-mass) models lump the planets.
    pub lumping: Lumping,
}

/// Whose 5-mass lumping the reduced models use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Lumping {
    /// Every body's kinetic energy at rigid rotation, the planets' spin included: the reduced models
    /// keep the full model's rigid-body inertia (the default, physically consistent).
    #[default]
    Physical,
    /// The thesis's Eq. 4.9, J2 = J_pc + N1²·J_s: the planets' spin inertia is left out (moves D's
    /// fourth 5-mass mode by 8.6 %).
    Thesis,
}

impl Lumping {
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "physical" => Some(Self::Physical),
            "thesis" => Some(Self::Thesis),
            _ => None,
        }
    }
}

impl Default for ModelOptions {
    fn default() -> Self {
        Self {
            shaft_damping_ratio: 0.006,
            mesh_damping_ratio: 0.1,
            damping_scale: 1.0,
            mesh_backlash: 0.0,
            mesh_stiffness_variation: 0.0,
            contact_ratio: 1.6,
            lumping: Lumping::Physical,
        }
    }
}

/// Single/double tooth contact: the mesh stiffness as a square wave of the mesh angle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeshStiffnessVariation {
    /// Model DOF whose angle sets the mesh position (carrier for planetary, pinion for parallel).
    pub dof: usize,
    /// Mesh cycles per radian of that DOF (z_ring/2π or z_pinion/2π).
    pub cycles_per_rad: f64,
    pub phase: f64,
    pub k_single: f64,
    pub k_double: f64,
    /// Fraction of each mesh period in double contact (contact ratio − 1).
    pub double_fraction: f64,
}

impl MeshStiffnessVariation {
    pub fn stiffness(&self, angle: f64) -> f64 {
        let x = (self.cycles_per_rad * angle + self.phase).rem_euclid(1.0);
        if x < self.double_fraction {
            self.k_double
        } else {
            self.k_single
        }
    }
}

/// A linear spring–damper on a combination of DOFs: force = k·δ + c·δ̇ with δ = Σ g_d θ_d.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Element {
    pub name: String,
    pub coeffs: Vec<(usize, f64)>,
    pub stiffness: f64,
    pub damping: f64,
    /// Half the backlash: no force while |δ| < half_backlash.
    pub half_backlash: f64,
    pub variation: Option<MeshStiffnessVariation>,
    /// Coefficient of the cut boundary's angle in δ when the rotor is cut away
    /// ([`Section::Drivetrain`]): δ = Σ g_d θ_d + boundary·θ_b. The boundary's share of the force is
    /// an external load (inputs [`INPUT_CUT_ANGLE`] and [`INPUT_CUT_SPEED`]), not part of
    /// [`Element::deflection`]. 0 for every other element.
    #[serde(default)]
    pub boundary: f64,
    /// Rigid-rotation speed ratio of each coefficient's DOF (filled by the model). Deflections are
    /// summed from angles relative to the rigid rotation with the rotor: the absolute angles grow to
    /// thousands of radians while a mesh deflects by micro-radians, and Σ g·θ over absolute angles
    /// would lose those digits (K·r = 0, so the result is the same in exact arithmetic).
    #[serde(default)]
    pub ratios: Vec<f64>,
}

impl Element {
    /// δ = Σ g_d (θ_d − r_d θ_0): relative to the rigid rotation with DOF 0 (the rotor, or the first
    /// body downstream of a cut).
    #[inline]
    pub fn deflection(&self, q: &[f64]) -> f64 {
        // a shaft or a mesh: two DOFs, inlined into every output read. `Sum` adds from −0.0, the
        // additive identity, so t₀ + t₁ is the general way's result to the bit, without its loop
        if let ([(d0, g0), (d1, g1)], [r0, r1]) = (&self.coeffs[..], &self.ratios[..]) {
            let q0 = q[0];
            return g0 * (q[*d0] - r0 * q0) + g1 * (q[*d1] - r1 * q0);
        }
        self.deflection_of_any(q)
    }

    #[inline(never)]
    fn deflection_of_any(&self, q: &[f64]) -> f64 {
        if self.ratios.is_empty() {
            return self.coeffs.iter().map(|&(d, g)| g * q[d]).sum();
        }
        let q0 = q[0];
        self.coeffs
            .iter()
            .zip(&self.ratios)
            .map(|(&(d, g), r)| g * (q[d] - r * q0))
            .sum()
    }

    /// Stiffness at the given DOF angles (changes only with time-varying mesh stiffness).
    pub fn stiffness_at(&self, q: &[f64]) -> f64 {
        match &self.variation {
            Some(v) => v.stiffness(q[v.dof]),
            None => self.stiffness,
        }
    }

    /// Elastic deflection beyond the backlash gap, and whether the flanks touch.
    pub fn contact(&self, delta: f64) -> (f64, bool) {
        Self::contact_of(self.half_backlash, delta)
    }

    /// [`Self::contact`] of an element with half the backlash `half_backlash`.
    #[inline]
    pub(super) fn contact_of(half_backlash: f64, delta: f64) -> (f64, bool) {
        if half_backlash == 0.0 {
            (delta, true)
        } else if delta > half_backlash {
            (delta - half_backlash, true)
        } else if delta < -half_backlash {
            (delta + half_backlash, true)
        } else {
            (0.0, false)
        }
    }

    /// Force for deflection and its rate with stiffness `k`: spring and damper act only in contact.
    pub fn force(&self, k: f64, delta: f64, rate: f64) -> f64 {
        self.force_in(k, self.contact(delta), rate)
    }

    /// [`Self::force`] from the deflection's [`Self::contact`].
    #[inline]
    pub fn force_in(&self, k: f64, contact: (f64, bool), rate: f64) -> f64 {
        Self::spring_damper(k, self.damping, contact, rate)
    }

    /// [`Self::force_in`] of an element with damping `damping`.
    #[inline]
    pub(super) fn spring_damper(k: f64, damping: f64, (elastic, touching): (f64, bool), rate: f64) -> f64 {
        if touching { k * elastic + damping * rate } else { 0.0 }
    }
}

/// One element's force and elastic energy at a state ([`ElementTable::loads`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ElementLoad {
    pub force: f64,
    pub energy: f64,
}

/// An output computed from one element's force: value = factor × force.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ForceOutput {
    pub element: usize,
    pub factor: f64,
}

/// Body slots of the FMU's angle_/speed_ outputs.
pub const BODY_SLOTS: [&str; 16] = [
    "rotor",
    "carrier_1",
    "planet_1_1",
    "planet_1_2",
    "planet_1_3",
    "sun_1",
    "carrier_2",
    "planet_2_1",
    "planet_2_2",
    "planet_2_3",
    "sun_2",
    "gear_1",
    "pinion_1",
    "gear_2",
    "pinion_2",
    "generator",
];
/// Mesh slots of the FMU's mesh_force_ outputs.
pub const MESH_SLOTS: [&str; 14] = [
    "ring_planet_1",
    "ring_planet_2",
    "ring_planet_3",
    "sun_planet_1",
    "sun_planet_2",
    "sun_planet_3",
    "ring_planet2_1",
    "ring_planet2_2",
    "ring_planet2_3",
    "sun_planet2_1",
    "sun_planet2_2",
    "sun_planet2_3",
    "gear_pinion_1",
    "gear_pinion_2",
];
/// Shaft slots: LSS, stage 1–2, stage 2–3, HSS.
pub const SHAFT_SLOTS: [&str; 4] = ["lss", "is1", "is2", "hss"];

/// The assembled equations M θ̈ + Σ g F(g·θ, g·θ̇) = τ, with M diagonal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TorsionalModel {
    pub fidelity: Fidelity,
    pub dof_names: Vec<String>,
    pub mass: Vec<f64>,
    pub elements: Vec<Element>,
    pub rotor: usize,
    /// The generator DOF: generator torque and HSS brake act here.
    pub generator: usize,
    /// Speed of each DOF over rotor speed in rigid rotation.
    pub speed_ratio: Vec<f64>,
    /// For every body slot present in the preset: (model DOF, factor) with θ_body = factor·θ_dof.
    pub bodies: Vec<Option<(usize, f64)>>,
    pub meshes: Vec<Option<ForceOutput>>,
    pub shafts: Vec<Option<ForceOutput>>,
    pub gear_ratio: f64,
    /// Some mesh has backlash (steps need Newton iterations).
    pub backlash: bool,
    /// Some mesh has time-varying stiffness.
    pub stiffness_variation: bool,
    /// The HSS brake on the generator DOF (none until the owner sets one).
    pub brake: DiskBrake,
    /// Rotor torque drives the rotor, generator torque opposes the generator (the inputs
    /// [`INPUT_ROTOR_TORQUE`] and [`INPUT_GENERATOR_TORQUE`]); a section's cut adds its own.
    pub input_loads: Vec<InputLoad>,
    /// The part of the drivetrain this model is (the whole, or one side of a cut in the LSS).
    #[serde(default)]
    pub section: Section,
}

/// Which side of a cut in the low-speed shaft a model is, so that a drivetrain can be split across
/// two FMUs at its main shaft (or coupled to an aeroelastic code that owns the rotor).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Section {
    #[default]
    Whole,
    /// The rotor's inertia alone: rotor torque drives it, the cut shaft's torque
    /// ([`INPUT_CUT_TORQUE`]) opposes it.
    Rotor,
    /// Everything downstream of the rotor: the LSS's rotor end turns at a prescribed speed
    /// ([`INPUT_CUT_SPEED`], its angle [`INPUT_CUT_ANGLE`] the integral), the LSS torque is the output.
    Drivetrain,
}

impl Section {
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "whole" => Some(Self::Whole),
            "rotor" => Some(Self::Rotor),
            "drivetrain" => Some(Self::Drivetrain),
            _ => None,
        }
    }
}

/// The model's inputs, in this order: rotor torque (N·m, driving), generator torque (N·m,
/// electromagnetic, opposing rotation), brake command (0–1); at a cut in the LSS the boundary's
/// angle (rad) and speed (rad/s) for [`Section::Drivetrain`] and the shaft's torque (N·m, opposing
/// rotation) for [`Section::Rotor`].
pub const INPUT_ROTOR_TORQUE: usize = 0;
pub const INPUT_GENERATOR_TORQUE: usize = 1;
pub const INPUT_BRAKE_COMMAND: usize = 2;
pub const INPUT_CUT_ANGLE: usize = 3;
pub const INPUT_CUT_SPEED: usize = 4;
pub const INPUT_CUT_TORQUE: usize = 5;
pub const INPUT_COUNT: usize = 6;
