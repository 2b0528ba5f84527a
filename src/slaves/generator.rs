//! The `generator` FMU: variables of modelDescription/generator.xml mapped onto
//! [`SpringGenerator`].

use crate::fmi2::slave::{Log, Slave, SlaveError, SlaveResult};
use crate::models::generator as xml;
use crate::models::generator::vr;
use crate::physics::drivetrain::Drivetrain;
use crate::physics::generator::{SpringGenerator, SpringState};
use crate::slaves::InputPolynomial;
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Params {
    pub preset: String,
    pub kind: String,
    pub stiffness: f64,
    pub damping: f64,
    pub synchronous_speed: f64,
    pub initial_torque: f64,
    pub trip_time_constant: f64,
}

/// The speed input with its time derivatives (orders 1 and 2), and the grid connection.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Inputs {
    pub speed: InputPolynomial,
    pub connected: bool,
}

#[derive(Clone, Serialize, Deserialize)]
pub struct GeneratorSlave {
    pub params: Params,
    pub inputs: Inputs,
    /// The model and its state, built from `params` when first needed.
    model: Option<(SpringGenerator, SpringState)>,
}

fn err(msg: impl Into<String>) -> SlaveError {
    SlaveError::new(msg)
}

impl Params {
    fn build(&self) -> SlaveResult<(SpringGenerator, SpringState)> {
        let drivetrain = Drivetrain::preset(&self.preset).ok_or_else(|| {
            err(format!(
                "parameter preset = {:?}: unknown drivetrain, use A, B, C or D",
                self.preset
            ))
        })?;
        if self.kind.trim() != "spring" {
            return Err(err(format!(
                "parameter kind = {:?}: this FMU models kind spring",
                self.kind
            )));
        }
        let stiffness = if self.stiffness > 0.0 {
            self.stiffness
        } else {
            drivetrain.k_generator
        };
        let synchronous_speed = if self.synchronous_speed > 0.0 {
            self.synchronous_speed
        } else {
            drivetrain.rated_rotor_speed * drivetrain.gear_ratio()
        };
        let g = SpringGenerator {
            stiffness,
            damping: self.damping,
            synchronous_speed,
        };
        Ok((g, g.initial_state(self.initial_torque)))
    }
}

impl GeneratorSlave {
    fn ensure(&mut self) -> SlaveResult<&mut (SpringGenerator, SpringState)> {
        if self.model.is_none() {
            self.model = Some(self.params.build()?);
        }
        Ok(self.model.as_mut().expect("just built"))
    }
}

impl Slave for GeneratorSlave {
    crate::slave_interface_from_xml!();

    fn instantiate(_resources: Option<&Path>) -> Self {
        let mut s = Self {
            params: Params::default(),
            inputs: Inputs::default(),
            model: None,
        };
        crate::fmi2::slave::apply_start_values(&mut s);
        s
    }

    fn get_real(&mut self, r: u32) -> SlaveResult<f64> {
        let p = &self.params;
        let direct = match r {
            vr::STIFFNESS => Some(p.stiffness),
            vr::DAMPING => Some(p.damping),
            vr::SYNCHRONOUS_SPEED => Some(p.synchronous_speed),
            vr::INITIAL_TORQUE => Some(p.initial_torque),
            vr::TRIP_TIME_CONSTANT => Some(p.trip_time_constant),
            vr::GENERATOR_SPEED => Some(self.inputs.speed.value()),
            _ => None,
        };
        if let Some(v) = direct {
            return Ok(v);
        }
        let omega = self.inputs.speed.value();
        let (g, st) = *self.ensure()?;
        Ok(match r {
            vr::STIFFNESS_USED => g.stiffness,
            vr::SYNCHRONOUS_SPEED_USED => g.synchronous_speed,
            vr::GENERATOR_TORQUE => g.torque(&st, omega),
            vr::LOAD_ANGLE => st.load_angle,
            vr::ELECTRICAL_POWER => g.torque(&st, omega) * omega,
            _ => return Err(err(format!("Real value reference {r} has no getter"))),
        })
    }

    fn set_real(&mut self, r: u32, value: f64, _: &mut dyn Log) -> SlaveResult<()> {
        if r == vr::GENERATOR_SPEED {
            self.inputs.speed.set(value);
            return Ok(());
        }
        let p = &mut self.params;
        let slot = match r {
            vr::STIFFNESS => &mut p.stiffness,
            vr::DAMPING => &mut p.damping,
            vr::SYNCHRONOUS_SPEED => &mut p.synchronous_speed,
            vr::INITIAL_TORQUE => &mut p.initial_torque,
            vr::TRIP_TIME_CONSTANT => &mut p.trip_time_constant,
            _ => return Err(err(format!("Real value reference {r} cannot be set"))),
        };
        *slot = value;
        self.model = None;
        Ok(())
    }

    fn get_integer(&mut self, r: u32) -> SlaveResult<i32> {
        Err(err(format!("Integer value reference {r} has no getter")))
    }

    fn set_integer(&mut self, r: u32, _: i32, _: &mut dyn Log) -> SlaveResult<()> {
        Err(err(format!("Integer value reference {r} cannot be set")))
    }

    fn get_boolean(&mut self, r: u32) -> SlaveResult<bool> {
        match r {
            vr::CONNECTED => Ok(self.inputs.connected),
            _ => Err(err(format!("Boolean value reference {r} has no getter"))),
        }
    }

    fn set_boolean(&mut self, r: u32, value: bool, log: &mut dyn Log) -> SlaveResult<()> {
        match r {
            vr::CONNECTED => {
                if value && !self.inputs.connected {
                    // resynchronised at reconnection: the spring starts untwisted
                    if let Some((_, st)) = &mut self.model {
                        *st = SpringState {
                            load_angle: 0.0,
                            connected_fraction: 1.0,
                        };
                        log.event("reconnected to the grid (load angle reset to 0)");
                    }
                } else if !value && self.inputs.connected && self.model.is_some() {
                    log.event("tripped: generator torque decays with trip_time_constant");
                }
                self.inputs.connected = value;
                Ok(())
            }
            _ => Err(err(format!("Boolean value reference {r} cannot be set"))),
        }
    }

    fn get_string(&mut self, r: u32) -> SlaveResult<String> {
        Ok(match r {
            vr::PRESET => self.params.preset.clone(),
            vr::KIND => self.params.kind.clone(),
            _ => return Err(err(format!("String value reference {r} has no getter"))),
        })
    }

    fn set_string(&mut self, r: u32, value: &str, _: &mut dyn Log) -> SlaveResult<()> {
        let slot = match r {
            vr::PRESET => &mut self.params.preset,
            vr::KIND => &mut self.params.kind,
            _ => return Err(err(format!("String value reference {r} cannot be set"))),
        };
        *slot = value.to_string();
        self.model = None;
        Ok(())
    }

    fn initialize(&mut self, _start_time: f64, _log: &mut dyn Log) -> SlaveResult<()> {
        self.ensure().map(|_| ())
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
        let (g, st) = self.ensure()?;
        g.advance(st, w.0, h, connected, tau);
        // the input polynomial continues from the new communication point
        self.inputs.speed.advance(h);
        Ok(())
    }
}
