//! [`Gearbox::new`]: the model assembled from its description, stage by stage ([`planetary`],
//! [`parallel`]), its shafts ([`shafts`]) and meshes ([`meshes`]) on the [`builder`]'s bodies.

use crate::physics::gearbox::contact::GearContact;
use crate::physics::gearbox::description::{self as desc, Description, ForceLaw};
use crate::physics::gearbox::model::{
    BodyKind, Gearbox, INPUT_BRAKE_COMMAND, INPUT_GENERATOR_TORQUE, INPUT_ROTOR_TORQUE, SPIN,
};
use crate::solver::system::{InputLoad, SparseColumns};
use builder::{Builder, MeshSpec, inertia};
use meshes::{add_mesh, rigid_mode};
use shafts::{add_beam_nodes, finish};
use std::f64::consts::TAU;

mod builder;
mod meshes;
mod parallel;
mod planetary;
mod shafts;

impl Gearbox {
    /// Builds the model. Errors name the description field at fault.
    pub fn new(d: &Description) -> Result<Gearbox, String> {
        let mut b = Builder {
            d,
            bodies: Vec::new(),
            springs: Vec::new(),
            bearings: Vec::new(),
            rollers: Vec::new(),
            tables: Default::default(),
            downwind_plate: None,
            webs: Vec::new(),
            beam_nodes: Vec::new(),
            meshes: Vec::new(),
            geometry: Vec::new(),
            shafts: Vec::new(),
            dofs: 0,
        };
        let density = d.model.density;
        let first_planetary = matches!(d.stages.first(), Some(desc::Stage::Planetary(_)));
        // the rotor turns with the first carrier's frame when that stage is planetary: its index is
        // known before the carrier is added (rotor first, carrier next)
        let mut upstream: Option<(usize, desc::Shaft, String)> = None;
        let mut mesh_specs: Vec<MeshSpec> = Vec::new();
        if let Some(r) = &d.rotor {
            let frame = if first_planetary { Some(1) } else { None };
            let i = b.add_body(
                "rotor".into(),
                BodyKind::Rotor,
                None,
                frame,
                [0.0; 2],
                inertia(r, None, density, "rotor")?,
                false,
            );
            let shaft = r.shaft.ok_or("rotor: give its shaft (the LSS) to the first stage")?;
            upstream = Some((i, shaft, "lss".into()));
        }
        let stages = d.stages.len();
        let mut last_output = 0;
        let mut planetary_count = 0;
        let mut parallel_count = 0;
        for (s, stage) in d.stages.iter().enumerate() {
            let at = |f: &str| format!("stage[{}].{f}", s + 1);
            let (input, output, out_body) = match stage {
                desc::Stage::Planetary(p) => {
                    planetary_count += 1;
                    let (carrier, sun) = planetary::add_stage(&mut b, s, p, planetary_count, &mut mesh_specs)?;
                    (carrier, sun, &p.sun)
                }
                desc::Stage::Parallel(p) => {
                    parallel_count += 1;
                    // the gear sits on the axis of the body upstream; the pinion off it
                    let base = match &upstream {
                        Some((u, _, _)) if b.bodies[*u].frame.is_none() => b.bodies[*u].centre,
                        _ => [0.0; 2],
                    };
                    let (gear, pinion) = parallel::add_stage(&mut b, s, p, parallel_count, base, &mut mesh_specs)?;
                    (gear, pinion, &p.pinion)
                }
            };
            if let Some((u, shaft, name)) = upstream.take() {
                b.shafts.push((u, input, shaft, name));
            }
            last_output = output;
            let name = if s + 1 == stages {
                "hss".to_string()
            } else {
                format!("is{}", s + 1)
            };
            upstream = match out_body.shaft {
                Some(sh) => Some((output, sh, name)),
                None if s + 1 < stages || d.generator.is_some() => {
                    return Err(format!(
                        "{}: give the shaft to the next body",
                        at(if matches!(stage, desc::Stage::Planetary(_)) {
                            "sun"
                        } else {
                            "pinion"
                        })
                    ));
                }
                None => None,
            };
        }
        // the rotor's bearings once the carrier whose frame it turns in exists
        if let Some(r) = &d.rotor {
            b.supports("", 0, r, None, [0.0; 2]);
        }
        if let Some(g) = &d.generator {
            let (u, shaft, name) = upstream.take().ok_or("generator: the last stage has no shaft to it")?;
            let centre = b.bodies[u].centre;
            let frame = b.bodies[u].frame;
            let i = b.add_body(
                "generator".into(),
                BodyKind::Generator,
                None,
                frame,
                centre,
                inertia(g, None, density, "generator")?,
                false,
            );
            b.supports("", i, g, None, [0.0; 2]);
            b.shafts.push((u, i, shaft, name));
            last_output = i;
        }
        add_beam_nodes(&mut b);
        let mut names: Vec<&str> = b.bearings.iter().map(|x| x.name.as_str()).collect();
        names.sort_unstable();
        if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
            return Err(format!(
                "two bearings are named {:?}: bearing names must be unique",
                w[0]
            ));
        }
        // The drive flank of each mesh is the one loaded when the input turns forwards under a
        // driving torque: build the rows once, read the kinematics off them (a rigid rotation does
        // not compress a mesh, whichever flank), then orient each line of action so the driver's
        // point moves along it.
        for spec in &mesh_specs {
            add_mesh(&mut b, spec, 1.0)?;
        }
        // the chain's first body (rotor, or the first stage's input) takes the rotor torque
        let input_body = 0;
        let output_body = last_output;
        let rigid = rigid_mode(&b, input_body);
        if let Some(r) = &rigid {
            let meshes = std::mem::take(&mut b.meshes);
            b.geometry.clear();
            for (spec, mesh) in mesh_specs.iter().zip(&meshes) {
                let spin_rel = |body: usize| -> f64 {
                    let own = b.bodies[body].first.map_or(0.0, |f| r[f + SPIN]);
                    own - b.frame_spin(body).map_or(0.0, |f| r[f])
                };
                // the driver's lever (r_A × n)_z times its relative speed is the power it delivers along n
                let coefficient = mesh.driver_arm;
                let sigma = if coefficient * spin_rel(spec.driver) >= 0.0 {
                    1.0
                } else {
                    -1.0
                };
                add_mesh(&mut b, spec, sigma)?;
            }
        }
        let (shafts, mass) = finish(&mut b, &rigid)?;
        let out_spin = b.bodies[output_body].first.map_or(0, |f| f + SPIN);
        let in_spin = b.bodies[input_body].first.map_or(0, |f| f + SPIN);
        let output_sign = rigid.as_ref().map_or(1.0, |r| r[out_spin].signum());
        let gear_ratio = rigid.as_ref().map_or(1.0, |r| r[out_spin].abs());
        let input_loads = vec![
            InputLoad {
                input: INPUT_ROTOR_TORQUE,
                dof: in_spin,
                gain: 1.0,
            },
            InputLoad {
                input: INPUT_GENERATOR_TORQUE,
                dof: out_spin,
                gain: -output_sign,
            },
            // the brake acts through `friction`; listed so the input count is three
            InputLoad {
                input: INPUT_BRAKE_COMMAND,
                dof: out_spin,
                gain: 0.0,
            },
        ];
        let tilt = d.model.shaft_tilt_deg.to_radians();
        let g = d.model.gravity;
        let rated = match (d.rated_power, d.rated_rotor_speed_rpm) {
            (Some(p), Some(rpm)) if rpm > 0.0 => Some(p / (rpm * TAU / 60.0)),
            _ => None,
        };
        // roller sets are nearly linear between contact patterns (their key): not a reason to
        // rebuild the Jacobian at every iterate
        let nonlinear = matches!(d.model.force_law, ForceLaw::Impact { .. });
        let contacts = b
            .geometry
            .iter()
            .zip(&b.meshes)
            .map(|(g, m)| GearContact::new(g, m.face_width, m.slices()))
            .collect();
        Ok(Gearbox {
            name: d.name.clone(),
            bodies: b.bodies,
            springs: b.springs,
            bearings: b.bearings,
            rollers: b.rollers,
            shafts,
            meshes: b.meshes,
            mass_entries: SparseColumns::of(&mass),
            mass,
            input_loads,
            rigid,
            rigid_dof: in_spin,
            gravity: [0.0, -g * tilt.cos(), g * tilt.sin()],
            external_moment: [0.0; 2],
            thrust: 0.0,
            input_body,
            output_body,
            output_sign,
            gear_ratio,
            rated_rotor_torque: rated,
            nonlinear,
            brake: Default::default(),
            contacts,
            geometry: b.geometry,
        })
    }
}
