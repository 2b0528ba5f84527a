//! Lumped torsional drivetrain assembled from a [`Drivetrain`] description at one of three fidelities.
//!
//! Every body has one rotational DOF, its angle positive in its own running direction. Shafts are
//! spring–dampers between two bodies; a gear mesh is a spring–damper along the line of action whose
//! deflection is δ = Σ g_d θ_d (metres, g = signed base radii), with optional backlash and a
//! time-varying (single/double tooth contact) stiffness. The reduced fidelities come from the full
//! model: `Five` makes every mesh rigid (one DOF per stage, thesis Eq. 4.8–4.21) and `Two` also
//! lumps all stages into the generator side with the shafts in series, so all three agree on the
//! static torque distribution and the low modes.

use super::brake::DiskBrake;
use super::drivetrain::{Drivetrain, Stage};
use crate::solver::system::{Friction, InputLoad, Linearity, Mass, SecondOrderSystem};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

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
    pub fn deflection(&self, q: &[f64]) -> f64 {
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
        if self.half_backlash == 0.0 {
            (delta, true)
        } else if delta > self.half_backlash {
            (delta - self.half_backlash, true)
        } else if delta < -self.half_backlash {
            (delta + self.half_backlash, true)
        } else {
            (0.0, false)
        }
    }

    /// Force for deflection and its rate with stiffness `k`: spring and damper act only in contact.
    pub fn force(&self, k: f64, delta: f64, rate: f64) -> f64 {
        let (elastic, touching) = self.contact(delta);
        if touching {
            k * elastic + self.damping * rate
        } else {
            0.0
        }
    }
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

struct FullBody {
    slot: Option<usize>,
    name: String,
    inertia: f64,
    ratio: f64,
    /// Index of the stage the body belongs to (None for rotor and generator).
    stage: Option<usize>,
    /// A planet: its spin inertia is what the thesis's 5-mass lumping leaves out.
    planet: bool,
}

struct Assembly {
    bodies: Vec<FullBody>,
    elements: Vec<Element>,
    /// (mesh slot, element index) of the full model.
    mesh_slots: Vec<(usize, usize)>,
    /// Per stage: the factor from stage input torque to each of its mesh slots' quasi-static force.
    quasi_static_mesh: Vec<Vec<(usize, f64)>>,
}

/// Inertia referred to the speed of body `at`, of all bodies upstream (true) or downstream of `at`.
fn lumped_inertia(bodies: &[FullBody], split: usize, upstream: bool, ratio: f64) -> f64 {
    bodies
        .iter()
        .enumerate()
        .filter(|(i, _)| if upstream { *i < split } else { *i >= split })
        .map(|(_, b)| b.inertia * (b.ratio / ratio).powi(2))
        .sum()
}

fn assemble_full(dt: &Drivetrain, opt: &ModelOptions) -> Assembly {
    let mut bodies = vec![FullBody {
        slot: Some(0),
        name: "rotor".into(),
        inertia: dt.j_rotor,
        ratio: 1.0,
        stage: None,
        planet: false,
    }];
    let mut elements = Vec::new();
    let mut mesh_slots = Vec::new();
    let mut quasi_static_mesh = Vec::new();
    // shaft i joins body shaft_ends[i].0 to the input body of stage i (or the generator)
    let mut shaft_ends: Vec<(usize, usize)> = Vec::new();
    let mut upstream = 0usize;
    let mut ratio = 1.0;
    let (mut n_planetary, mut n_parallel) = (0usize, 0usize);
    let double_fraction = (opt.contact_ratio - 1.0).clamp(0.0, 1.0);
    let variation = |k: f64, dof: usize, cycles_per_rad: f64, phase: f64| {
        (opt.mesh_stiffness_variation > 0.0).then(|| {
            let k_single = k * (1.0 - opt.mesh_stiffness_variation * double_fraction);
            MeshStiffnessVariation {
                dof,
                cycles_per_rad,
                phase,
                k_single,
                k_double: k_single + opt.mesh_stiffness_variation * k,
                double_fraction,
            }
        })
    };
    let half_backlash = 0.5 * opt.mesh_backlash;
    for (s, stage) in dt.stages.iter().enumerate() {
        let input = bodies.len();
        shaft_ends.push((upstream, input));
        let mut qs = Vec::new();
        match stage {
            Stage::Planetary(p) => {
                let slot = |base: usize| (n_planetary < 2).then_some(base + 5 * n_planetary);
                let (r_s, r_p) = (p.geometry.base_radius(p.z_sun), p.geometry.base_radius(p.z_planet));
                // The carrier's lever arm in each mesh, in base radii: r_s + r_p against the sun and
                // r_ring − r_p against the ring. They are equal for standard tooth counts
                // (z_r = z_s + 2 z_p); with profile-shifted counts (the paper's 25/45/116) only these
                // two keep the meshes on the tooth counts' kinematics, ω_s/ω_c = 1 + z_r/z_s and
                // ω_p/ω_c = (z_r − z_p)/z_p, the rigid rotation the deflections are measured from.
                let a = r_s + r_p;
                let a_ring = p.geometry.base_radius(p.z_ring) - r_p;
                let planet_ratio = ratio * f64::from(p.z_ring - p.z_planet) / f64::from(p.z_planet);
                bodies.push(FullBody {
                    slot: slot(1),
                    name: format!("carrier {}", s + 1),
                    inertia: p.j_carrier,
                    ratio,
                    stage: Some(s),
                    planet: false,
                });
                let carrier = input;
                let first_planet = bodies.len();
                for k in 0..p.planets {
                    bodies.push(FullBody {
                        slot: if k < 3 { slot(2 + k) } else { None },
                        name: format!("planet {}.{}", s + 1, k + 1),
                        inertia: p.j_planet,
                        ratio: planet_ratio,
                        stage: Some(s),
                        planet: true,
                    });
                }
                let sun = bodies.len();
                bodies.push(FullBody {
                    slot: slot(5),
                    name: format!("sun {}", s + 1),
                    inertia: p.j_sun,
                    ratio: ratio * stage.ratio(),
                    stage: Some(s),
                    planet: false,
                });
                let k_rp = p.k_ring_planet / (r_s * r_s);
                let k_sp = p.k_sun_planet / (r_s * r_s);
                let m_rp = p.j_planet / (r_p * r_p);
                let m_sp = 1.0 / (r_s * r_s / p.j_sun + r_p * r_p / p.j_planet);
                let c_rp = p
                    .c_ring_planet
                    .map_or(2.0 * opt.mesh_damping_ratio * (k_rp * m_rp).sqrt(), |c| c / (r_s * r_s));
                let c_sp = p
                    .c_sun_planet
                    .map_or(2.0 * opt.mesh_damping_ratio * (k_sp * m_sp).sqrt(), |c| c / (r_s * r_s));
                let cycles = f64::from(p.z_ring) / TAU;
                for k in 0..p.planets {
                    let planet = first_planet + k;
                    let phase = (k as f64 * f64::from(p.z_ring) / p.planets as f64).fract();
                    let rp = elements.len();
                    elements.push(Element {
                        name: format!("ring-planet {}.{}", s + 1, k + 1),
                        coeffs: vec![(carrier, a_ring), (planet, -r_p)],
                        stiffness: k_rp,
                        damping: c_rp * opt.damping_scale,
                        half_backlash,
                        variation: variation(k_rp, carrier, cycles, phase),
                        boundary: 0.0,
                        ratios: Vec::new(),
                    });
                    let sp = elements.len();
                    elements.push(Element {
                        name: format!("sun-planet {}.{}", s + 1, k + 1),
                        coeffs: vec![(carrier, a), (planet, r_p), (sun, -r_s)],
                        stiffness: k_sp,
                        damping: c_sp * opt.damping_scale,
                        half_backlash,
                        variation: variation(k_sp, carrier, cycles, phase),
                        boundary: 0.0,
                        ratios: Vec::new(),
                    });
                    if n_planetary < 2 && k < 3 {
                        let base = 6 * n_planetary;
                        mesh_slots.push((base + k, rp));
                        mesh_slots.push((base + 3 + k, sp));
                        // quasi-static: carrier torque T = N · F · (a + a_ring)  →  F = T / (N (a + a_ring))
                        let f = 1.0 / (p.planets as f64 * (a + a_ring));
                        qs.push((base + k, f));
                        qs.push((base + 3 + k, f));
                    }
                }
                n_planetary += 1;
                upstream = sun;
            }
            Stage::Parallel(p) => {
                let slot = |base: usize| (n_parallel < 2).then_some(base + 2 * n_parallel);
                let (r_g, r_p) = (p.geometry.base_radius(p.z_gear), p.geometry.base_radius(p.z_pinion));
                bodies.push(FullBody {
                    slot: slot(11),
                    name: format!("gear {}", s + 1),
                    inertia: p.j_gear,
                    ratio,
                    stage: Some(s),
                    planet: false,
                });
                let pinion = bodies.len();
                bodies.push(FullBody {
                    slot: slot(12),
                    name: format!("pinion {}", s + 1),
                    inertia: p.j_pinion,
                    ratio: ratio * stage.ratio(),
                    stage: Some(s),
                    planet: false,
                });
                let k = p.k_mesh / (r_p * r_p);
                let m_eq = 1.0 / (r_g * r_g / p.j_gear + r_p * r_p / p.j_pinion);
                let c = p
                    .c_mesh
                    .map_or(2.0 * opt.mesh_damping_ratio * (k * m_eq).sqrt(), |c| c / (r_p * r_p));
                let e = elements.len();
                elements.push(Element {
                    name: format!("gear-pinion {}", s + 1),
                    coeffs: vec![(input, r_g), (pinion, -r_p)],
                    stiffness: k,
                    damping: c * opt.damping_scale,
                    half_backlash,
                    variation: variation(k, pinion, f64::from(p.z_pinion) / TAU, 0.0),
                    boundary: 0.0,
                    ratios: Vec::new(),
                });
                if n_parallel < 2 {
                    mesh_slots.push((12 + n_parallel, e));
                    qs.push((12 + n_parallel, 1.0 / r_g));
                }
                n_parallel += 1;
                upstream = pinion;
            }
        }
        quasi_static_mesh.push(qs);
        ratio *= stage.ratio();
    }
    let generator = bodies.len();
    shaft_ends.push((upstream, generator));
    bodies.push(FullBody {
        slot: Some(15),
        name: "generator".into(),
        inertia: dt.j_generator,
        ratio,
        stage: None,
        planet: false,
    });
    // Shafts go first in the element list: element i = shaft i.
    let mut shafts = Vec::new();
    for (i, (&(a, b), spec)) in shaft_ends.iter().zip(&dt.shafts).enumerate() {
        let r = bodies[b].ratio;
        let j_up = lumped_inertia(&bodies, b, true, r);
        let j_down = lumped_inertia(&bodies, b, false, r);
        let j_eq = j_up * j_down / (j_up + j_down);
        let c = spec
            .damping
            .unwrap_or(2.0 * opt.shaft_damping_ratio * (spec.stiffness * j_eq).sqrt());
        shafts.push(Element {
            name: format!("shaft {}", SHAFT_SLOTS[shaft_slot(i, dt.shafts.len())]),
            coeffs: vec![(a, 1.0), (b, -1.0)],
            stiffness: spec.stiffness,
            damping: c * opt.damping_scale,
            half_backlash: 0.0,
            variation: None,
            boundary: 0.0,
            ratios: Vec::new(),
        });
    }
    let n_shafts = shafts.len();
    shafts.extend(elements);
    for (_, e) in mesh_slots.iter_mut() {
        *e += n_shafts;
    }
    Assembly {
        bodies,
        elements: shafts,
        mesh_slots,
        quasi_static_mesh,
    }
}

/// Shaft i of n → output slot: first is LSS, last is HSS, the rest IS1, IS2 in order.
fn shaft_slot(i: usize, n: usize) -> usize {
    if i == 0 {
        0
    } else if i == n - 1 {
        3
    } else {
        i.min(2)
    }
}

impl TorsionalModel {
    pub fn new(dt: &Drivetrain, fidelity: Fidelity, opt: &ModelOptions) -> Result<Self, String> {
        if dt.shafts.len() != dt.stages.len() + 1 {
            return Err(format!(
                "drivetrain {} needs {} shafts for {} stages",
                dt.name,
                dt.stages.len() + 1,
                dt.stages.len()
            ));
        }
        let full = assemble_full(dt, opt);
        let n_shafts = dt.shafts.len();
        let shaft_outputs = |factor_of: &dyn Fn(usize) -> ForceOutput| {
            let mut out = vec![None; 4];
            for i in 0..n_shafts {
                out[shaft_slot(i, n_shafts)] = Some(factor_of(i));
            }
            out
        };
        let speed_at_shaft = |i: usize| -> f64 { dt.stages[..i].iter().map(Stage::ratio).product() };
        // group[d] = (reduced DOF, factor θ_d / θ_master)
        let (names, group): (Vec<String>, Vec<(usize, f64)>) = match fidelity {
            Fidelity::Full => (
                full.bodies.iter().map(|b| b.name.clone()).collect(),
                (0..full.bodies.len()).map(|d| (d, 1.0)).collect(),
            ),
            Fidelity::Five => {
                let mut names = vec!["rotor".to_string()];
                names.extend((0..dt.stages.len()).map(|s| format!("stage {}", s + 1)));
                names.push("generator".into());
                // master of stage s is its input body (carrier or gear), turning at the speed of shaft s
                let master_ratio = |g: usize| -> f64 { if g == 0 { 1.0 } else { speed_at_shaft(g - 1) } };
                let group = full
                    .bodies
                    .iter()
                    .map(|b| {
                        let g = match b.stage {
                            Some(s) => s + 1,
                            None if b.slot == Some(0) => 0,
                            None => dt.stages.len() + 1,
                        };
                        (g, b.ratio / master_ratio(g))
                    })
                    .collect();
                (names, group)
            }
            Fidelity::Two => {
                let gear_ratio = dt.gear_ratio();
                let group = full
                    .bodies
                    .iter()
                    .enumerate()
                    .map(|(d, b)| if d == 0 { (0, 1.0) } else { (1, b.ratio / gear_ratio) })
                    .collect();
                (vec!["rotor".into(), "generator (drivetrain lumped)".into()], group)
            }
        };
        let n = names.len();
        let mut mass = vec![0.0; n];
        let mut speed_ratio = vec![0.0; n];
        let omit_planets = fidelity != Fidelity::Full && opt.lumping == Lumping::Thesis;
        for (b, &(g, f)) in full.bodies.iter().zip(&group) {
            if !(omit_planets && b.planet) {
                mass[g] += b.inertia * f * f;
            }
            speed_ratio[g] = b.ratio / f;
        }
        let mut bodies = vec![None; BODY_SLOTS.len()];
        for (b, &(g, f)) in full.bodies.iter().zip(&group) {
            if let Some(slot) = b.slot {
                bodies[slot] = Some((g, f));
            }
        }
        let generator = n - 1;
        let gear_ratio = dt.gear_ratio();
        let (elements, meshes, shafts) = match fidelity {
            Fidelity::Full => {
                let mut meshes = vec![None; MESH_SLOTS.len()];
                for &(slot, e) in &full.mesh_slots {
                    meshes[slot] = Some(ForceOutput {
                        element: e,
                        factor: 1.0,
                    });
                }
                let shafts = shaft_outputs(&|i| ForceOutput {
                    element: i,
                    factor: 1.0,
                });
                (full.elements, meshes, shafts)
            }
            Fidelity::Five => {
                // Shafts survive with their coefficients mapped to the stage DOFs; meshes become rigid.
                let elements: Vec<Element> = full.elements[..n_shafts]
                    .iter()
                    .map(|e| Element {
                        coeffs: e.coeffs.iter().map(|&(d, g)| (group[d].0, g * group[d].1)).collect(),
                        ..e.clone()
                    })
                    .collect();
                let mut meshes = vec![None; MESH_SLOTS.len()];
                for (s, qs) in full.quasi_static_mesh.iter().enumerate() {
                    for &(slot, f) in qs {
                        meshes[slot] = Some(ForceOutput { element: s, factor: f });
                    }
                }
                (
                    elements,
                    meshes,
                    shaft_outputs(&|i| ForceOutput {
                        element: i,
                        factor: 1.0,
                    }),
                )
            }
            Fidelity::Two => {
                // Shafts in series, referred to the LSS (thesis: 1/K = Σ 1/K_i, 1/C = Σ 1/C_i).
                let mut compliance = 0.0;
                let mut resistance = 0.0;
                for (i, e) in full.elements[..n_shafts].iter().enumerate() {
                    let n2 = speed_at_shaft(i).powi(2);
                    compliance += 1.0 / (e.stiffness * n2);
                    resistance += if e.damping > 0.0 {
                        1.0 / (e.damping * n2)
                    } else {
                        f64::INFINITY
                    };
                }
                let element = Element {
                    name: "lumped shaft (LSS-referred)".into(),
                    coeffs: vec![(0, 1.0), (1, -1.0 / gear_ratio)],
                    stiffness: 1.0 / compliance,
                    damping: if resistance.is_finite() { 1.0 / resistance } else { 0.0 },
                    half_backlash: 0.0,
                    variation: None,
                    boundary: 0.0,
                    ratios: Vec::new(),
                };
                let mut meshes = vec![None; MESH_SLOTS.len()];
                for (s, qs) in full.quasi_static_mesh.iter().enumerate() {
                    for &(slot, f) in qs {
                        meshes[slot] = Some(ForceOutput {
                            element: 0,
                            factor: f / speed_at_shaft(s),
                        });
                    }
                }
                let shafts = shaft_outputs(&|i| ForceOutput {
                    element: 0,
                    factor: 1.0 / speed_at_shaft(i),
                });
                (vec![element], meshes, shafts)
            }
        };
        let mut elements = elements;
        for e in &mut elements {
            e.ratios = e.coeffs.iter().map(|&(d, _)| speed_ratio[d]).collect();
        }
        let backlash = elements.iter().any(|e| e.half_backlash > 0.0);
        let stiffness_variation = elements.iter().any(|e| e.variation.is_some());
        Ok(Self {
            backlash,
            stiffness_variation,
            brake: DiskBrake::default(),
            input_loads: vec![
                InputLoad {
                    input: INPUT_ROTOR_TORQUE,
                    dof: 0,
                    gain: 1.0,
                },
                InputLoad {
                    input: INPUT_GENERATOR_TORQUE,
                    dof: generator,
                    gain: -1.0,
                },
            ],
            section: Section::Whole,
            fidelity,
            dof_names: names,
            mass,
            elements,
            rotor: 0,
            generator,
            speed_ratio,
            bodies,
            meshes,
            shafts,
            gear_ratio,
        })
    }

    pub fn dofs(&self) -> usize {
        self.mass.len()
    }

    /// This model cut in its low-speed shaft, keeping one side ([`Section`]). The rotor side keeps
    /// the rotor's inertia and loses every element; the drivetrain side loses the rotor's DOF, its
    /// LSS grounded at the cut boundary, whose angle and speed load the LSS's downstream body as
    /// inputs (exact for a linear shaft: k·g₀·θ_b + c·g₀·ω_b moved to the right-hand side).
    pub fn into_section(mut self, section: Section) -> Self {
        if self.section != Section::Whole || section == Section::Whole {
            return self;
        }
        self.section = section;
        let rotor = self.rotor;
        match section {
            Section::Whole => {}
            Section::Rotor => {
                self.mass.truncate(1);
                self.dof_names.truncate(1);
                self.speed_ratio.truncate(1);
                self.elements.clear();
                self.generator = 0;
                self.bodies = self
                    .bodies
                    .iter()
                    .enumerate()
                    .map(|(slot, b)| if slot == 0 { *b } else { None })
                    .collect();
                self.meshes.iter_mut().for_each(|m| *m = None);
                self.shafts.iter_mut().for_each(|s| *s = None);
                self.backlash = false;
                self.stiffness_variation = false;
                self.input_loads = vec![
                    InputLoad {
                        input: INPUT_ROTOR_TORQUE,
                        dof: 0,
                        gain: 1.0,
                    },
                    InputLoad {
                        input: INPUT_CUT_TORQUE,
                        dof: 0,
                        gain: -1.0,
                    },
                ];
            }
            Section::Drivetrain => {
                let shift = |d: usize| d - usize::from(d > rotor);
                self.mass.remove(rotor);
                self.dof_names.remove(rotor);
                self.speed_ratio.remove(rotor);
                let first_ratio = self.speed_ratio[0];
                let mut loads = vec![InputLoad {
                    input: INPUT_GENERATOR_TORQUE,
                    dof: shift(self.generator),
                    gain: -1.0,
                }];
                for e in &mut self.elements {
                    if let Some(pos) = e.coeffs.iter().position(|&(d, _)| d == rotor) {
                        // a shaft: linear, so its boundary share is exactly an external load
                        e.boundary = e.coeffs.remove(pos).1;
                        for &(d, g) in &e.coeffs {
                            for (input, gain) in [(INPUT_CUT_ANGLE, e.stiffness), (INPUT_CUT_SPEED, e.damping)] {
                                loads.push(InputLoad {
                                    input,
                                    dof: shift(d),
                                    gain: -g * e.boundary * gain,
                                });
                            }
                        }
                    }
                    e.coeffs.iter_mut().for_each(|(d, _)| *d = shift(*d));
                    if let Some(v) = &mut e.variation {
                        v.dof = shift(v.dof);
                    }
                    // deflections relative to the new DOF 0's rigid rotation; the grounded shaft
                    // has no rigid rotation to subtract
                    e.ratios = if e.boundary != 0.0 {
                        Vec::new()
                    } else {
                        e.coeffs
                            .iter()
                            .map(|&(d, _)| self.speed_ratio[d] / first_ratio)
                            .collect()
                    };
                }
                self.generator = shift(self.generator);
                self.bodies.iter_mut().enumerate().for_each(|(slot, b)| {
                    *b = if slot == 0 { None } else { b.map(|(d, f)| (shift(d), f)) };
                });
                self.input_loads = loads;
            }
        }
        self
    }

    /// The cut boundary's share of element `e`'s deflection and its rate at the boundary's angle and
    /// speed (zero unless the element is the grounded shaft of [`Section::Drivetrain`]).
    fn boundary_share(e: &Element, boundary: (f64, f64)) -> (f64, f64) {
        (e.boundary * boundary.0, e.boundary * boundary.1)
    }

    /// True when some element is nonlinear (backlash) so a step needs Newton iterations.
    pub fn has_backlash(&self) -> bool {
        self.backlash
    }

    pub fn has_stiffness_variation(&self) -> bool {
        self.stiffness_variation
    }

    /// Adds Σ_e w_e · g_e g_eᵀ to `matrix`, with the weight w_e = `weight(index, element)`: the one
    /// assembly loop behind the stiffness, damping and iteration matrices.
    pub fn assemble_into(&self, matrix: &mut nalgebra::DMatrix<f64>, weight: impl Fn(usize, &Element) -> f64) {
        for (index, e) in self.elements.iter().enumerate() {
            let w = weight(index, e);
            if w == 0.0 {
                continue;
            }
            for &(i, gi) in &e.coeffs {
                for &(j, gj) in &e.coeffs {
                    matrix[(i, j)] += w * gi * gj;
                }
            }
        }
    }

    fn assemble(&self, weight: impl Fn(usize, &Element) -> f64) -> nalgebra::DMatrix<f64> {
        let mut m = nalgebra::DMatrix::zeros(self.dofs(), self.dofs());
        self.assemble_into(&mut m, weight);
        m
    }

    /// Stiffness matrix with every element in contact at its nominal (mean) stiffness.
    pub fn stiffness_matrix(&self) -> nalgebra::DMatrix<f64> {
        self.assemble(|_, e| e.stiffness)
    }

    /// Stiffness and damping matrices with every element in contact at nominal stiffness.
    pub fn stiffness_and_damping(&self) -> (nalgebra::DMatrix<f64>, nalgebra::DMatrix<f64>) {
        (self.stiffness_matrix(), self.assemble(|_, e| e.damping))
    }

    /// Largest undamped natural angular frequency with every mesh at its stiffest, rad/s.
    pub fn max_angular_frequency(&self) -> f64 {
        let n = self.dofs();
        let k = self.assemble(|_, e| e.variation.map_or(e.stiffness, |v| v.k_double.max(v.k_single)));
        let inv_sqrt: Vec<f64> = self.mass.iter().map(|m| 1.0 / m.sqrt()).collect();
        let a = nalgebra::DMatrix::from_fn(n, n, |i, j| k[(i, j)] * inv_sqrt[i] * inv_sqrt[j]);
        let eig = nalgebra::SymmetricEigen::new(a);
        eig.eigenvalues.iter().cloned().fold(0.0, f64::max).sqrt()
    }

    /// Angles of a static equilibrium carrying `rotor_torque` at the LSS (balanced at the generator),
    /// rotor angle 0. Backlash gaps are closed on the loaded flank.
    /// Cut away from the rotor ([`Section::Drivetrain`]), the boundary's angle is the 0 the rotor's
    /// would be, and the grounded shaft carries the torque.
    pub fn static_deflection(&self, rotor_torque: f64) -> Result<Vec<f64>, String> {
        let n = self.dofs();
        if self.section == Section::Rotor || (n < 2 && self.section == Section::Whole) {
            return Ok(vec![0.0; n]);
        }
        let mut f = vec![0.0; n];
        if self.section == Section::Whole {
            f[self.rotor] += rotor_torque;
        }
        f[self.generator] -= rotor_torque / self.gear_ratio;
        // A loaded mesh with backlash carries k·(δ − b/2·sign): move that offset to the right-hand side.
        let mut rhs = f.clone();
        let probe = self.solve_pinned(&f)?;
        for e in &self.elements {
            if e.half_backlash > 0.0 {
                let sign = e.deflection(&probe).signum();
                for &(d, g) in &e.coeffs {
                    rhs[d] += e.stiffness * g * e.half_backlash * sign;
                }
            }
        }
        self.solve_pinned(&rhs)
    }

    /// Solves K θ = f with the rotor pinned (the free-free K is singular; cut from the rotor, the
    /// LSS's boundary holds the model).
    fn solve_pinned(&self, f: &[f64]) -> Result<Vec<f64>, String> {
        let n = self.dofs();
        let k = self.stiffness_matrix();
        let pinned = (self.section == Section::Whole).then_some(self.rotor);
        let keep: Vec<usize> = (0..n).filter(|&d| Some(d) != pinned).collect();
        let kr = nalgebra::DMatrix::from_fn(keep.len(), keep.len(), |i, j| k[(keep[i], keep[j])]);
        let fr = nalgebra::DVector::from_iterator(keep.len(), keep.iter().map(|&d| f[d]));
        let x = kr
            .lu()
            .solve(&fr)
            .ok_or("stiffness matrix is singular with the rotor held")?;
        let mut q = vec![0.0; n];
        for (i, &d) in keep.iter().enumerate() {
            q[d] = x[i];
        }
        Ok(q)
    }
}

impl TorsionalModel {
    /// Kinetic energy plus the elastic energy of every element in contact, J; `boundary` is the
    /// cut's (angle, speed) for [`Section::Drivetrain`] (ignored otherwise).
    pub fn stored_energy(&self, q: &[f64], v: &[f64], boundary: (f64, f64)) -> f64 {
        let kinetic: f64 = self.mass.iter().zip(v).map(|(m, w)| 0.5 * m * w * w).sum();
        let elastic: f64 = self
            .elements
            .iter()
            .map(|e| {
                let (x, _) = e.contact(e.deflection(q) + Self::boundary_share(e, boundary).0);
                0.5 * e.stiffness_at(q) * x * x
            })
            .sum();
        kinetic + elastic
    }

    /// Force in element `o` (times its output factor) at the state (q, v) and the cut's (angle,
    /// speed) `boundary`.
    pub fn element_output(&self, o: Option<ForceOutput>, q: &[f64], v: &[f64], boundary: (f64, f64)) -> f64 {
        let Some(o) = o else { return 0.0 };
        let e = &self.elements[o.element];
        let (angle, speed) = Self::boundary_share(e, boundary);
        o.factor * e.force(e.stiffness_at(q), e.deflection(q) + angle, e.deflection(v) + speed)
    }
}

/// Two pattern bits per element (flanks touching, double tooth contact), packed into u64 words.
fn set_bit(key: &mut Vec<u64>, bit: usize) {
    let word = bit / 64;
    if key.len() <= word {
        key.resize(word + 1, 0);
    }
    key[word] |= 1 << (bit % 64);
}

impl SecondOrderSystem for TorsionalModel {
    fn dofs(&self) -> usize {
        self.mass.len()
    }

    fn linearity(&self) -> Linearity {
        if self.backlash || self.stiffness_variation {
            Linearity::PiecewiseLinear
        } else {
            Linearity::Linear
        }
    }

    fn mass(&self) -> Mass<'_> {
        Mass::Diagonal(&self.mass)
    }

    fn input_loads(&self) -> &[InputLoad] {
        &self.input_loads
    }

    fn internal_forces(&self, _t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|x| *x = 0.0);
        for e in &self.elements {
            let f = e.force(e.stiffness_at(q), e.deflection(q), e.deflection(v));
            for &(d, g) in &e.coeffs {
                out[d] += g * f;
            }
        }
    }

    fn add_tangent(&self, _t: f64, q: &[f64], _v: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>) {
        self.assemble_into(j, |_, e| {
            if e.contact(e.deflection(q)).1 {
                c_k * e.stiffness_at(q) + c_c * e.damping
            } else {
                0.0
            }
        });
    }

    fn factor_key(&self, _t: f64, q: &[f64], key: &mut Vec<u64>) {
        key.clear();
        if !self.backlash && !self.stiffness_variation {
            return;
        }
        key.push(0);
        for (i, e) in self.elements.iter().enumerate() {
            if e.half_backlash > 0.0 && e.contact(e.deflection(q)).1 {
                set_bit(key, 2 * i);
            }
            if let Some(v) = &e.variation
                && v.stiffness(q[v.dof]) == v.k_double
            {
                set_bit(key, 2 * i + 1);
            }
        }
    }

    fn friction(&self, u: &[f64]) -> Option<Friction> {
        self.brake.friction(self.generator, u[INPUT_BRAKE_COMMAND])
    }

    /// None when cut from the rotor: the grounded shaft has no rigid rotation.
    fn rigid_mode(&self) -> Option<(&[f64], usize)> {
        (self.section != Section::Drivetrain).then_some((&self.speed_ratio[..], 0))
    }
}
