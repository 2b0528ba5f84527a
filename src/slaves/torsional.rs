//! The `torsional` FMU: variables of modelDescription/torsional.xml mapped onto [`TorsionalModel`]
//! and the integrators of [`crate::solver`].

use crate::fmi2::slave::{Changed, Log, ParameterError, Slave, SlaveResult, err};
use crate::fmi2::variables::VarType;
use crate::models::torsional as xml;
use crate::models::torsional::vr;
use crate::physics::drivetrain::Drivetrain;
use crate::physics::torsional::{Fidelity, ModelOptions, TorsionalModel};
use crate::solver::{self, DynState, Loads, Scratch, newmark::Newmark, rk4};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Integrator {
    Implicit,
    Rk4,
}

/// Every parameter of torsional.xml (generated from it), at its start value by default.
pub type Params = xml::Parameters;
/// Input values and their time derivatives (set by fmi2SetRealInputDerivatives, orders 1 and 2).
pub type Inputs = xml::Inputs;

impl Inputs {
    /// The loads `dt` seconds after the communication point; the brake command is clamped to [0, 1].
    fn loads(&self, dt: f64, brake_torque_max: f64) -> Loads {
        Loads {
            rotor_torque: self.rotor_torque.at(dt),
            generator_torque: self.generator_torque.at(dt),
            brake_capacity: self.brake_command.at(dt).clamp(0.0, 1.0) * brake_torque_max,
        }
    }
}

/// What a set of parameters builds: checked once, shared by snapshots.
#[derive(Debug)]
pub struct Built {
    pub drivetrain: Drivetrain,
    pub model: TorsionalModel,
    pub integrator: Integrator,
    pub brake_torque_max: f64,
    pub rk4_step_limit: f64,
}

#[derive(Clone, Serialize, Deserialize)]
pub struct TorsionalSlave {
    pub params: Params,
    pub inputs: Inputs,
    /// None until the model is first needed; rebuilt from `params` after deserialisation.
    state: Option<DynState>,
    #[serde(skip)]
    built: Option<Arc<Built>>,
    #[serde(skip)]
    newmark: Newmark,
    #[serde(skip)]
    rk4: rk4::Rk4,
    #[serde(skip)]
    scratch: Scratch,
}

impl Params {
    pub fn build(&self) -> SlaveResult<Built> {
        let drivetrain = Drivetrain::preset(&self.preset)
            .ok_or_else(|| ParameterError::invalid("preset", &self.preset, "unknown drivetrain, use A, B, C or D"))?;
        let fidelity = Fidelity::parse(&self.fidelity)
            .ok_or_else(|| ParameterError::invalid("fidelity", &self.fidelity, "use 2, 5 or full"))?;
        let integrator = match self.integrator.trim().to_ascii_lowercase().as_str() {
            "implicit" | "newmark" | "trapezoidal" => Integrator::Implicit,
            "rk4" | "explicit" => Integrator::Rk4,
            other => return Err(ParameterError::invalid("integrator", &other, "use implicit or rk4").into()),
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
        };
        let model = TorsionalModel::new(&drivetrain, fidelity, &options).map_err(ParameterError::Model)?;
        let brake_torque_max = if self.brake_torque_max > 0.0 {
            self.brake_torque_max
        } else {
            1.5 * drivetrain.rated_generator_torque()
        };
        let rk4_step_limit = rk4::stability_limit(model.max_angular_frequency());
        Ok(Built {
            drivetrain,
            model,
            integrator,
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

impl TorsionalSlave {
    fn blank() -> Self {
        Self {
            params: Params::default(),
            inputs: Inputs::default(),
            state: None,
            built: None,
            newmark: Newmark::new(),
            rk4: rk4::Rk4::default(),
            scratch: Scratch::default(),
        }
    }

    /// The built model and state, created from the current parameters on first use.
    pub fn ensure(&mut self) -> SlaveResult<(&Built, &mut DynState)> {
        if self.built.is_none() {
            self.built = Some(Arc::new(self.params.build()?));
        }
        let built = self.built.as_ref().unwrap();
        if self.state.is_none() {
            self.state = Some(self.params.initial_state(built)?);
        }
        Ok((built, self.state.as_mut().unwrap()))
    }

    fn invalidate(&mut self) {
        self.built = None;
        self.state = None;
    }

    /// A parameter change rebuilds the model and its state; inputs are read at the next step.
    fn changed(&mut self, what: Changed) {
        if what == Changed::Parameter {
            self.invalidate();
        }
    }

    fn element_output(built: &Built, st: &DynState, out: Option<crate::physics::torsional::ForceOutput>) -> f64 {
        let Some(o) = out else { return 0.0 };
        let e = &built.model.elements[o.element];
        o.factor * e.force(e.stiffness_at(&st.q), e.deflection(&st.q), e.deflection(&st.v))
    }

    /// Statistics of the implicit integrator: (factorisations, Newton iterations).
    pub fn solver_statistics(&self) -> (u64, u64) {
        (self.newmark.factorizations, self.newmark.iterations)
    }

    pub fn built(&mut self) -> SlaveResult<&Built> {
        Ok(self.ensure()?.0)
    }
}

/// Deepest halving of an implicit substep whose backlash contact does not settle: 2⁻¹² of a
/// substep (0.24 µs at 1 ms) resolves any mesh contact event of these drivetrains.
const MAX_SUBDIVISION: u32 = 12;

/// One implicit step over the interval `span` (seconds after the communication point), halved
/// recursively while a backlash contact event inside it keeps the Newton iteration from settling.
fn implicit_step(
    newmark: &mut Newmark,
    built: &Built,
    st: &mut DynState,
    inputs: &Inputs,
    span: (f64, f64),
    static_ratio: f64,
    depth: u32,
) -> SlaveResult<()> {
    let loads = inputs.loads(span.1, built.brake_torque_max);
    match newmark.step(&built.model, st, span.1 - span.0, &loads, static_ratio) {
        Ok(()) => Ok(()),
        Err(solver::newmark::NewmarkError::NotSettled) if depth < MAX_SUBDIVISION => {
            let mid = 0.5 * (span.0 + span.1);
            implicit_step(newmark, built, st, inputs, (span.0, mid), static_ratio, depth + 1)?;
            implicit_step(newmark, built, st, inputs, (mid, span.1), static_ratio, depth + 1)
        }
        Err(e) => Err(err(format!(
            "{e} (step of {:.3e} s after {depth} halvings)",
            span.1 - span.0
        ))),
    }
}

const MESH_FIRST: u32 = vr::MESH_FORCE_RING_PLANET_1;
const ANGLE_FIRST: u32 = vr::ANGLE_ROTOR;
const SPEED_FIRST: u32 = vr::SPEED_ROTOR;
const BODY_COUNT: u32 = crate::physics::torsional::BODY_SLOTS.len() as u32;
const MESH_COUNT: u32 = crate::physics::torsional::MESH_SLOTS.len() as u32;

impl Slave for TorsionalSlave {
    crate::slave_interface_from_xml!();

    fn instantiate(_resources: Option<&Path>) -> Self {
        Self::blank()
    }

    fn get_real(&mut self, r: u32) -> SlaveResult<f64> {
        if let Some(v) = xml::get_real(&self.params, &self.inputs, r) {
            return Ok(v);
        }
        let (b, st) = self.ensure()?;
        let body = |slot: u32, speed: bool| {
            b.model.bodies[slot as usize].map_or(0.0, |(d, f)| f * if speed { st.v[d] } else { st.q[d] })
        };
        Ok(match r {
            vr::GEAR_RATIO => b.model.gear_ratio,
            vr::RATED_ROTOR_TORQUE => b.drivetrain.rated_rotor_torque(),
            vr::RATED_GENERATOR_TORQUE => b.drivetrain.rated_generator_torque(),
            vr::RK4_STEP_LIMIT => b.rk4_step_limit,
            vr::ROTOR_SPEED => body(0, true),
            vr::GENERATOR_SPEED => body(BODY_COUNT - 1, true),
            vr::LSS_TORQUE => Self::element_output(b, st, b.model.shafts[0]),
            vr::IS1_TORQUE => Self::element_output(b, st, b.model.shafts[1]),
            vr::IS2_TORQUE => Self::element_output(b, st, b.model.shafts[2]),
            vr::HSS_TORQUE => Self::element_output(b, st, b.model.shafts[3]),
            vr::BRAKE_TORQUE => st.brake_torque,
            vr::STORED_ENERGY => solver::stored_energy(&b.model, &st.q, &st.v),
            r if (MESH_FIRST..MESH_FIRST + MESH_COUNT).contains(&r) => {
                Self::element_output(b, st, b.model.meshes[(r - MESH_FIRST) as usize])
            }
            r if (ANGLE_FIRST..ANGLE_FIRST + BODY_COUNT).contains(&r) => body(r - ANGLE_FIRST, false),
            r if (SPEED_FIRST..SPEED_FIRST + BODY_COUNT).contains(&r) => body(r - SPEED_FIRST, true),
            _ => return Err(xml::no_getter(VarType::Real, r)),
        })
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

    fn initialize(&mut self, _start_time: f64, _log: &mut dyn Log) -> SlaveResult<()> {
        let p = &self.params;
        if p.max_internal_step <= 0.0 {
            return Err(err(format!(
                "max_internal_step = {} must be positive",
                p.max_internal_step
            )));
        }
        self.ensure()?;
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

impl TorsionalSlave {
    fn step_with(&mut self, built: &Built, t: f64, h: f64, log: &mut dyn Log) -> SlaveResult<()> {
        let static_ratio = self.params.brake_static_ratio;
        let max_step = self.params.max_internal_step;
        let substeps = (h / max_step * (1.0 - 1e-12)).ceil().max(1.0);
        let hs = h / substeps;
        if built.integrator == Integrator::Rk4 && hs > built.rk4_step_limit {
            return Err(err(format!(
                "RK4 is unstable at an internal step of {hs:.3e} s: its stability limit is 2.785/omega_max = {:.3e} s \
                 (omega_max = {:.0} rad/s, the stiffest gear-mesh mode at {:.0} Hz); set max_internal_step <= {:.3e} \
                 or use integrator = implicit",
                built.rk4_step_limit,
                2.785 / built.rk4_step_limit,
                2.785 / built.rk4_step_limit / std::f64::consts::TAU,
                built.rk4_step_limit
            )));
        }
        let brake_max = built.brake_torque_max;
        let inputs = self.inputs;
        let start_loads = inputs.loads(0.0, brake_max);
        let st = self.state.as_mut().unwrap();
        let was_locked = st.locked;
        solver::consistent_acceleration(&built.model, st, &start_loads, static_ratio, &mut self.scratch);
        let n = substeps as usize;
        for i in 0..n {
            let tau = if i + 1 == n { h } else { (i + 1) as f64 * hs };
            match built.integrator {
                Integrator::Implicit => {
                    let t0 = if i == 0 { 0.0 } else { i as f64 * hs };
                    implicit_step(&mut self.newmark, built, st, &inputs, (t0, tau), static_ratio, 0)?;
                }
                Integrator::Rk4 => self
                    .rk4
                    .step(&built.model, st, hs, &inputs.loads(tau, brake_max), static_ratio),
            }
        }
        if st.q.iter().chain(&st.v).any(|x| !x.is_finite()) {
            return Err(err(format!(
                "the state became non-finite during the step from t = {t} s"
            )));
        }
        if st.locked != was_locked {
            log.event(&format!(
                "t = {:.6} s: HSS brake {}",
                t + h,
                if st.locked {
                    "locked (stiction)"
                } else {
                    "released (slipping)"
                }
            ));
        }
        self.inputs.advance(h);
        Ok(())
    }
}
