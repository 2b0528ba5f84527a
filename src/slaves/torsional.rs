//! The `torsional` FMU: variables of modelDescription/torsional.xml mapped onto [`TorsionalModel`]
//! and the integrators of [`crate::solver`].

use crate::fmi2::fmu::error::{ParameterError, SlaveResult, err};
use crate::fmi2::fmu::slave::{Changed, Log, Slave};
use crate::fmi2::fmu::variables::VarType;
use crate::models::torsional as xml;
use crate::models::torsional::vr;
use crate::physics::brake::DiskBrake;
use crate::physics::drivetrain::Drivetrain;
use crate::physics::torsional::{
    ElementLoad, ElementTable, Fidelity, INPUT_BRAKE_COMMAND, INPUT_COUNT, INPUT_CUT_ANGLE, INPUT_CUT_SPEED,
    INPUT_CUT_TORQUE, INPUT_GENERATOR_TORQUE, INPUT_ROTOR_TORQUE, Lumping, ModelOptions, Section, TorsionalModel,
};
use crate::solver::alpha::Alpha;
use crate::solver::{Driver, DynState, Method, Statistics, rk4};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;

/// Every parameter of torsional.xml (generated from it), at its start value by default.
pub type Params = xml::Parameters;
/// Input values and their time derivatives (set by fmi2SetRealInputDerivatives, orders 1 and 2).
pub type Inputs = xml::Inputs;

impl Inputs {
    /// The model's inputs `dt` seconds after the communication point (rotor torque, generator torque,
    /// brake command, the model clamping the command to [0, 1]; the cut's angle from `cut_angle` at
    /// the communication point, its speed and torque).
    fn write(&self, cut_angle: f64, dt: f64, u: &mut [f64]) {
        // one length check instead of one per input (the driver samples the inputs twice a step)
        let u: &mut [f64; INPUT_COUNT] = (&mut u[..INPUT_COUNT]).try_into().expect("INPUT_COUNT inputs");
        u[INPUT_ROTOR_TORQUE] = self.rotor_torque.at(dt);
        u[INPUT_GENERATOR_TORQUE] = self.generator_torque.at(dt);
        u[INPUT_BRAKE_COMMAND] = self.brake_command.at(dt);
        u[INPUT_CUT_ANGLE] = cut_angle + self.cut_speed.integral(dt);
        u[INPUT_CUT_SPEED] = self.cut_speed.at(dt);
        u[INPUT_CUT_TORQUE] = self.cut_torque.at(dt);
    }
}

/// What a set of parameters builds: checked once, shared by snapshots.
#[derive(Debug)]
pub struct Built {
    pub drivetrain: Drivetrain,
    pub model: TorsionalModel,
    /// The integrator and its parameters (`integrator`, `spectral_radius`).
    pub method: Method,
    pub brake_torque_max: f64,
    pub rk4_step_limit: f64,
    /// The model's elements packed for reading their loads (every element output reads through it).
    pub elements: ElementTable,
}

#[derive(Clone, Serialize, Deserialize)]
pub struct TorsionalSlave {
    /// Shared, copy-on-write, with the states taken while they are unchanged: taking or restoring a
    /// state compares a pointer instead of every parameter.
    pub params: std::sync::Arc<Params>,
    pub inputs: Inputs,
    /// None until the model is first needed; rebuilt from `params` after deserialisation.
    state: Option<DynState>,
    /// Angle of the LSS's rotor end at the communication point (section = drivetrain: the integral of
    /// `cut_speed`; 0 at the static deflection), rad.
    #[serde(default)]
    cut_angle: f64,
    #[serde(skip)]
    built: Option<Arc<Built>>,
    #[serde(skip, default = "implicit_driver")]
    driver: Driver,
    #[serde(skip)]
    read_plan: ReadPlan,
}

fn implicit_driver() -> Driver {
    Driver::new(Method::Implicit(Alpha::NEWMARK))
}

impl Params {
    pub fn build(&self) -> SlaveResult<Built> {
        let drivetrain = Drivetrain::preset(&self.preset).ok_or_else(|| {
            ParameterError::invalid("preset", &self.preset, "unknown drivetrain, use A, B, C, D or P")
        })?;
        let fidelity = Fidelity::parse(&self.fidelity)
            .ok_or_else(|| ParameterError::invalid("fidelity", &self.fidelity, "use 2, 5 or full"))?;
        let lumping = Lumping::parse(&self.lumping)
            .ok_or_else(|| ParameterError::invalid("lumping", &self.lumping, "use physical or thesis"))?;
        let section = Section::parse(&self.section)
            .ok_or_else(|| ParameterError::invalid("section", &self.section, "use whole, rotor or drivetrain"))?;
        let mut drivetrain = drivetrain;
        for shaft in &mut drivetrain.shafts {
            shaft.stiffness *= self.shaft_stiffness_scale;
        }
        let rho = self.spectral_radius;
        let radius =
            |alpha: Result<Alpha, String>| alpha.map_err(|e| ParameterError::invalid("spectral_radius", &rho, &e));
        let integrator = self.integrator.trim().to_ascii_lowercase();
        // RK4's limit is known once the model is built; it is filled in below
        let mut method = match integrator.as_str() {
            "implicit" | "newmark" | "trapezoidal" => Method::Implicit(Alpha::NEWMARK),
            "hht" | "hht-alpha" => Method::Implicit(radius(Alpha::hht(rho))?),
            "generalized-alpha" | "generalised-alpha" => Method::Implicit(radius(Alpha::generalised(rho))?),
            "rk4" | "explicit" => Method::Rk4 { stability_limit: 0.0 },
            other => {
                return Err(ParameterError::invalid(
                    "integrator",
                    &other,
                    "use implicit, hht, generalized-alpha or rk4",
                )
                .into());
            }
        };
        let nonlinear = self.mesh_backlash > 0.0 || self.mesh_stiffness_variation > 0.0;
        if nonlinear && fidelity != Fidelity::Full {
            return Err(ParameterError::Conflict(
                "mesh_backlash and mesh_stiffness_variation need fidelity = full (meshes are rigid below it)".into(),
            )
            .into());
        }
        if self.mesh_stiffness_variation * (self.contact_ratio - 1.0) >= 1.0 {
            return Err(ParameterError::Conflict(format!(
                "mesh_stiffness_variation {} with contact_ratio {} makes the single-contact stiffness negative",
                self.mesh_stiffness_variation, self.contact_ratio
            ))
            .into());
        }
        let options = ModelOptions {
            shaft_damping_ratio: self.shaft_damping_ratio,
            mesh_damping_ratio: self.mesh_damping_ratio,
            damping_scale: self.damping_scale,
            mesh_backlash: self.mesh_backlash,
            mesh_stiffness_variation: self.mesh_stiffness_variation,
            contact_ratio: self.contact_ratio,
            lumping,
        };
        let mut model = TorsionalModel::new(&drivetrain, fidelity, &options)
            .map_err(ParameterError::Model)?
            .into_section(section);
        // the rotor section has no HSS, so no brake
        let brake_torque_max = if section == Section::Rotor {
            0.0
        } else if self.brake_torque_max > 0.0 {
            self.brake_torque_max
        } else {
            1.5 * drivetrain.rated_generator_torque()
        };
        model.brake = DiskBrake {
            torque_max: brake_torque_max,
            static_ratio: self.brake_static_ratio,
        };
        let rk4_step_limit = rk4::stability_limit(model.max_angular_frequency());
        if let Method::Rk4 { stability_limit } = &mut method {
            *stability_limit = rk4_step_limit;
        }
        Ok(Built {
            drivetrain,
            elements: ElementTable::new(&model),
            model,
            method,
            brake_torque_max,
            rk4_step_limit,
        })
    }

    fn initial_state(&self, b: &Built) -> SlaveResult<DynState> {
        let m = &b.model;
        let q = m.static_deflection(self.initial_rotor_torque).map_err(err)?;
        let w = self.initial_speed_ratio * b.drivetrain.rated_rotor_speed;
        let v = m.speed_ratio.iter().map(|r| r * w).collect();
        Ok(DynState::new(q, v))
    }
}

/// Where one Real variable's value comes from: resolved once for an array a host reads repeatedly,
/// so that reading it costs what each value's physics costs, not a search for the variable.
#[derive(Clone, Copy, Debug)]
enum Source {
    /// Fixed while the model is built (gear ratio, rated torques, RK4's limit, an absent body's 0).
    Constant(f64),
    /// factor × the DOF's angle or speed.
    Body {
        dof: usize,
        factor: f64,
        speed: bool,
    },
    /// An element's force (a shaft's torque, a mesh's force); None reads 0.
    Element(Option<crate::physics::torsional::ForceOutput>),
    BrakeTorque,
    StoredEnergy,
}

impl Source {
    /// Where the computed variable `r` comes from in model `b` (None: no computed variable).
    fn of(b: &Built, r: u32) -> Option<Self> {
        let body = |slot: u32, speed: bool| {
            b.model.bodies[slot as usize].map_or(Self::Constant(0.0), |(dof, factor)| Self::Body { dof, factor, speed })
        };
        let shaft = |i: usize| Self::Element(b.model.shafts[i]);
        Some(match r {
            vr::GEAR_RATIO => Self::Constant(b.model.gear_ratio),
            vr::RATED_ROTOR_TORQUE => Self::Constant(b.drivetrain.rated_rotor_torque()),
            vr::RATED_GENERATOR_TORQUE => Self::Constant(b.drivetrain.rated_generator_torque()),
            vr::RK4_STEP_LIMIT => Self::Constant(b.rk4_step_limit),
            vr::ROTOR_SPEED => body(0, true),
            vr::GENERATOR_SPEED => body(BODY_COUNT - 1, true),
            vr::LSS_TORQUE => shaft(0),
            vr::IS1_TORQUE => shaft(1),
            vr::IS2_TORQUE => shaft(2),
            vr::HSS_TORQUE => shaft(3),
            vr::BRAKE_TORQUE => Self::BrakeTorque,
            vr::STORED_ENERGY => Self::StoredEnergy,
            r if (MESH_FIRST..MESH_FIRST + MESH_COUNT).contains(&r) => {
                Self::Element(b.model.meshes[(r - MESH_FIRST) as usize])
            }
            r if (ANGLE_FIRST..ANGLE_FIRST + BODY_COUNT).contains(&r) => body(r - ANGLE_FIRST, false),
            r if (SPEED_FIRST..SPEED_FIRST + BODY_COUNT).contains(&r) => body(r - SPEED_FIRST, true),
            _ => return None,
        })
    }

    /// The value now, at state `st` and the cut's (angle, speed) `cut`.
    fn value(self, b: &Built, st: &DynState, cut: (f64, f64)) -> f64 {
        match self {
            Self::Constant(v) => v,
            Self::Body { dof, factor, speed } => factor * if speed { st.v[dof] } else { st.q[dof] },
            // `element_output`'s product, the element's load from the packed table
            Self::Element(o) => o.map_or(0.0, |o| {
                o.factor * b.elements.load(&b.model, o.element, &st.q, &st.v, cut).force
            }),
            Self::BrakeTorque => -st.friction_force,
            Self::StoredEnergy => b.model.stored_energy(&st.q, &st.v, cut),
        }
    }
}

/// The sources of the last long array read ([`Slave::get_reals`]), for the model they were resolved in
/// (held, so that its address cannot be another model's), sorted by kind: each kind is one tight
/// loop over (position in the array, where its value comes from).
#[derive(Clone, Default)]
struct ReadPlan {
    vrs: Vec<u32>,
    built: Option<Arc<Built>>,
    declared: Vec<(usize, u32)>,
    constants: Vec<(usize, f64)>,
    /// (position, DOF, factor): factor × the DOF's angle, or its speed.
    angles: Vec<(usize, usize, f64)>,
    speeds: Vec<(usize, usize, f64)>,
    /// (position, element, factor): factor × the element's force.
    elements: Vec<(usize, usize, f64)>,
    brake_torque: Vec<usize>,
    stored_energy: Vec<usize>,
    /// Every element's force and energy at the read's state, evaluated once per read when an element
    /// or the energy is read.
    loads: Vec<ElementLoad>,
}

impl ReadPlan {
    /// Arrays shorter than this are read value by value (a master's coupling reads: one or two).
    const MIN_LEN: usize = 8;

    fn fits(&self, b: &Arc<Built>, vrs: &[u32]) -> bool {
        self.built.as_ref().is_some_and(|p| Arc::ptr_eq(p, b)) && self.vrs == vrs
    }

    /// Resolves `vrs` in `b`; false (and no plan) if one of them is no Real variable with a value.
    fn resolve(&mut self, b: &Arc<Built>, (params, inputs): (&Params, &Inputs), vrs: &[u32]) -> bool {
        *self = Self {
            loads: std::mem::take(&mut self.loads),
            ..Self::default()
        };
        for (i, &r) in vrs.iter().enumerate() {
            if xml::get_real(params, inputs, r).is_some() {
                self.declared.push((i, r));
                continue;
            }
            match Source::of(b, r) {
                Some(Source::Constant(c)) => self.constants.push((i, c)),
                Some(Source::Body { dof, factor, speed }) => {
                    if speed { &mut self.speeds } else { &mut self.angles }.push((i, dof, factor))
                }
                // an absent element reads 0 (`element_output`)
                Some(Source::Element(None)) => self.constants.push((i, 0.0)),
                Some(Source::Element(Some(o))) => self.elements.push((i, o.element, o.factor)),
                Some(Source::BrakeTorque) => self.brake_torque.push(i),
                Some(Source::StoredEnergy) => self.stored_energy.push(i),
                // no plan: `built` stays None, so the next array is resolved afresh
                None => return false,
            }
        }
        self.vrs.extend_from_slice(vrs);
        self.built = Some(Arc::clone(b));
        true
    }

    /// The planned array's values at state `st`, the cut's (angle, speed) `cut`, into `values`.
    fn read(
        &mut self,
        b: &Built,
        (params, inputs): (&Params, &Inputs),
        st: &DynState,
        cut: (f64, f64),
        values: &mut [f64],
    ) {
        if !(self.elements.is_empty() && self.stored_energy.is_empty()) {
            b.elements.loads(&b.model, &st.q, &st.v, cut, &mut self.loads);
        }
        // resolved because it has a value; NaN sends the host to the value-by-value path
        for &(i, r) in &self.declared {
            values[i] = xml::get_real(params, inputs, r).unwrap_or(f64::NAN);
        }
        for &(i, c) in &self.constants {
            values[i] = c;
        }
        // the same products as `Source::value`
        for &(i, dof, factor) in &self.angles {
            values[i] = factor * st.q[dof];
        }
        for &(i, dof, factor) in &self.speeds {
            values[i] = factor * st.v[dof];
        }
        for &(i, element, factor) in &self.elements {
            values[i] = factor * self.loads[element].force;
        }
        for &i in &self.brake_torque {
            values[i] = -st.friction_force;
        }
        for &i in &self.stored_energy {
            values[i] = b.model.stored_energy_of(&st.v, &self.loads);
        }
    }
}

impl TorsionalSlave {
    fn blank() -> Self {
        Self {
            params: std::sync::Arc::default(),
            inputs: Inputs::default(),
            state: None,
            cut_angle: 0.0,
            built: None,
            driver: implicit_driver(),
            read_plan: ReadPlan::default(),
        }
    }

    /// The built model and state, created from the current parameters on first use. Every step and
    /// every output read passes here: the check is inlined, the building kept out of line.
    #[inline]
    pub fn ensure(&mut self) -> SlaveResult<(&Built, &mut DynState)> {
        if self.built.is_none() || self.state.is_none() {
            self.build_model_and_state()?;
        }
        match (&self.built, &mut self.state) {
            (Some(built), Some(state)) => Ok((built, state)),
            _ => Err(err("the model was not built")),
        }
    }

    #[cold]
    #[inline(never)]
    fn build_model_and_state(&mut self) -> SlaveResult<()> {
        if self.built.is_none() {
            let built = self.params.build()?;
            self.driver = Driver::new(built.method);
            self.built = Some(Arc::new(built));
        }
        if self.state.is_none()
            && let Some(built) = &self.built
        {
            self.state = Some(self.params.initial_state(built)?);
        }
        Ok(())
    }

    fn invalidate(&mut self) {
        self.built = None;
        self.state = None;
        self.cut_angle = 0.0;
    }

    /// A parameter change rebuilds the model and its state; inputs are read at the next step.
    fn changed(&mut self, what: Changed) {
        if what == Changed::Parameter {
            self.invalidate();
        }
    }

    /// Reads `vrs` through the [`ReadPlan`] (resolved now unless it is the last long array read);
    /// false, nothing read, if one of them is no Real variable with a value or the model cannot be
    /// built (parameters still read then, value by value). Out of line: a coupling's read of one or two
    /// values stays the small loop it was.
    #[inline(never)]
    fn read_planned(&mut self, vrs: &[u32], values: &mut [f64]) -> bool {
        let cut = self.cut();
        if self.ensure().is_err() {
            return false;
        }
        let Self {
            params,
            inputs,
            built: Some(b),
            state: Some(st),
            read_plan,
            ..
        } = self
        else {
            unreachable!("ensure built the model and its state")
        };
        if !(read_plan.fits(b, vrs) || read_plan.resolve(b, (params, inputs), vrs)) {
            return false;
        }
        read_plan.read(b, (params, inputs), st, cut, values);
        true
    }

    /// A value the model computes from its state: a calculated parameter or an output.
    fn computed(b: &Built, st: &DynState, cut: (f64, f64), r: u32) -> SlaveResult<f64> {
        let source = Source::of(b, r).ok_or_else(|| xml::no_getter(VarType::Real, r))?;
        Ok(source.value(b, st, cut))
    }

    /// The cut's angle and speed now (section = drivetrain; unused by the other sections).
    fn cut(&self) -> (f64, f64) {
        (self.cut_angle, self.inputs.cut_speed.value())
    }

    /// The integrator's work counters since the model was built.
    pub fn solver_statistics(&self) -> Statistics {
        self.driver.stats
    }

    /// Takes every step the solver's general way until the model is next built (a parameter
    /// change): the check that its plain linear steps change no bit ([`Driver::plain_linear_steps`]).
    pub fn general_steps_only(&mut self) -> SlaveResult<()> {
        self.ensure()?;
        self.driver.plain_linear_steps = false;
        Ok(())
    }

    pub fn built(&mut self) -> SlaveResult<&Built> {
        Ok(self.ensure()?.0)
    }
}

const MESH_FIRST: u32 = vr::MESH_FORCE_RING_PLANET_1;
const ANGLE_FIRST: u32 = vr::ANGLE_ROTOR;
const SPEED_FIRST: u32 = vr::SPEED_ROTOR;
const BODY_COUNT: u32 = crate::physics::torsional::BODY_SLOTS.len() as u32;
const MESH_COUNT: u32 = crate::physics::torsional::MESH_SLOTS.len() as u32;

impl Slave for TorsionalSlave {
    crate::slave_interface_from_xml!();

    /// The integrator's workspace (cached factorisations, step maps) stays out of a state.
    fn snapshot(&self) -> Self {
        Self {
            params: self.params.clone(),
            inputs: self.inputs,
            state: self.state.clone(),
            cut_angle: self.cut_angle,
            built: self.built.clone(),
            driver: implicit_driver(),
            read_plan: ReadPlan::default(),
        }
    }

    /// Reuses the earlier snapshot's vectors and strings.
    fn snapshot_into(&self, into: &mut Self) {
        if !std::sync::Arc::ptr_eq(&into.params, &self.params) {
            into.params = std::sync::Arc::clone(&self.params);
        }
        into.inputs.clone_from(&self.inputs);
        into.state.clone_from(&self.state);
        into.cut_angle = self.cut_angle;
        super::share_build(&mut into.built, &self.built);
    }

    /// Keeps this instance's integrator while the model is the snapshot's own (the same build).
    fn restore(&mut self, snap: &Self) {
        let same_model = super::same_build(&self.built, &snap.built);
        snap.snapshot_into(self);
        if !same_model {
            self.driver = self
                .built
                .as_ref()
                .map_or_else(implicit_driver, |b| Driver::new(b.method));
        }
    }

    fn instantiate(_resources: Option<&Path>) -> Self {
        Self::blank()
    }

    fn get_real(&mut self, r: u32) -> SlaveResult<f64> {
        let mut out = [0.0];
        self.get_reals(&[r], &mut out)?;
        Ok(out[0])
    }

    /// The model built (or checked) once for all the values asked; an array a host reads again and
    /// again (a recorder's row) is resolved once into where each value comes from ([`ReadPlan`]).
    fn get_reals(&mut self, vrs: &[u32], values: &mut [f64]) -> SlaveResult<()> {
        // the plan writes by position, so only where both arrays have one length (the value-by-value
        // path pairs them as far as both go)
        if vrs.len() >= ReadPlan::MIN_LEN && vrs.len() == values.len() && self.read_planned(vrs, values) {
            return Ok(());
        }
        let cut = self.cut();
        for (&r, value) in vrs.iter().zip(values) {
            *value = match xml::get_real(&self.params, &self.inputs, r) {
                Some(v) => v,
                None => {
                    let (b, st) = self.ensure()?;
                    Self::computed(b, st, cut, r)?
                }
            };
        }
        Ok(())
    }

    fn set_real(&mut self, r: u32, value: f64, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_real(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn get_integer(&mut self, r: u32) -> SlaveResult<i32> {
        match r {
            vr::DOF_COUNT => Ok(self.ensure()?.0.model.dofs() as i32),
            _ => Err(xml::no_getter(VarType::Integer, r)),
        }
    }

    fn get_boolean(&mut self, r: u32) -> SlaveResult<bool> {
        match r {
            vr::BRAKE_LOCKED => Ok(self.ensure()?.1.locked),
            _ => Err(xml::no_getter(VarType::Boolean, r)),
        }
    }

    fn get_string(&mut self, r: u32) -> SlaveResult<String> {
        xml::get_string(&self.params, &self.inputs, r).ok_or_else(|| xml::no_getter(VarType::String, r))
    }

    fn set_string(&mut self, r: u32, value: &str, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_string(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn initialize(&mut self, _start_time: f64, log: &mut dyn Log) -> SlaveResult<()> {
        let p = &self.params;
        if p.max_internal_step <= 0.0 {
            return Err(err(format!(
                "max_internal_step = {} must be positive",
                p.max_internal_step
            )));
        }
        self.ensure()?;
        self.warn_rattle(log);
        Ok(())
    }

    fn set_input_derivative(&mut self, r: u32, order: i32, value: f64) -> SlaveResult<()> {
        self.inputs.set_derivative(r, order, value)
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut dyn Log) -> SlaveResult<()> {
        self.ensure()?;
        // taken out for the step and put back below: no atomic reference counting per step
        let built = self.built.take().unwrap();
        let result = self.step_with(&built, t, h, log);
        self.built = Some(built);
        result
    }
}

/// h·ω_max above which an undamped integrator leaves the top mesh modes ringing into a backlash's dead
/// zone, as measured with 100 µm: drivetrain C's shutdown rattles at 1 ms (h·ω = 49), not at 0.5 ms
/// (24); D's does not at 1 ms (30) (docs/SPEED-ACCURACY.md, tests/it/non_smooth.rs).
const RATTLE_H_OMEGA: f64 = 30.0;

impl TorsionalSlave {
    /// Backlash with Newmark (no numerical damping) at an internal step far above the mesh modes'
    /// periods: the contact rattles numerically; say so once, with the remedies.
    fn warn_rattle(&self, log: &mut dyn Log) {
        let (p, Some(built)) = (&self.params, &self.built) else {
            return;
        };
        let undamped = matches!(built.method, Method::Implicit(a) if a.alpha_f == 0.0 && a.alpha_m == 0.0);
        let h_omega = p.max_internal_step * built.model.max_angular_frequency();
        if p.mesh_backlash > 0.0 && undamped && h_omega > RATTLE_H_OMEGA {
            log.warning(&format!(
                "mesh_backlash = {} m with integrator = implicit at max_internal_step = {} s: the top mesh mode \
                 (h*omega = {h_omega:.0}) is undamped and the contacts rattle in the dead zone; use max_internal_step <= {:.1e} s \
                 or integrator = hht with spectral_radius < 1",
                p.mesh_backlash,
                p.max_internal_step,
                RATTLE_H_OMEGA / built.model.max_angular_frequency()
            ));
        }
    }

    fn step_with(&mut self, built: &Built, t: f64, h: f64, log: &mut dyn Log) -> SlaveResult<()> {
        let inputs = &self.inputs;
        let cut_angle = self.cut_angle;
        let st = self.state.as_mut().unwrap();
        self.driver.max_steps_per_call = self.params.max_steps_per_call;
        let result = self.driver.advance(
            &built.model,
            st,
            t,
            h,
            self.params.max_internal_step,
            INPUT_COUNT,
            |dt, u| inputs.write(cut_angle, dt, u),
        );
        super::log_brake_events(&self.driver.events, log);
        result.map_err(|e| match e {
            crate::solver::SolverError::AboveStabilityLimit { step, limit } => err(format!(
                "RK4 is unstable at an internal step of {step:.3e} s: its stability limit is 2.785/omega_max = \
                 {limit:.3e} s (omega_max = {:.0} rad/s, the stiffest gear-mesh mode at {:.0} Hz); set \
                 max_internal_step <= {limit:.3e} or use integrator = implicit",
                rk4::STABILITY_BOUND / limit,
                rk4::STABILITY_BOUND / limit / std::f64::consts::TAU,
            )),
            e => err(format!("{e} (communication step from t = {t} s, h = {h} s)")),
        })?;
        self.cut_angle += self.inputs.cut_speed.integral(h);
        self.inputs.advance(h);
        Ok(())
    }
}
