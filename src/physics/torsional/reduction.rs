//! [`TorsionalModel::new`]: the full assembly reduced to the asked fidelity (rigid meshes for `Five`,
//! everything lumped to two bodies for `Two`), with its output slots.

use super::assembly::{assemble_full, shaft_slot};
use super::{
    BODY_SLOTS, Element, Fidelity, ForceOutput, INPUT_GENERATOR_TORQUE, INPUT_ROTOR_TORQUE, Lumping, MESH_SLOTS,
    ModelOptions, Section, TorsionalModel,
};
use crate::physics::brake::DiskBrake;
use crate::physics::drivetrain::{Drivetrain, Stage};
use crate::solver::system::InputLoad;

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
}
