//! The `generator` FMU: variables of modelDescription/generator.xml mapped onto
//! [`crate::physics::generator`]. The model is built from the parameters when first needed, in
//! equilibrium at the speed input of that moment (re-built while the speed is still being set
//! during initialisation).

use crate::fmi2::fmu::error::{ParameterError, SlaveResult, err};
use crate::fmi2::fmu::slave::{Changed, Log, Slave};
use crate::fmi2::fmu::variables::VarType;
use crate::models::generator as xml;
use crate::models::generator::vr;
use crate::physics::generator::presets::{self, Kind, Overrides};
use crate::physics::generator::{GenState, Generator, Machine, Outputs};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Every parameter of generator.xml (generated from it).
pub type Params = xml::Parameters;
/// The speed input with its time derivatives (orders 1 and 2), and the grid connection.
pub type Inputs = xml::Inputs;

/// A built model, its state and what the calculated parameters report.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
struct Built {
    generator: Generator,
    state: GenState,
    equivalent: (f64, f64),
    rated_torque: f64,
    region2_gain: f64,
}

#[derive(Clone, Serialize, Deserialize)]
pub struct GeneratorSlave {
    /// Shared, copy-on-write, with the states taken while they are unchanged: taking or restoring a
    /// state compares a pointer instead of every parameter.
    pub params: std::sync::Arc<Params>,
    pub inputs: Inputs,
    model: Option<Built>,
    /// Once stepped, the state is the simulation's: a speed change no longer rebuilds it.
    stepped: bool,
}

/// Most RK4 sub-steps one doStep may take (≈ 0.1 s of work).
const MAX_SUBSTEPS: f64 = 1e6;

impl Params {
    /// What the physics calls overrides of the preset: every electrical and control parameter.
    fn overrides(&self) -> Overrides {
        Overrides {
            stiffness: self.stiffness,
            damping: self.damping,
            synchronous_speed: self.synchronous_speed,
            poles: self.poles,
            frequency: self.frequency,
            stator_resistance: self.stator_resistance,
            rotor_resistance: self.rotor_resistance,
            stator_leakage: self.stator_leakage,
            rotor_leakage: self.rotor_leakage,
            mutual_inductance: self.mutual_inductance,
            line_inductance: self.line_inductance,
            current_bandwidth: self.current_bandwidth,
            torque_control: self.torque_control.clone(),
            reference_speed: self.reference_speed,
            region2_gain: self.region2_gain,
            cut_in_speed: self.cut_in_speed,
            transition_slip: self.transition_slip,
            max_torque: self.max_torque,
            speed_filter_frequency: self.speed_filter_frequency,
            speed_bandwidth: self.speed_bandwidth,
        }
    }

    fn build(&self, speed: f64) -> Result<Built, ParameterError> {
        let kind = Kind::parse(&self.kind)
            .ok_or_else(|| ParameterError::invalid("kind", &self.kind, "use spring, fixed, dfig or pmg"))?;
        let generator = presets::build(&self.preset, kind, &self.overrides()).map_err(ParameterError::Model)?;
        let dt = crate::physics::drivetrain::Drivetrain::preset(&self.preset).expect("checked by presets::build");
        let rated_speed = dt.rated_rotor_speed * dt.gear_ratio();
        let state = generator.initial_state(speed, self.initial_torque);
        let omega = 2.0 * std::f64::consts::PI * self.stiffness_frequency;
        let equivalent = generator.equivalent_stiffness_damping(&state, speed, omega);
        let region2_gain = match generator.control {
            Some(crate::physics::generator::control::TorqueControl::Law(l)) => l.k,
            _ => 0.0,
        };
        Ok(Built {
            generator,
            state,
            equivalent,
            rated_torque: dt.rated_power / rated_speed,
            region2_gain,
        })
    }
}

impl GeneratorSlave {
    fn ensure(&mut self) -> SlaveResult<&mut Built> {
        if self.model.is_none() {
            self.model = Some(self.params.build(self.inputs.generator_speed.value())?);
        }
        Ok(self.model.as_mut().expect("just built"))
    }

    /// A value the model computes: a calculated parameter or an output.
    fn computed(b: &Built, out: &Outputs, r: u32) -> SlaveResult<f64> {
        Ok(match r {
            vr::STIFFNESS_USED => match b.generator.machine {
                Machine::Spring(s) => s.stiffness,
                _ => 0.0,
            },
            vr::SYNCHRONOUS_SPEED_USED => b.generator.base_speed,
            vr::EQUIVALENT_STIFFNESS => b.equivalent.0,
            vr::EQUIVALENT_DAMPING => b.equivalent.1,
            vr::RATED_TORQUE => b.rated_torque,
            vr::REGION2_GAIN_USED => b.region2_gain,
            vr::GENERATOR_TORQUE => out.torque,
            vr::LOAD_ANGLE => out.load_angle,
            vr::ELECTRICAL_POWER => out.electrical_power,
            vr::TORQUE_DEMAND => out.torque_demand,
            vr::SLIP => out.slip,
            vr::STATOR_CURRENT => out.stator_current,
            vr::ROTOR_CURRENT => out.rotor_current,
            _ => return Err(xml::no_getter(VarType::Real, r)),
        })
    }

    /// A parameter change rebuilds the model; so does a speed change until the first step.
    fn changed(&mut self, what: Changed) {
        if what == Changed::Parameter || !self.stepped {
            self.model = None;
        }
    }
}

impl Slave for GeneratorSlave {
    crate::slave_interface_from_xml!();

    /// Reuses an earlier snapshot's strings: the parameters are copied only when they differ.
    fn snapshot_into(&self, into: &mut Self) {
        if !std::sync::Arc::ptr_eq(&into.params, &self.params) {
            into.params = std::sync::Arc::clone(&self.params);
        }
        into.inputs.clone_from(&self.inputs);
        into.model = self.model;
        into.stepped = self.stepped;
    }

    fn restore(&mut self, snap: &Self) {
        snap.snapshot_into(self);
    }

    fn instantiate(_resources: Option<&Path>) -> Self {
        Self {
            params: std::sync::Arc::default(),
            inputs: Inputs::default(),
            model: None,
            stepped: false,
        }
    }

    fn get_real(&mut self, r: u32) -> SlaveResult<f64> {
        let mut out = [0.0];
        self.get_reals(&[r], &mut out)?;
        Ok(out[0])
    }

    /// The model's outputs computed once for all the values asked.
    fn get_reals(&mut self, vrs: &[u32], values: &mut [f64]) -> SlaveResult<()> {
        let omega = self.inputs.generator_speed.value();
        // the outputs once per array, read with the model by reference for every value
        let mut outputs = None;
        for (&r, value) in vrs.iter().zip(values) {
            *value = match xml::get_real(&self.params, &self.inputs, r) {
                Some(v) => v,
                None => {
                    if outputs.is_none() {
                        let b = self.ensure()?;
                        outputs = Some(b.generator.outputs(&b.state, omega));
                    }
                    let (Some(out), Some(b)) = (&outputs, &self.model) else {
                        return Err(err("the model was not built"));
                    };
                    Self::computed(b, out, r)?
                }
            };
        }
        Ok(())
    }

    fn set_real(&mut self, r: u32, value: f64, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_real(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn get_integer(&mut self, r: u32) -> SlaveResult<i32> {
        xml::get_integer(&self.params, &self.inputs, r).ok_or_else(|| xml::no_getter(VarType::Integer, r))
    }

    fn set_integer(&mut self, r: u32, value: i32, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_integer(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn get_boolean(&mut self, r: u32) -> SlaveResult<bool> {
        xml::get_boolean(&self.params, &self.inputs, r).ok_or_else(|| xml::no_getter(VarType::Boolean, r))
    }

    fn set_boolean(&mut self, r: u32, value: bool, log: &mut dyn Log) -> SlaveResult<()> {
        let was = self.inputs.connected;
        xml::set_boolean(&mut self.params, &mut self.inputs, r, value, log)?;
        if let Some(b) = &mut self.model {
            if value && !was {
                b.state.connected_fraction = 1.0;
                if let Machine::Spring(_) = b.generator.machine {
                    // resynchronised at reconnection: the spring starts untwisted
                    b.state.x[0] = 0.0;
                    log.event("reconnected to the grid (load angle reset to 0)");
                } else {
                    log.event("reconnected to the grid");
                }
            } else if !value && was {
                log.event("tripped: generator torque decays with trip_time_constant");
            }
        }
        Ok(())
    }

    fn get_string(&mut self, r: u32) -> SlaveResult<String> {
        xml::get_string(&self.params, &self.inputs, r).ok_or_else(|| xml::no_getter(VarType::String, r))
    }

    fn set_string(&mut self, r: u32, value: &str, log: &mut dyn Log) -> SlaveResult<()> {
        xml::set_string(&mut self.params, &mut self.inputs, r, value, log).map(|what| self.changed(what))
    }

    fn initialize(&mut self, _start_time: f64, log: &mut dyn Log) -> SlaveResult<()> {
        let freq = self.params.stiffness_frequency;
        let b = self.ensure()?;
        log.event(&format!(
            "equivalent torque-angle stiffness {:.6e} N.m/rad and damping {:.6e} N.m.s/rad at {freq} Hz",
            b.equivalent.0, b.equivalent.1
        ));
        Ok(())
    }

    fn set_input_derivative(&mut self, r: u32, order: i32, value: f64) -> SlaveResult<()> {
        self.inputs.set_derivative(r, order, value)
    }

    fn do_step(&mut self, _t: f64, h: f64, _log: &mut dyn Log) -> SlaveResult<()> {
        let Inputs {
            generator_speed: w,
            connected,
        } = self.inputs;
        let tau = self.params.trip_time_constant;
        let bandwidth = self.params.current_bandwidth;
        let b = self.ensure()?;
        // a step of hours with a 1 ms current loop would never return: refuse it instead
        let n = b.generator.substeps(h);
        if n > MAX_SUBSTEPS {
            return Err(err(format!(
                "a step of {h} s needs {n:.0} internal steps for the current loop (current_bandwidth {bandwidth} rad/s); \
                 the most per step is {MAX_SUBSTEPS:.0}: take shorter steps"
            )));
        }
        b.generator.advance(&mut b.state, w.0, h, connected, tau);
        if !b.state.x.iter().all(|v| v.is_finite()) {
            return Err(err(format!(
                "the electrical state became non-finite at speed {} rad/s: parameters outside the model's range",
                w.value()
            )));
        }
        self.stepped = true;
        // the input polynomial continues from the new communication point
        self.inputs.advance(h);
        Ok(())
    }
}
