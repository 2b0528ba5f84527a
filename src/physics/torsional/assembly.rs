//! The full model's bodies and elements from a [`Drivetrain`] description: every body one DOF, every
//! shaft and mesh one element, with the quasi-static mesh-force factors of each stage.

use super::{Element, MeshStiffnessVariation, ModelOptions, SHAFT_SLOTS};
use crate::physics::drivetrain::{Drivetrain, Stage};
use std::f64::consts::TAU;

pub(super) struct FullBody {
    pub(super) slot: Option<usize>,
    pub(super) name: String,
    pub(super) inertia: f64,
    pub(super) ratio: f64,
    /// Index of the stage the body belongs to (None for rotor and generator).
    pub(super) stage: Option<usize>,
    /// A planet: its spin inertia is what the thesis's 5-mass lumping leaves out.
    pub(super) planet: bool,
}

pub(super) struct Assembly {
    pub(super) bodies: Vec<FullBody>,
    pub(super) elements: Vec<Element>,
    /// (mesh slot, element index) of the full model.
    pub(super) mesh_slots: Vec<(usize, usize)>,
    /// Per stage: the factor from stage input torque to each of its mesh slots' quasi-static force.
    pub(super) quasi_static_mesh: Vec<Vec<(usize, f64)>>,
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

pub(super) fn assemble_full(dt: &Drivetrain, opt: &ModelOptions) -> Assembly {
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
pub(super) fn shaft_slot(i: usize, n: usize) -> usize {
    if i == 0 {
        0
    } else if i == n - 1 {
        3
    } else {
        i.min(2)
    }
}
