//! The `generator` FMU: variables of modelDescription/generator.xml mapped onto
//! [`crate::physics::generator`]. The model is built from the parameters when first needed, in
//! equilibrium at the speed input of that moment (re-built while the speed is still being set
//! during initialisation).

use crate::fmi2::slave::{Log, Slave, SlaveError, SlaveResult};
use crate::models::generator as xml;
use crate::models::generator::vr;
use crate::physics::generator::presets::{self, Kind, Overrides};
use crate::physics::generator::{GenState, Generator, Machine};
use crate::slaves::InputPolynomial;
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Params {
    pub preset: String,
    pub kind: String,
    pub initial_torque: f64,
    pub trip_time_constant: f64,
    pub stiffness_frequency: f64,
    pub o: Overrides,
}

/// The speed input with its time derivatives (orders 1 and 2), and the grid connection.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Inputs {
    pub speed: InputPolynomial,
    pub connected: bool,
}

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
    pub params: Params,
    pub inputs: Inputs,
    model: Option<Built>,
    /// Once stepped, the state is the simulation's: a speed change no longer rebuilds it.
    stepped: bool,
}

/// Most RK4 sub-steps one doStep may take (≈ 0.1 s of work).
const MAX_SUBSTEPS: f64 = 1e6;

fn err(msg: impl Into<String>) -> SlaveError {
    SlaveError::new(msg)
}

impl Params {
    fn build(&self, speed: f64) -> SlaveResult<Built> {
        let kind = Kind::parse(&self.kind).ok_or_else(|| {
            err(format!(
                "parameter kind = {:?}: use spring, fixed, dfig or pmg",
                self.kind
            ))
        })?;
        let generator = presets::build(&self.preset, kind, &self.o).map_err(err)?;
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
            self.model = Some(self.params.build(self.inputs.speed.value())?);
        }
        Ok(self.model.as_mut().expect("just built"))
    }

    fn real_param(&mut self, r: u32) -> Option<&mut f64> {
        let p = &mut self.params;
        let o = &mut p.o;
        Some(match r {
            vr::STIFFNESS => &mut o.stiffness,
            vr::DAMPING => &mut o.damping,
            vr::SYNCHRONOUS_SPEED => &mut o.synchronous_speed,
            vr::INITIAL_TORQUE => &mut p.initial_torque,
            vr::TRIP_TIME_CONSTANT => &mut p.trip_time_constant,
            vr::FREQUENCY => &mut o.frequency,
            vr::STATOR_RESISTANCE => &mut o.stator_resistance,
            vr::ROTOR_RESISTANCE => &mut o.rotor_resistance,
            vr::STATOR_LEAKAGE => &mut o.stator_leakage,
            vr::ROTOR_LEAKAGE => &mut o.rotor_leakage,
            vr::MUTUAL_INDUCTANCE => &mut o.mutual_inductance,
            vr::LINE_INDUCTANCE => &mut o.line_inductance,
            vr::CURRENT_BANDWIDTH => &mut o.current_bandwidth,
            vr::REFERENCE_SPEED => &mut o.reference_speed,
            vr::REGION2_GAIN => &mut o.region2_gain,
            vr::CUT_IN_SPEED => &mut o.cut_in_speed,
            vr::TRANSITION_SLIP => &mut o.transition_slip,
            vr::MAX_TORQUE => &mut o.max_torque,
            vr::SPEED_FILTER_FREQUENCY => &mut o.speed_filter_frequency,
            vr::SPEED_BANDWIDTH => &mut o.speed_bandwidth,
            vr::STIFFNESS_FREQUENCY => &mut p.stiffness_frequency,
            _ => return None,
        })
    }
}

impl Slave for GeneratorSlave {
    crate::slave_interface_from_xml!();

    fn instantiate(_resources: Option<&Path>) -> Self {
        let mut s = Self {
            params: Params::default(),
            inputs: Inputs::default(),
            model: None,
            stepped: false,
        };
        crate::fmi2::slave::apply_start_values(&mut s);
        s
    }

    fn get_real(&mut self, r: u32) -> SlaveResult<f64> {
        if r == vr::GENERATOR_SPEED {
            return Ok(self.inputs.speed.value());
        }
        if let Some(v) = self.real_param(r) {
            return Ok(*v);
        }
        let omega = self.inputs.speed.value();
        let b = *self.ensure()?;
        let out = b.generator.outputs(&b.state, omega);
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
            _ => return Err(err(format!("Real value reference {r} has no getter"))),
        })
    }

    fn set_real(&mut self, r: u32, value: f64, _: &mut dyn Log) -> SlaveResult<()> {
        if r == vr::GENERATOR_SPEED {
            self.inputs.speed.set(value);
            if !self.stepped {
                self.model = None;
            }
            return Ok(());
        }
        let slot = self
            .real_param(r)
            .ok_or_else(|| err(format!("Real value reference {r} cannot be set")))?;
        *slot = value;
        self.model = None;
        Ok(())
    }

    fn get_integer(&mut self, r: u32) -> SlaveResult<i32> {
        match r {
            vr::POLES => Ok(self.params.o.poles),
            _ => Err(err(format!("Integer value reference {r} has no getter"))),
        }
    }

    fn set_integer(&mut self, r: u32, value: i32, _: &mut dyn Log) -> SlaveResult<()> {
        match r {
            vr::POLES => {
                self.params.o.poles = value;
                self.model = None;
                Ok(())
            }
            _ => Err(err(format!("Integer value reference {r} cannot be set"))),
        }
    }

    fn get_boolean(&mut self, r: u32) -> SlaveResult<bool> {
        match r {
            vr::CONNECTED => Ok(self.inputs.connected),
            _ => Err(err(format!("Boolean value reference {r} has no getter"))),
        }
    }

    fn set_boolean(&mut self, r: u32, value: bool, log: &mut dyn Log) -> SlaveResult<()> {
        if r != vr::CONNECTED {
            return Err(err(format!("Boolean value reference {r} cannot be set")));
        }
        if let Some(b) = &mut self.model {
            if value && !self.inputs.connected {
                b.state.connected_fraction = 1.0;
                if let Machine::Spring(_) = b.generator.machine {
                    // resynchronised at reconnection: the spring starts untwisted
                    b.state.x[0] = 0.0;
                    log.event("reconnected to the grid (load angle reset to 0)");
                } else {
                    log.event("reconnected to the grid");
                }
            } else if !value && self.inputs.connected {
                log.event("tripped: generator torque decays with trip_time_constant");
            }
        }
        self.inputs.connected = value;
        Ok(())
    }

    fn get_string(&mut self, r: u32) -> SlaveResult<String> {
        Ok(match r {
            vr::PRESET => self.params.preset.clone(),
            vr::KIND => self.params.kind.clone(),
            vr::TORQUE_CONTROL => self.params.o.torque_control.clone(),
            _ => return Err(err(format!("String value reference {r} has no getter"))),
        })
    }

    fn set_string(&mut self, r: u32, value: &str, _: &mut dyn Log) -> SlaveResult<()> {
        let slot = match r {
            vr::PRESET => &mut self.params.preset,
            vr::KIND => &mut self.params.kind,
            vr::TORQUE_CONTROL => &mut self.params.o.torque_control,
            _ => return Err(err(format!("String value reference {r} cannot be set"))),
        };
        *slot = value.to_string();
        self.model = None;
        Ok(())
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
        if r != vr::GENERATOR_SPEED {
            return Err(err(format!("value reference {r} is not a Real input")));
        }
        self.inputs.speed.set_derivative(order, value)
    }

    fn do_step(&mut self, _t: f64, h: f64, _log: &mut dyn Log) -> SlaveResult<()> {
        let Inputs { speed: w, connected } = self.inputs;
        let tau = self.params.trip_time_constant;
        let bandwidth = self.params.o.current_bandwidth;
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
        self.inputs.speed.advance(h);
        Ok(())
    }
}
