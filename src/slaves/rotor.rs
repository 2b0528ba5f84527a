//! The `rotor` FMU: variables of modelDescription/rotor.xml mapped onto [`RotorModel`].

use crate::fmi2::slave::{Log, Slave, SlaveError, SlaveResult};
use crate::models::rotor as xml;
use crate::models::rotor::vr;
use crate::physics::aero::{PitchController, PitchState, Rotor};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::rotor::{
    PitchTarget, RotorModel, RotorOutputs, Shutdown, Source, TiltModel, TorqueSeries, preset_rotor, rated_wind_speed,
};
use crate::physics::turbulence::{TurbulenceModel, TurbulenceSeries, iec_sigma, kaimal_length};
use crate::slaves::InputPolynomial;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The Real parameters, in the order `Params::reals` stores them.
const REAL_PARAMS: [u32; 21] = [
    vr::WIND_SPEED,
    vr::TURBULENCE_INTENSITY,
    vr::RADIUS,
    vr::HUB_HEIGHT,
    vr::SHEAR_EXPONENT,
    vr::ROTOR_MASS,
    vr::OVERHANG,
    vr::PITCH_KP,
    vr::PITCH_KI,
    vr::PITCH_GAIN_HALVING,
    vr::PITCH_MAX_RATE,
    vr::PITCH_MAX,
    vr::SPEED_SETPOINT,
    vr::SOURCE_ROTOR_DIAMETER,
    vr::SHUTDOWN_TIME,
    vr::FEATHER_RATE,
    vr::TRIP_DELAY,
    vr::BRAKE_DELAY,
    vr::BRAKE_RAMP_TIME,
    vr::POWER_KP,
    vr::POWER_KI,
];
const STRING_PARAMS: [u32; 9] = [
    vr::PRESET,
    vr::SOURCE_PRESET,
    vr::MODE,
    vr::TURBULENCE,
    vr::TURBULENCE_CLASS,
    vr::SERIES,
    vr::SERIES_UNIT,
    vr::INTERPOLATION,
    vr::PITCH_CONTROL,
];

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Params {
    pub reals: Vec<f64>,
    pub strings: Vec<String>,
    pub seed: i32,
}

impl Params {
    fn real(&self, r: u32) -> f64 {
        self.reals[REAL_PARAMS.iter().position(|&x| x == r).expect("a Real parameter")]
    }
    fn string(&self, r: u32) -> &str {
        &self.strings[STRING_PARAMS.iter().position(|&x| x == r).expect("a String parameter")]
    }
}

/// What a set of parameters builds, with the numbers the calculated parameters report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Built {
    model: RotorModel,
    rated_wind_speed: f64,
    radius: f64,
    rated_rotor_torque: f64,
    sigma: f64,
}

fn err(msg: impl Into<String>) -> SlaveError {
    SlaveError::new(msg)
}

fn read_series(path: &Path, scale: f64, cubic: bool) -> SlaveResult<TorqueSeries> {
    let text = std::fs::read_to_string(path).map_err(|e| err(format!("series {}: {e}", path.display())))?;
    let (mut time, mut torque, mut pm) = (Vec::new(), Vec::new(), Vec::new());
    for (n, line) in text.lines().enumerate() {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if line.trim().is_empty() || line.trim_start().starts_with('#') {
            continue;
        }
        let nums: Result<Vec<f64>, _> = fields.iter().map(|f| f.parse::<f64>()).collect();
        match nums {
            Ok(v) if v.len() >= 2 && v.iter().all(|x| x.is_finite()) => {
                if time.last().is_some_and(|&t: &f64| v[0] <= t) {
                    return Err(err(format!(
                        "series {} line {}: time {} does not increase",
                        path.display(),
                        n + 1,
                        v[0]
                    )));
                }
                time.push(v[0]);
                torque.push(v[1] * scale);
                pm.push(v.get(2).copied().unwrap_or(0.0));
            }
            _ if time.is_empty() => continue, // header lines before the data
            _ => {
                return Err(err(format!(
                    "series {} line {}: expected time,torque[,pitching moment] numbers",
                    path.display(),
                    n + 1
                )));
            }
        }
    }
    if time.len() < 2 {
        return Err(err(format!("series {}: fewer than two samples", path.display())));
    }
    let has_pm = text.lines().any(|l| l.split(',').count() >= 3);
    Ok(TorqueSeries {
        time,
        torque,
        pitching_moment: has_pm.then_some(pm),
        cubic,
    })
}

impl Params {
    fn build(&self, resources: Option<&Path>) -> SlaveResult<Built> {
        let preset = self.string(vr::PRESET);
        let drivetrain = Drivetrain::preset(preset).ok_or_else(|| {
            err(format!(
                "parameter preset = {preset:?}: unknown drivetrain, use A, B, C or D"
            ))
        })?;
        let (r0, h0) = preset_rotor(&drivetrain, preset);
        let pick = |x: f64, default: f64| if x > 0.0 { x } else { default };
        let radius = pick(self.real(vr::RADIUS), r0);
        let hub_height = pick(self.real(vr::HUB_HEIGHT), h0);
        let rotor = Rotor {
            radius,
            lambda_min: 0.5,
        };
        let rated_speed = drivetrain.rated_rotor_speed;
        let rated_torque = drivetrain.rated_rotor_torque();
        let rated_wind = rated_wind_speed(&rotor, drivetrain.rated_power, rated_speed).map_err(err)?;
        let shutdown = Shutdown {
            time: self.real(vr::SHUTDOWN_TIME),
            feather_rate: self.real(vr::FEATHER_RATE),
            trip_delay: self.real(vr::TRIP_DELAY),
            brake_delay: self.real(vr::BRAKE_DELAY),
            brake_ramp_time: self.real(vr::BRAKE_RAMP_TIME),
        };
        let mut sigma = 0.0;
        let source = match self.string(vr::MODE).trim() {
            "aero" => {
                let mean_wind = pick(self.real(vr::WIND_SPEED), rated_wind);
                let class = self.string(vr::TURBULENCE_CLASS).trim().to_ascii_uppercase();
                let i_ref = match class.as_str() {
                    "A" => 0.16,
                    "B" => 0.14,
                    "C" => 0.12,
                    other => return Err(err(format!("parameter turbulence_class = {other:?}: use A, B or C"))),
                };
                let model = match self.string(vr::TURBULENCE).trim() {
                    "none" => None,
                    "ntm" => Some(TurbulenceModel::Ntm),
                    "etm" => Some(TurbulenceModel::Etm),
                    other => return Err(err(format!("parameter turbulence = {other:?}: use none, ntm or etm"))),
                };
                let ti = self.real(vr::TURBULENCE_INTENSITY);
                sigma = match model {
                    None => 0.0,
                    Some(_) if ti > 0.0 => ti * mean_wind,
                    Some(m) => iec_sigma(m, mean_wind, i_ref, 50.0),
                };
                let turbulence = (sigma > 0.0).then(|| {
                    // 0.05 s spacing (content to 10 Hz), 2^16 samples: periodic over 3277 s
                    TurbulenceSeries::kaimal(
                        sigma,
                        kaimal_length(hub_height),
                        mean_wind,
                        0.05,
                        1 << 16,
                        self.seed as u32 as u64,
                    )
                });
                let gear_ratio = drivetrain.gear_ratio();
                let (target, kp, ki) = match self.string(vr::PITCH_CONTROL).trim() {
                    "speed" => (
                        PitchTarget::Speed(pick(self.real(vr::SPEED_SETPOINT), rated_speed * gear_ratio)),
                        self.real(vr::PITCH_KP),
                        self.real(vr::PITCH_KI),
                    ),
                    "power" => (
                        PitchTarget::Power(drivetrain.rated_power),
                        self.real(vr::POWER_KP),
                        self.real(vr::POWER_KI),
                    ),
                    other => return Err(err(format!("parameter pitch_control = {other:?}: use speed or power"))),
                };
                Source::Aero {
                    rotor,
                    mean_wind,
                    turbulence,
                    pitch: PitchController {
                        kp,
                        ki,
                        gain_halving_pitch: self.real(vr::PITCH_GAIN_HALVING),
                        min_pitch: 0.0,
                        max_pitch: self.real(vr::PITCH_MAX),
                        max_rate: self.real(vr::PITCH_MAX_RATE),
                    },
                    target,
                    tilt: TiltModel::new(
                        radius,
                        hub_height,
                        self.real(vr::SHEAR_EXPONENT),
                        self.real(vr::ROTOR_MASS),
                        self.real(vr::OVERHANG),
                    ),
                    gear_ratio,
                }
            }
            "playback" => {
                let name = self.string(vr::SERIES).trim();
                if name.is_empty() {
                    return Err(err(
                        "mode = playback needs the parameter series (a CSV file of time, torque)",
                    ));
                }
                let mut path = PathBuf::from(name);
                if path.is_relative()
                    && let Some(dir) = resources
                {
                    path = dir.join(name);
                }
                let per_unit = match self.string(vr::SERIES_UNIT).trim() {
                    "pu" => true,
                    "N.m" | "Nm" => false,
                    other => return Err(err(format!("parameter series_unit = {other:?}: use pu or N.m"))),
                };
                let d_source = self.real(vr::SOURCE_ROTOR_DIAMETER);
                let source_preset = self.string(vr::SOURCE_PRESET).trim();
                // (torque per unit, rotor diameter) of the turbine the series was recorded on
                let (unit_scale, d_source) = if source_preset.is_empty() {
                    if d_source > 0.0 && per_unit {
                        return Err(err(
                            "source_rotor_diameter scales an absolute series (series_unit = N.m); a per-unit series \
                             is already scaled by the preset's rated rotor torque (or give source_preset)",
                        ));
                    }
                    (if per_unit { rated_torque } else { 1.0 }, d_source)
                } else {
                    if d_source > 0.0 {
                        return Err(err("give source_preset or source_rotor_diameter, not both"));
                    }
                    let source = Drivetrain::preset(source_preset).ok_or_else(|| {
                        err(format!(
                            "parameter source_preset = {source_preset:?}: use A, B, C or D (or leave it empty)"
                        ))
                    })?;
                    let (r_source, _) = preset_rotor(&source, source_preset);
                    (if per_unit { source.rated_rotor_torque() } else { 1.0 }, 2.0 * r_source)
                };
                let diameter_scale = if d_source > 0.0 {
                    (2.0 * radius / d_source).powi(3)
                } else {
                    1.0
                };
                let cubic = match self.string(vr::INTERPOLATION).trim() {
                    "linear" => false,
                    "cubic" => true,
                    other => return Err(err(format!("parameter interpolation = {other:?}: use linear or cubic"))),
                };
                Source::Playback(read_series(&path, unit_scale * diameter_scale, cubic)?)
            }
            other => return Err(err(format!("parameter mode = {other:?}: use aero or playback"))),
        };
        Ok(Built {
            model: RotorModel {
                source,
                shutdown,
                state: PitchState::default(),
                time: 0.0,
            },
            rated_wind_speed: rated_wind,
            radius,
            rated_rotor_torque: rated_torque,
            sigma,
        })
    }
}

#[derive(Clone, Serialize, Deserialize)]
pub struct RotorSlave {
    pub params: Params,
    /// Rotor speed and its time derivatives (canInterpolateInputs; used at the step's midpoint).
    pub speed: InputPolynomial,
    resources: Option<PathBuf>,
    built: Option<Built>,
    start_time: f64,
    /// Outputs at (time, rotor speed) last computed: a master reads several per step.
    #[serde(skip)]
    cache: Option<(f64, f64, RotorOutputs)>,
}

impl RotorSlave {
    fn ensure(&mut self) -> SlaveResult<&mut Built> {
        if self.built.is_none() {
            let mut b = self.params.build(self.resources.as_deref())?;
            b.model.time = self.start_time;
            self.built = Some(b);
        }
        Ok(self.built.as_mut().expect("just built"))
    }
}

impl Slave for RotorSlave {
    crate::slave_interface_from_xml!();

    fn instantiate(resources: Option<&Path>) -> Self {
        let mut s = Self {
            params: Params {
                reals: vec![0.0; REAL_PARAMS.len()],
                strings: vec![String::new(); STRING_PARAMS.len()],
                seed: 1,
            },
            speed: InputPolynomial::default(),
            resources: resources.map(Path::to_path_buf),
            built: None,
            start_time: 0.0,
            cache: None,
        };
        crate::fmi2::slave::apply_start_values(&mut s);
        s
    }

    fn get_real(&mut self, r: u32) -> SlaveResult<f64> {
        if let Some(i) = REAL_PARAMS.iter().position(|&x| x == r) {
            return Ok(self.params.reals[i]);
        }
        if r == vr::ROTOR_SPEED {
            return Ok(self.speed.value());
        }
        let omega = self.speed.value();
        let cache = self.cache;
        let b = self.ensure()?;
        let out = match cache {
            Some((t, w, out)) if t == b.model.time && w == omega => out,
            _ => b.model.outputs(omega),
        };
        let time = b.model.time;
        let value = match r {
            vr::RATED_WIND_SPEED => b.rated_wind_speed,
            vr::RADIUS_USED => b.radius,
            vr::RATED_ROTOR_TORQUE => b.rated_rotor_torque,
            vr::TURBULENCE_SIGMA => b.sigma,
            vr::ROTOR_TORQUE => out.torque,
            vr::PITCHING_MOMENT => out.pitching_moment,
            vr::BRAKE_COMMAND => b.model.shutdown.brake_command(b.model.time),
            vr::PITCH => out.pitch,
            vr::WIND_SPEED_HUB => out.wind_speed,
            vr::THRUST => out.thrust,
            vr::AERODYNAMIC_POWER => out.torque * omega,
            _ => return Err(err(format!("Real value reference {r} has no getter"))),
        };
        self.cache = Some((time, omega, out));
        Ok(value)
    }

    fn set_real(&mut self, r: u32, value: f64, _: &mut dyn Log) -> SlaveResult<()> {
        if r == vr::ROTOR_SPEED {
            self.speed.set(value);
            return Ok(());
        }
        let i = REAL_PARAMS
            .iter()
            .position(|&x| x == r)
            .ok_or_else(|| err(format!("Real value reference {r} cannot be set")))?;
        self.params.reals[i] = value;
        self.built = None;
        self.cache = None;
        Ok(())
    }

    fn get_integer(&mut self, r: u32) -> SlaveResult<i32> {
        match r {
            vr::SEED => Ok(self.params.seed),
            _ => Err(err(format!("Integer value reference {r} has no getter"))),
        }
    }

    fn set_integer(&mut self, r: u32, value: i32, _: &mut dyn Log) -> SlaveResult<()> {
        match r {
            vr::SEED => {
                self.params.seed = value;
                self.built = None;
                self.cache = None;
                Ok(())
            }
            _ => Err(err(format!("Integer value reference {r} cannot be set"))),
        }
    }

    fn get_boolean(&mut self, r: u32) -> SlaveResult<bool> {
        match r {
            vr::GENERATOR_CONNECTED => {
                let b = self.ensure()?;
                Ok(b.model.shutdown.generator_connected(b.model.time))
            }
            _ => Err(err(format!("Boolean value reference {r} has no getter"))),
        }
    }

    fn set_boolean(&mut self, r: u32, _: bool, _: &mut dyn Log) -> SlaveResult<()> {
        Err(err(format!("Boolean value reference {r} cannot be set")))
    }

    fn get_string(&mut self, r: u32) -> SlaveResult<String> {
        STRING_PARAMS
            .iter()
            .position(|&x| x == r)
            .map(|i| self.params.strings[i].clone())
            .ok_or_else(|| err(format!("String value reference {r} has no getter")))
    }

    fn set_string(&mut self, r: u32, value: &str, _: &mut dyn Log) -> SlaveResult<()> {
        let i = STRING_PARAMS
            .iter()
            .position(|&x| x == r)
            .ok_or_else(|| err(format!("String value reference {r} cannot be set")))?;
        self.params.strings[i] = value.to_string();
        self.built = None;
        self.cache = None;
        Ok(())
    }

    fn initialize(&mut self, start_time: f64, _log: &mut dyn Log) -> SlaveResult<()> {
        self.start_time = start_time;
        self.built = None;
        self.cache = None;
        self.ensure().map(|_| ())
    }

    fn set_input_derivative(&mut self, r: u32, order: i32, value: f64) -> SlaveResult<()> {
        if r != vr::ROTOR_SPEED {
            return Err(err(format!("value reference {r} is not a Real input")));
        }
        self.speed.set_derivative(order, value)
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut dyn Log) -> SlaveResult<()> {
        let w = self.speed;
        let b = self.ensure()?;
        let sd = b.model.shutdown;
        let (before, after) = (t, t + h);
        if sd.time >= 0.0 {
            let crossed = |at: f64| before < at && at <= after;
            if crossed(sd.time) {
                log.event(&format!("shutdown at t = {} s: pitching to feather", sd.time));
            }
            if crossed(sd.time + sd.trip_delay) {
                log.event("generator tripped (generator_connected = false)");
            }
            if crossed(sd.time + sd.brake_delay) {
                log.event("HSS brake deploying");
            }
        }
        // the controller sees the speed at the middle of the step (second order in h)
        b.model.advance(w.at(h / 2.0), h);
        self.speed.advance(h);
        Ok(())
    }
}
