//! The `gearbox6dof` FMU: variables of modelDescription/gearbox6dof.xml mapped onto
//! [`Gearbox`] and the implicit integrators of [`crate::solver`]. Its connectors are `torsional`'s,
//! so it replaces it in any scene.

use crate::fmi2::fmu::error::{ParameterError, SlaveResult, err};
use crate::fmi2::fmu::slave::{Changed, Log, Slave};
use crate::fmi2::fmu::variables::VarType;
use crate::models::gearbox6dof as xml;
use crate::models::gearbox6dof::vr;
use crate::physics::brake::DiskBrake;
use crate::physics::gearbox::Gearbox;
use crate::physics::gearbox::description::{BearingModel, Description, MeshStiffnessModel};
use crate::physics::gearbox::loads::BearingLoad;
use crate::physics::gearbox::mesh::MeshReport;
use crate::physics::gearbox::model::{INPUT_BRAKE_COMMAND, INPUT_GENERATOR_TORQUE, INPUT_ROTOR_TORQUE};
use crate::physics::gearbox::near::SetTangents;
use crate::physics::gearbox::statics::equilibrium;
use crate::solver::alpha::{Alpha, Newton};
use crate::solver::state::ForcesAt;
use crate::solver::{Driver, DynState, Method, Statistics};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub type Params = xml::Parameters;
pub type Inputs = xml::Inputs;

const INPUT_COUNT: usize = 3;

// The mesh and shaft slots of the XML are `torsional`'s, in value-reference order.
use crate::physics::torsional::{MESH_SLOTS, SHAFT_SLOTS};

/// The XML's bearing outputs, named `<bearing>_radial_load` from value reference 200 on.
fn bearing_slots() -> Vec<&'static str> {
    xml::VARIABLES
        .iter()
        .filter(|v| v.vr >= vr::MAIN_RADIAL_LOAD && v.name.ends_with("_radial_load"))
        .map(|v| v.name.trim_end_matches("_radial_load"))
        .collect()
}

impl Inputs {
    fn write(&self, dt: f64, u: &mut [f64]) {
        u[INPUT_ROTOR_TORQUE] = self.rotor_torque.at(dt);
        u[INPUT_GENERATOR_TORQUE] = self.generator_torque.at(dt);
        u[INPUT_BRAKE_COMMAND] = self.brake_command.at(dt);
    }
}

/// What a set of parameters builds: checked once, shared by snapshots.
#[derive(Debug, Clone)]
pub struct Built {
    pub description: Description,
    pub model: Gearbox,
    pub method: Method,
    pub newton: Newton,
    /// Output slot → mesh, shaft, bearing index in the model.
    meshes: Vec<Option<usize>>,
    shafts: Vec<Option<usize>>,
    bearings: Vec<Option<usize>>,
    /// Bearings of the description no output reports.
    pub unreported: Vec<String>,
}

impl Built {
    /// A driver of this build's method and Newton iteration.
    fn driver(&self) -> Driver {
        let mut d = Driver::new(self.method);
        d.set_newton(self.newton);
        // the step's end forces from its equation: the next step starts from them instead of an
        // evaluation (a read of the loads evaluates only the elements it reports)
        d.set_forces_by_equation(true);
        d
    }
}

impl Params {
    /// The description named by `gearbox`: a preset, an absolute path, or a path under resources/.
    fn description(&self, resources: Option<&Path>) -> SlaveResult<Description> {
        let name = self.gearbox.trim();
        let path = Path::new(name);
        let found = match resources {
            Some(dir) if path.is_relative() && dir.join(path).is_file() => dir.join(path),
            _ => path.to_path_buf(),
        };
        let arg = if found.is_file() {
            found.to_string_lossy().into_owned()
        } else {
            name.to_string()
        };
        Description::load(&arg).map_err(|e| ParameterError::Model(format!("parameter gearbox = {name:?}: {e}")).into())
    }

    pub fn build(&self, resources: Option<&Path>) -> SlaveResult<Built> {
        let mut d = self.description(resources)?;
        if self.slices > 0 {
            d.model.slices = self.slices as usize;
        }
        match self.mesh_stiffness.trim().to_ascii_lowercase().as_str() {
            "" => {}
            "mean" => d.model.mesh_stiffness = MeshStiffnessModel::Mean,
            "varying" => d.model.mesh_stiffness = MeshStiffnessModel::Varying,
            other => {
                return Err(ParameterError::invalid("mesh_stiffness", &other, "use mean or varying (or empty)").into());
            }
        }
        if self.gravity >= 0.0 {
            d.model.gravity = self.gravity;
        }
        match self.bearing_model.trim().to_ascii_lowercase().as_str() {
            "" => {}
            "linear" => d.model.bearings = BearingModel::Linear,
            "lamina" => d.model.bearings = BearingModel::Lamina,
            "lamina-table" => d.model.bearings = BearingModel::LaminaTable,
            other => {
                return Err(ParameterError::invalid(
                    "bearing_model",
                    &other,
                    "use linear, lamina or lamina-table (or empty)",
                )
                .into());
            }
        }
        let rho = self.spectral_radius;
        let radius = |a: Result<Alpha, String>| a.map_err(|e| ParameterError::invalid("spectral_radius", &rho, &e));
        let method = match self.integrator.trim().to_ascii_lowercase().as_str() {
            "implicit" | "newmark" | "trapezoidal" => Method::Implicit(Alpha::NEWMARK),
            "hht" | "hht-alpha" => Method::Implicit(radius(Alpha::hht(rho))?),
            "generalized-alpha" | "generalised-alpha" => Method::Implicit(radius(Alpha::generalised(rho))?),
            "rk4" | "explicit" => {
                return Err(ParameterError::invalid(
                    "integrator",
                    &self.integrator,
                    "RK4 is not offered for the 6-DOF gearbox: its stiffest bearing and mesh modes (tens of kHz) \
                     would need steps of microseconds; use implicit, hht or generalized-alpha",
                )
                .into());
            }
            other => {
                return Err(
                    ParameterError::invalid("integrator", &other, "use implicit, hht or generalized-alpha").into(),
                );
            }
        };
        let sparse = match self.linear_solver.trim().to_ascii_lowercase().as_str() {
            "" | "dense" => false,
            "sparse" => true,
            other => return Err(ParameterError::invalid("linear_solver", &other, "use dense or sparse").into()),
        };
        let newton = Newton {
            tolerance: self.newton_tolerance,
            motion_floor: self.newton_motion_floor,
            sparse,
            ..Newton::parse(&self.newton).ok_or_else(|| {
                ParameterError::invalid("newton", &self.newton, "use pattern, kept, predicted or kept+predicted")
            })?
        };
        let mut model = Gearbox::new(&d).map_err(|e| ParameterError::Model(format!("gearbox {:?}: {e}", d.name)))?;
        let rated_generator = model.rated_rotor_torque.map(|t| t / model.gear_ratio);
        let brake_torque_max = match (self.brake_torque_max > 0.0, rated_generator) {
            (true, _) => self.brake_torque_max,
            (false, Some(t)) => 1.5 * t,
            (false, None) => 0.0,
        };
        model.brake = DiskBrake {
            torque_max: brake_torque_max,
            static_ratio: self.brake_static_ratio,
        };
        let meshes = MESH_SLOTS
            .iter()
            .map(|s| model.meshes.iter().position(|m| m.name == *s))
            .collect();
        let shafts = SHAFT_SLOTS
            .iter()
            .map(|s| model.shafts.iter().position(|m| m.name == *s))
            .collect();
        let slots = bearing_slots();
        let bearings = slots
            .iter()
            .map(|s| model.bearings.iter().position(|b| b.name == *s))
            .collect();
        let unreported = model
            .bearings
            .iter()
            .filter(|b| !slots.contains(&b.name.as_str()))
            .map(|b| b.name.clone())
            .collect();
        Ok(Built {
            description: d,
            model,
            method,
            newton,
            meshes,
            shafts,
            bearings,
            unreported,
        })
    }

    /// The loaded static equilibrium at the initial speed, the chain turning rigidly, carrying
    /// `input_torque` with `initial_torque_from_input`, else `initial_rotor_torque`.
    fn initial_state(&self, b: &Built, input_torque: f64) -> SlaveResult<DynState> {
        let m = &b.model;
        let rated_speed = b.description.rated_rotor_speed_rpm.unwrap_or(0.0) * std::f64::consts::TAU / 60.0;
        let t = if self.initial_torque_from_input {
            input_torque
        } else {
            self.initial_rotor_torque
        };
        let u = [t, t / m.gear_ratio, 0.0];
        let (q, v) = equilibrium(m, &u, self.initial_speed_ratio * rated_speed)
            .map_err(|e| err(format!("initial equilibrium of gearbox {:?}: {e}", m.name)))?;
        Ok(DynState::new(q, v))
    }
}

#[derive(Clone, Serialize, Deserialize)]
pub struct Gearbox6dofSlave {
    /// Shared, copy-on-write, with the states taken while they are unchanged: taking or restoring a
    /// state compares a pointer instead of every parameter.
    pub params: std::sync::Arc<Params>,
    pub inputs: Inputs,
    resources: Option<PathBuf>,
    state: Option<DynState>,
    #[serde(skip)]
    built: Option<Arc<Built>>,
    #[serde(skip, default = "implicit_driver")]
    driver: Driver,
    /// The roller sets' last exact evaluations (`roller_update_distance`): history no state holds,
    /// forgotten with the driver's factorisations.
    #[serde(skip)]
    tangents: SetTangents,
    /// Loads of the current state (a master reads a hundred outputs per step).
    #[serde(skip)]
    loads: LoadsCache,
    /// f_int less the rotor's loads where the loads were last evaluated, for the next step.
    #[serde(skip)]
    state_forces: StateForces,
    /// Once stepped, the state is the simulation's: an input no longer rebuilds it.
    #[serde(default)]
    stepped: bool,
}

/// f_int less the rotor's loads at the state the last step ended in, as the step's equation of motion
/// left it ([`Driver::set_forces_by_equation`]), and a scratch vector for the rotor's loads.
#[derive(Clone, Default)]
struct StateForces {
    at: ForcesAt,
    rotor: Vec<f64>,
}

/// The loads of the current state, each mesh's, bearing's and shaft's evaluated on its own the first
/// time an output of it is read in that state: a master that records a few load outputs (a campaign's
/// channels) pays for their elements, not for every mesh's slices and every roller set's rollers. The
/// vectors stay between steps.
#[derive(Clone, Default)]
struct LoadsCache {
    /// Whether the entries below belong to the current state (false: every entry is stale).
    valid: bool,
    meshes: Vec<Option<MeshReport>>,
    bearings: Vec<Option<BearingLoad>>,
    shafts: Vec<Option<f64>>,
    /// One mesh's per-slice loads, and f_int's part of the element evaluated (both discarded).
    slices: Vec<f64>,
    scratch: Vec<f64>,
}

impl LoadsCache {
    /// Forgets every entry when they belong to an earlier state, sized for `model`.
    fn refresh(&mut self, model: &Gearbox) {
        if !self.valid {
            self.meshes.clear();
            self.meshes.resize(model.meshes.len(), None);
            self.bearings.clear();
            self.bearings.resize(model.bearings.len(), None);
            self.shafts.clear();
            self.shafts.resize(model.shafts.len(), None);
            self.valid = true;
        }
    }

    /// Mesh `i`'s report in state `st`.
    fn mesh(&mut self, model: &Gearbox, st: &DynState, i: usize) -> MeshReport {
        if let Some(r) = self.meshes[i] {
            return r;
        }
        self.slices.resize(model.meshes[i].slices(), 0.0);
        self.scratch.clear();
        self.scratch.resize(st.q.len(), 0.0);
        let r = model.mesh_report(i, &st.q, &st.v, &mut self.slices, &mut self.scratch);
        self.meshes[i] = Some(r);
        r
    }

    /// Bearing `i`'s loads in state `st`.
    fn bearing(&mut self, model: &Gearbox, st: &DynState, i: usize) -> BearingLoad {
        if let Some(l) = self.bearings[i] {
            return l;
        }
        self.scratch.clear();
        self.scratch.resize(st.q.len(), 0.0);
        let l = model.bearing_load(i, &st.q, &st.v, &mut self.scratch);
        self.bearings[i] = Some(l);
        l
    }

    /// Shaft `i`'s torsion in state `st`.
    fn shaft(&mut self, model: &Gearbox, st: &DynState, i: usize) -> f64 {
        *self.shafts[i].get_or_insert_with(|| model.shaft_torque(i, &st.q, &st.v))
    }

    /// The output `r` of the loads: shaft torques, load sharing, each bearing's and each mesh's.
    fn output(&mut self, b: &Built, st: &DynState, r: u32) -> SlaveResult<f64> {
        self.refresh(&b.model);
        let m = &b.model;
        Ok(match r {
            vr::LSS_TORQUE..=vr::HSS_TORQUE => {
                b.shafts[(r - vr::LSS_TORQUE) as usize].map_or(0.0, |i| self.shaft(m, st, i))
            }
            vr::LOAD_SHARING_FACTOR | vr::LOAD_SHARING_FACTOR_2 => {
                let stage = if r == vr::LOAD_SHARING_FACTOR { "" } else { "2" };
                m.load_sharing_by(stage, |i| self.mesh(m, st, i).force).unwrap_or(0.0)
            }
            r if r >= vr::MAIN_RADIAL_LOAD => {
                let k = (r - vr::MAIN_RADIAL_LOAD) as usize;
                let slot = k / BEARING_OUTPUTS;
                match b.bearings.get(slot).copied().flatten() {
                    Some(i) => bearing_output(&self.bearing(m, st, i), k % BEARING_OUTPUTS),
                    None if slot < b.bearings.len() => 0.0,
                    None => return Err(xml::no_getter(VarType::Real, r)),
                }
            }
            r => {
                let Some((family, first)) = FAMILIES
                    .iter()
                    .enumerate()
                    .find(|(_, f)| (**f..**f + MESH_SLOTS.len() as u32).contains(&r))
                else {
                    return Err(xml::no_getter(VarType::Real, r));
                };
                b.meshes[(r - first) as usize].map_or(0.0, |i| {
                    let m = self.mesh(m, st, i);
                    match family {
                        0 => m.force,
                        1 => m.max_slice,
                        2 => m.max_position,
                        3 => m.face_load_factor,
                        4 => m.transmission_error,
                        5 => m.contact.pressure,
                        6 => m.contact.max_shear,
                        _ => m.contact.max_shear_depth,
                    }
                })
            }
        })
    }
}

fn implicit_driver() -> Driver {
    Driver::new(Method::Implicit(Alpha::NEWMARK))
}

impl Gearbox6dofSlave {
    pub fn ensure(&mut self) -> SlaveResult<(&Built, &mut DynState)> {
        if self.built.is_none() {
            let built = self.params.build(self.resources.as_deref())?;
            self.driver = built.driver();
            self.tangents.forget();
            self.built = Some(Arc::new(built));
            self.loads.valid = false;
            self.state_forces.at.valid = false;
        }
        if self.state.is_none() {
            // the initial equilibrium carries the rotor's moments and thrust as the inputs have them
            self.apply_rotor_loads();
            let built = self.built.as_ref().unwrap();
            self.state = Some(self.params.initial_state(built, self.inputs.rotor_torque.value())?);
            self.loads.valid = false;
            self.tangents.forget();
        }
        let built = self.built.as_ref().unwrap();
        Ok((built, self.state.as_mut().unwrap()))
    }

    /// With `initial_torque_from_input`, an input set before the first step rebuilds the initial
    /// equilibrium (the master propagates the rotor's initial torque in initialization mode).
    fn changed(&mut self, what: Changed) {
        if what == Changed::Parameter {
            self.built = None;
            self.state = None;
        }
        if what == Changed::Input && self.params.initial_torque_from_input && !self.stepped {
            self.state = None;
        }
        self.loads.valid = false;
    }

    pub fn solver_statistics(&self) -> Statistics {
        self.driver.stats
    }

    pub fn built(&mut self) -> SlaveResult<&Built> {
        Ok(self.ensure()?.0)
    }
}

/// Per-mesh output families: value reference of the first slot.
const FAMILIES: [u32; 8] = [
    vr::MESH_FORCE_RING_PLANET_1,
    vr::MAX_SLICE_LOAD_RING_PLANET_1,
    vr::MAX_SLICE_POSITION_RING_PLANET_1,
    vr::FACE_LOAD_FACTOR_RING_PLANET_1,
    vr::TRANSMISSION_ERROR_RING_PLANET_1,
    vr::MAX_CONTACT_PRESSURE_RING_PLANET_1,
    vr::MAX_SUBSURFACE_SHEAR_RING_PLANET_1,
    vr::MAX_SHEAR_DEPTH_RING_PLANET_1,
];

/// Outputs per bearing, in value-reference order from `<first bearing>_radial_load` on.
const BEARING_OUTPUTS: usize = 9;

/// The outputs that need no loads, read straight off the model and state; None for the others.
fn state_output(b: &Built, st: &DynState, r: u32) -> Option<f64> {
    let m = &b.model;
    let rated = m.rated_rotor_torque.unwrap_or(0.0);
    Some(match r {
        vr::GEAR_RATIO => m.gear_ratio,
        vr::RATED_ROTOR_TORQUE => rated,
        vr::RATED_GENERATOR_TORQUE => rated / m.gear_ratio,
        vr::ROTOR_SPEED => m.speed(m.input_body, &st.v),
        vr::GENERATOR_SPEED => m.speed(m.output_body, &st.v),
        vr::MAIN_SHAFT_TILT_RATE => m.input_tilt_rates(&st.q, &st.v)[0],
        vr::MAIN_SHAFT_YAW_RATE => m.input_tilt_rates(&st.q, &st.v)[1],
        vr::BRAKE_TORQUE => -st.friction_force * m.output_sign,
        _ => return None,
    })
}

fn bearing_output(l: &BearingLoad, k: usize) -> f64 {
    let s = &l.stresses;
    [
        l.radial,
        l.axial,
        l.tilting,
        l.rollers_in_contact as f64,
        l.max_roller_load,
        s.inner_pressure,
        s.outer_pressure,
        s.max_shear,
        s.max_shear_depth,
    ][k]
}

impl Slave for Gearbox6dofSlave {
    crate::slave_interface_from_xml!();

    /// The integrator's workspace (cached factorisations) and the loads cache stay out of a state.
    fn snapshot(&self) -> Self {
        Self {
            params: self.params.clone(),
            inputs: self.inputs,
            resources: self.resources.clone(),
            state: self.state.clone(),
            built: self.built.clone(),
            driver: implicit_driver(),
            tangents: SetTangents::default(),
            loads: LoadsCache::default(),
            state_forces: StateForces::default(),
            stepped: self.stepped,
        }
    }

    /// Reuses the earlier snapshot's vectors and strings.
    fn snapshot_into(&self, into: &mut Self) {
        if !std::sync::Arc::ptr_eq(&into.params, &self.params) {
            into.params = std::sync::Arc::clone(&self.params);
        }
        into.inputs.clone_from(&self.inputs);
        into.resources.clone_from(&self.resources);
        into.state.clone_from(&self.state);
        super::share_build(&mut into.built, &self.built);
        into.loads.valid = false;
        into.state_forces.at.valid = false;
        into.stepped = self.stepped;
    }

    /// Keeps this instance's integrator while the model is the snapshot's own (the same build), less its
    /// factorisations, which no state holds (where a J was assembled is history).
    fn restore(&mut self, snap: &Self) {
        let same_model = super::same_build(&self.built, &snap.built);
        snap.snapshot_into(self);
        if same_model {
            self.driver.forget_factorisations();
        } else {
            self.driver = self.built.as_ref().map_or_else(implicit_driver, |b| b.driver());
        }
        self.tangents.forget();
    }

    /// The run goes on without factorisations and without the last step's end forces, as a run
    /// restored from the state starts (see `restore`): the next step evaluates its start forces, so
    /// the run that goes on and every rerun from the state repeat bit for bit.
    fn state_taken(&mut self) {
        self.driver.forget_factorisations();
        self.tangents.forget();
        self.state_forces.at.valid = false;
    }

    fn instantiate(resources: Option<&Path>) -> Self {
        Self {
            params: std::sync::Arc::default(),
            inputs: Inputs::default(),
            resources: resources.map(Path::to_path_buf),
            state: None,
            built: None,
            driver: implicit_driver(),
            tangents: SetTangents::default(),
            loads: LoadsCache::default(),
            state_forces: StateForces::default(),
            stepped: false,
        }
    }

    /// An array of one.
    fn get_real(&mut self, r: u32) -> SlaveResult<f64> {
        let mut value = [0.0];
        self.get_reals(&[r], &mut value)?;
        Ok(value[0])
    }

    /// A recorder's row: the model and the loads are checked once for the array instead of once per
    /// value, the loads taken only when a value needs them.
    fn get_reals(&mut self, vrs: &[u32], values: &mut [f64]) -> SlaveResult<()> {
        let mut ensured = false;
        for (&r, value) in vrs.iter().zip(values) {
            if let Some(v) = xml::get_real(&self.params, &self.inputs, r) {
                *value = v;
                continue;
            }
            if !ensured {
                self.ensure()?;
                ensured = true;
            }
            let (b, st) = (
                self.built.as_deref().expect("built by ensure"),
                self.state.as_ref().expect("by ensure"),
            );
            *value = match state_output(b, st, r) {
                Some(v) => v,
                None => self.loads.output(b, st, r)?,
            };
        }
        Ok(())
    }

    fn set_real(&mut self, r: u32, value: f64, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_real(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn get_integer(&mut self, r: u32) -> SlaveResult<i32> {
        if let Some(v) = xml::get_integer(&self.params, &self.inputs, r) {
            return Ok(v);
        }
        match r {
            vr::DOF_COUNT => Ok(self.ensure()?.0.model.dofs() as i32),
            _ => Err(xml::no_getter(VarType::Integer, r)),
        }
    }

    fn set_integer(&mut self, r: u32, value: i32, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_integer(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn get_boolean(&mut self, r: u32) -> SlaveResult<bool> {
        if let Some(v) = xml::get_boolean(&self.params, &self.inputs, r) {
            return Ok(v);
        }
        match r {
            vr::BRAKE_LOCKED => Ok(self.ensure()?.1.locked),
            _ => Err(xml::no_getter(VarType::Boolean, r)),
        }
    }

    fn set_boolean(&mut self, r: u32, value: bool, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_boolean(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn get_string(&mut self, r: u32) -> SlaveResult<String> {
        xml::get_string(&self.params, &self.inputs, r).ok_or_else(|| xml::no_getter(VarType::String, r))
    }

    fn set_string(&mut self, r: u32, value: &str, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_string(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn initialize(&mut self, _start_time: f64, log: &mut dyn Log) -> SlaveResult<()> {
        self.ensure()?;
        let unreported = &self.built.as_ref().unwrap().unreported;
        if !unreported.is_empty() {
            log.warning(&format!(
                "bearings {} have no output variable (the FMU reports the presets' bearing names); \
                 `windrive gearbox` reports every bearing",
                unreported.join(", ")
            ));
        }
        Ok(())
    }

    fn set_input_derivative(&mut self, r: u32, order: i32, value: f64) -> SlaveResult<()> {
        self.inputs.set_derivative(r, order, value)
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut dyn Log) -> SlaveResult<()> {
        self.ensure()?;
        if let Some(built) = &self.built {
            check_torques(&self.inputs, &built.model, h)?;
        }
        self.stepped = true;
        self.loads.valid = false;
        self.apply_rotor_loads();
        let built = self.built.take().unwrap();
        let result = self.step_with(&built, t, h, log);
        self.built = Some(built);
        result
    }
}

/// Largest rotor or generator torque, in multiples of the gearbox's rated torque, a step accepts.
/// An estimate with a wide margin: a drivetrain's worst transients (emergency stops, a generator's
/// short circuit) reach a few times rated torque; at thousands of times rated the contacts deform
/// beyond their laws and the step would halve for minutes before failing.
pub const MAX_TORQUE_OVER_RATED: f64 = 20.0;

/// Refuses a torque input beyond [`MAX_TORQUE_OVER_RATED`] times its rating over the step from 0 to
/// `h` (the input polynomial at both ends), naming the input; a description without a rated point
/// has no limit.
fn check_torques(inputs: &Inputs, model: &Gearbox, h: f64) -> SlaveResult<()> {
    let Some(rated) = model.rated_rotor_torque.filter(|r| *r > 0.0) else {
        return Ok(());
    };
    let rated_generator = rated / model.gear_ratio;
    for (name, input, rating) in [
        ("rotor_torque", &inputs.rotor_torque, rated),
        ("generator_torque", &inputs.generator_torque, rated_generator),
    ] {
        for dt in [0.0, h] {
            let value = input.at(dt);
            if value.abs() > MAX_TORQUE_OVER_RATED * rating {
                return Err(err(format!(
                    "input {name} = {value:e} N·m is {:.0} times the gearbox's rated {rating:.6e} N·m, beyond the \
                     {MAX_TORQUE_OVER_RATED}× any load case of a drivetrain reaches: refused before stepping",
                    value.abs() / rating
                )));
            }
        }
    }
    Ok(())
}

impl Gearbox6dofSlave {
    /// The main-shaft moments (housing frame, turned into the rotor's frame with its angle) and the
    /// thrust, held over the communication step (they change at rotor frequencies).
    fn apply_rotor_loads(&mut self) {
        let moment = [
            self.inputs.main_shaft_tilt_moment.at(0.0),
            self.inputs.main_shaft_yaw_moment.at(0.0),
        ];
        let thrust = self.inputs.rotor_thrust.at(0.0);
        if let Some(built) = self.built.as_mut()
            && (built.model.external_moment != moment || built.model.thrust != thrust)
        {
            let model = &mut Arc::make_mut(built).model;
            model.external_moment = moment;
            model.thrust = thrust;
        }
    }

    fn step_with(&mut self, built: &Built, t: f64, h: f64, log: &mut dyn Log) -> SlaveResult<()> {
        let inputs = &self.inputs;
        let st = self.state.as_mut().unwrap();
        let kept = &mut self.state_forces;
        if let Some(forces) = kept.at.at(&st.q, &st.v) {
            // the last step's end forces with this step's rotor loads
            self.driver.give_start_forces(st.q.len(), |fi| {
                fi.copy_from_slice(forces);
                built.model.add_rotor_loads(&st.q, fi);
            });
        }
        kept.at.valid = false;
        self.driver.max_steps_per_call = self.params.max_steps_per_call;
        let result = self.driver.advance(
            &self.tangents.around(&built.model, self.params.roller_update_distance),
            st,
            t,
            h,
            self.params.max_internal_step,
            INPUT_COUNT,
            |dt, u| inputs.write(dt, u),
        );
        super::log_brake_events(&self.driver.events, log);
        result.map_err(|e| err(format!("{e} (communication step from t = {t} s, h = {h} s)")))?;
        if let Some(forces) = self.driver.end_forces(&st.q, &st.v) {
            // kept less this step's rotor loads, which the next step's inputs replace
            let StateForces { at, rotor } = kept;
            rotor.clear();
            rotor.resize(forces.len(), 0.0);
            built.model.add_rotor_loads(&st.q, rotor);
            at.forces.clear();
            at.forces.extend(forces.iter().zip(rotor.iter()).map(|(f, r)| f - r));
            at.belong_to(&st.q, &st.v);
        }
        self.inputs.advance(h);
        Ok(())
    }
}
