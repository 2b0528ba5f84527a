//! The `rotor` FMU: variables of modelDescription/rotor.xml mapped onto [`RotorModel`].

use crate::fmi2::fmu::error::{ParameterError, SlaveError, SlaveResult};
use crate::fmi2::fmu::slave::{Changed, Log, Slave};
use crate::fmi2::fmu::variables::VarType;
use crate::models::rotor as xml;
use crate::models::rotor::vr;
use crate::physics::aero::{AIR_DENSITY, PitchController, PitchState, Rotor};
use crate::physics::bem::BemRotor;
use crate::physics::blade::Blade;
use crate::physics::blades::{BladeSampling, DiscMotion};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::rotor::{
    Aerodynamics, CONTROL_STEP, PitchTarget, RotorModel, RotorOutputs, SequenceState, Shutdown, Source, Startup,
    TiltModel, TorqueSeries, preset_rotor, rated_wind_speed, trim_pitch,
};
use crate::physics::turbulence::{
    TurbulenceModel, TurbulenceSeries, Variance, class_reference_intensity, iec_sigma, kaimal_length, sampling,
};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Every parameter of rotor.xml (generated from it).
pub type Params = xml::Parameters;
/// The rotor speed input with its time derivatives (canInterpolateInputs; used at the step's midpoint).
pub type Inputs = xml::Inputs;

/// What a set of parameters builds, with the numbers the calculated parameters report.
#[derive(Debug, PartialEq)]
struct Built {
    model: RotorModel,
    rated_wind_speed: f64,
    rated_tip_speed_ratio: f64,
    radius: f64,
    rated_rotor_torque: f64,
    sigma: f64,
}

impl Clone for Built {
    fn clone(&self) -> Self {
        Self {
            model: self.model.clone(),
            ..*self
        }
    }

    /// Field by field, so that the model keeps its shared source (see `RotorModel::clone_from`).
    fn clone_from(&mut self, other: &Self) {
        self.model.clone_from(&other.model);
        self.rated_wind_speed = other.rated_wind_speed;
        self.rated_tip_speed_ratio = other.rated_tip_speed_ratio;
        self.radius = other.radius;
        self.rated_rotor_torque = other.rated_rotor_torque;
        self.sigma = other.sigma;
    }
}

/// A torque series the rotor cannot play back, naming the file and line.
#[derive(Debug, thiserror::Error)]
pub enum SeriesError {
    #[error("series {}: {source}", path.display())]
    Read { path: PathBuf, source: std::io::Error },
    #[error("series {} line {line}: time {time} does not increase", path.display())]
    NotIncreasing { path: PathBuf, line: usize, time: f64 },
    #[error("series {} line {line}: expected time,torque[,pitching moment] numbers", path.display())]
    Malformed { path: PathBuf, line: usize },
    #[error("series {}: fewer than two samples", path.display())]
    TooShort { path: PathBuf },
}

impl From<SeriesError> for SlaveError {
    fn from(e: SeriesError) -> Self {
        SlaveError::new(e.to_string())
    }
}

fn read_series(path: &Path, scale: f64, cubic: bool) -> Result<TorqueSeries, SeriesError> {
    let text = std::fs::read_to_string(path).map_err(|source| SeriesError::Read {
        path: path.into(),
        source,
    })?;
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
                    return Err(SeriesError::NotIncreasing {
                        path: path.into(),
                        line: n + 1,
                        time: v[0],
                    });
                }
                time.push(v[0]);
                torque.push(v[1] * scale);
                pm.push(v.get(2).copied().unwrap_or(0.0));
            }
            _ if time.is_empty() => continue, // header lines before the data
            _ => {
                return Err(SeriesError::Malformed {
                    path: path.into(),
                    line: n + 1,
                });
            }
        }
    }
    if time.len() < 2 {
        return Err(SeriesError::TooShort { path: path.into() });
    }
    let has_pm = text.lines().any(|l| l.split(',').count() >= 3);
    Ok(TorqueSeries {
        time,
        torque,
        pitching_moment: has_pm.then_some(pm),
        cubic,
    })
}

mod blade_field;

/// The blade folder named by the parameter `blade`: an absolute path, or a name under resources/blades/.
fn blade_dir(name: &str, resources: Option<&Path>) -> SlaveResult<PathBuf> {
    let path = PathBuf::from(name);
    if name.is_empty() {
        return Err(
            ParameterError::invalid("blade", &name, "name a folder under resources/blades/ or give a path").into(),
        );
    }
    if path.is_absolute() {
        return Ok(path);
    }
    match resources {
        Some(dir) => Ok(dir.join("blades").join(path)),
        None => Err(SlaveError::new(format!(
            "parameter blade = {name:?}: the FMU has no resources folder to look it up in; give an absolute path \
             or aerodynamics = analytic"
        ))),
    }
}

impl Params {
    /// The rotor's aerodynamics and its tip radius: `radius` (the preset's `preset_radius` when 0), the
    /// BEM's blade scaled to it; or with `scale_blade_to_radius` false the blade as its files give it,
    /// whose tip radius is then the rotor's (`radius` must be 0 or that).
    fn aerodynamics(&self, preset_radius: f64, resources: Option<&Path>) -> SlaveResult<(Aerodynamics, f64)> {
        let radius = if self.radius > 0.0 { self.radius } else { preset_radius };
        match self.aerodynamics.trim() {
            "bem" => {
                let dir = blade_dir(self.blade.trim(), resources)?;
                let blade = Blade::load(&dir).map_err(|e| SlaveError::new(e.to_string()))?;
                if self.scale_blade_to_radius {
                    return Ok((
                        Aerodynamics::Bem(BemRotor::new(blade.scaled(radius), AIR_DENSITY)),
                        radius,
                    ));
                }
                let tip = blade.tip_radius();
                if self.radius > 0.0 && (self.radius - tip).abs() > 1e-9 * tip {
                    return Err(ParameterError::Conflict(format!(
                        "radius = {} m, but scale_blade_to_radius = false keeps the blade {} as stored, tip radius \
                         {tip} m: set radius = 0 (or {tip}), or scale_blade_to_radius = true",
                        self.radius,
                        dir.display()
                    ))
                    .into());
                }
                Ok((Aerodynamics::Bem(BemRotor::new(blade, AIR_DENSITY)), tip))
            }
            "analytic" => Ok((
                Aerodynamics::Analytic(Rotor {
                    radius,
                    lambda_min: 0.5,
                }),
                radius,
            )),
            other => Err(ParameterError::invalid("aerodynamics", &other, "use bem or analytic").into()),
        }
    }

    /// The controller's and the shutdown's numbers, checked before any reaches the physics (where a
    /// limit of −inf or a NaN gain would make `clamp` panic or the pitch non-finite).
    fn check_control(&self) -> SlaveResult<()> {
        let finite = [
            ("pitch_kp", self.pitch_kp),
            ("pitch_ki", self.pitch_ki),
            ("power_kp", self.power_kp),
            ("power_ki", self.power_ki),
            ("pitch_max_rate", self.pitch_max_rate),
            ("pitch_max", self.pitch_max),
            ("feather_rate", self.feather_rate),
            ("startup_pitch_rate", self.startup_pitch_rate),
            ("connect_speed_ratio", self.connect_speed_ratio),
            ("pitch_delay", self.pitch_delay),
            ("brake_speed_ratio", self.brake_speed_ratio),
        ];
        for (name, v) in finite {
            if !(v.is_finite() && v >= 0.0) {
                return Err(ParameterError::invalid(name, &v, "must be finite and ≥ 0").into());
            }
        }
        // 0 or below: the rated wind speed
        if !self.wind_speed.is_finite() {
            return Err(ParameterError::invalid("wind_speed", &self.wind_speed, "must be finite").into());
        }
        if !(self.pitch_gain_halving.is_finite() && self.pitch_gain_halving > 0.0) {
            return Err(ParameterError::invalid(
                "pitch_gain_halving",
                &self.pitch_gain_halving,
                "must be finite and positive",
            )
            .into());
        }
        if self.pitch_max > std::f64::consts::PI {
            return Err(
                ParameterError::invalid("pitch_max", &self.pitch_max, "beyond π rad: not a pitch angle").into(),
            );
        }
        Ok(())
    }

    /// Every enumerated String parameter read, in either mode: a misspelt choice is an error even
    /// where the mode does not use it (a user who set it meant something by it).
    fn choices(&self) -> Result<Choices, ParameterError> {
        let class = self.turbulence_class.trim().to_ascii_uppercase();
        let source_preset = self.source_preset.trim();
        Ok(Choices {
            i_ref: class_reference_intensity(&class)
                .ok_or_else(|| ParameterError::invalid("turbulence_class", &class.as_str(), "use A, B or C"))?,
            turbulence: match self.turbulence.trim() {
                "none" => None,
                "ntm" => Some(TurbulenceModel::Ntm),
                "etm" => Some(TurbulenceModel::Etm),
                other => return Err(ParameterError::invalid("turbulence", &other, "use none, ntm or etm")),
            },
            blades: match self.wind_sampling.trim() {
                "rotor_average" => false,
                "blades" => true,
                other => {
                    return Err(ParameterError::invalid(
                        "wind_sampling",
                        &other,
                        "use rotor_average or blades",
                    ));
                }
            },
            rotor_average: match self.wind_averaging.trim() {
                "rotor" => true,
                "hub" => false,
                other => return Err(ParameterError::invalid("wind_averaging", &other, "use rotor or hub")),
            },
            period_variance: match self.turbulence_scaling.trim() {
                "ten_minute" => Variance::TenMinute,
                "period" => Variance::Period,
                other => {
                    return Err(ParameterError::invalid(
                        "turbulence_scaling",
                        &other,
                        "use ten_minute or period",
                    ));
                }
            },
            power_control: match self.pitch_control.trim() {
                "speed" => false,
                "power" => true,
                other => return Err(ParameterError::invalid("pitch_control", &other, "use speed or power")),
            },
            per_unit: match self.series_unit.trim() {
                "pu" => true,
                "N.m" | "Nm" => false,
                other => return Err(ParameterError::invalid("series_unit", &other, "use pu or N.m")),
            },
            cubic: match self.interpolation.trim() {
                "linear" => false,
                "cubic" => true,
                other => return Err(ParameterError::invalid("interpolation", &other, "use linear or cubic")),
            },
            source: if source_preset.is_empty() {
                None
            } else {
                let d = Drivetrain::preset(source_preset).ok_or_else(|| {
                    ParameterError::invalid(
                        "source_preset",
                        &source_preset,
                        "use A, B, C, D or P (or leave it empty)",
                    )
                })?;
                Some((d, source_preset.to_string()))
            },
        })
    }

    fn build(&self, resources: Option<&Path>) -> SlaveResult<Built> {
        self.check_control()?;
        let choices = self.choices()?;
        let preset = self.preset.as_str();
        let drivetrain = Drivetrain::preset(preset)
            .ok_or_else(|| ParameterError::invalid("preset", &preset, "unknown drivetrain, use A, B, C, D or P"))?;
        if !matches!(self.mode.trim(), "aero" | "playback") {
            return Err(ParameterError::invalid("mode", &self.mode.trim(), "use aero or playback").into());
        }
        let (r0, h0) = preset_rotor(&drivetrain, preset);
        let pick = |x: f64, default: f64| if x > 0.0 { x } else { default };
        let hub_height = pick(self.hub_height, h0);
        let (rotor, radius) = self.aerodynamics(r0, resources)?;
        let rated_speed = drivetrain.rated_rotor_speed;
        let rated_torque = drivetrain.rated_rotor_torque();
        let rated_wind =
            rated_wind_speed(&rotor, drivetrain.rated_power, rated_speed).map_err(ParameterError::Model)?;
        if self.initial_pitch > self.pitch_max {
            return Err(ParameterError::Conflict(format!(
                "initial_pitch = {} rad: must not exceed pitch_max = {} rad",
                self.initial_pitch, self.pitch_max
            ))
            .into());
        }
        let wind_file = self.wind_file.trim();
        if !wind_file.is_empty() && !choices.blades {
            let why = "a full field is read only with wind_sampling = blades (rotor_average takes the series)";
            return Err(ParameterError::invalid("wind_file", &wind_file, why).into());
        }
        let sampled = choices.blades && self.mode.trim() == "aero";
        let file_field = match wind_file {
            "" => None,
            _ if !sampled => None,
            name => Some(blade_field::read(name, resources)?),
        };
        let mean_wind = match &file_field {
            Some((field, _)) => field.mean_hub,
            None => pick(self.wind_speed, rated_wind),
        };
        let pitch = if self.initial_pitch >= 0.0 {
            self.initial_pitch
        } else {
            trim_pitch(&rotor, mean_wind, drivetrain.rated_power, rated_speed, self.pitch_max)
        };
        let mut state = PitchState { pitch, integral: 0.0 };
        if !self.startup_time.is_finite() {
            return Err(ParameterError::invalid("startup_time", &self.startup_time, "must be finite").into());
        }
        let startup = Startup {
            time: self.startup_time,
            pitch_rate: self.startup_pitch_rate,
            connect_speed: self.connect_speed_ratio * rated_speed,
        };
        let shutdown = Shutdown {
            time: self.shutdown_time,
            feather_rate: self.feather_rate,
            pitch_delay: self.pitch_delay,
            brake_speed: self.brake_speed_ratio * rated_speed,
            trip_delay: self.trip_delay,
            brake_delay: self.brake_delay,
            brake_ramp_time: self.brake_ramp_time,
        };
        let mut sigma = 0.0;
        let source = match self.mode.trim() {
            "aero" => {
                let (i_ref, model) = (choices.i_ref, choices.turbulence);
                let ti = self.turbulence_intensity;
                sigma = match model {
                    None => 0.0,
                    Some(_) if ti > 0.0 => ti * mean_wind,
                    Some(m) => iec_sigma(m, mean_wind, i_ref, 50.0),
                };
                // a day at 0.05 s is 1.7 million samples, beyond it the series would only cost memory; below
                // a second there is no turbulence to speak of, and the spacing would shrink without end
                let period = self.turbulence_period;
                if !(period == 0.0 || (1.0..=86_400.0).contains(&period)) {
                    let why = "must be 0 (3276.8 s) or 1 to 86 400 s";
                    return Err(ParameterError::invalid("turbulence_period", &self.turbulence_period, why).into());
                }
                if let Some((field, _)) = &file_field {
                    sigma = blade_field::hub_sigma(field, hub_height);
                }
                let turbulence = (sigma > 0.0 && !sampled).then(|| {
                    // a window of its own: its period, spacing ≤ 0.05 s (content to 10 Hz), σ the 10-minute
                    // one or the period's (turbulence_scaling); else one long record of 2^16 samples at
                    // 0.05 s (3276.8 s), the spectrum as it is
                    let ((dt, n), variance) = if self.turbulence_period > 0.0 {
                        (sampling(self.turbulence_period, 0.05), choices.period_variance)
                    } else {
                        ((0.05, 1 << 16), Variance::Spectrum)
                    };
                    let (length, seed) = (kaimal_length(hub_height), self.seed as u32 as u64);
                    if choices.rotor_average {
                        TurbulenceSeries::kaimal_rotor_average(sigma, length, mean_wind, radius, dt, n, variance, seed)
                    } else {
                        TurbulenceSeries::kaimal(sigma, length, mean_wind, dt, n, variance, seed)
                    }
                });
                let gear_ratio = drivetrain.gear_ratio();
                let (target, kp, ki) = if choices.power_control {
                    (PitchTarget::Power(drivetrain.rated_power), self.power_kp, self.power_ki)
                } else {
                    (
                        PitchTarget::Speed(pick(self.speed_setpoint, rated_speed * gear_ratio)),
                        self.pitch_kp,
                        self.pitch_ki,
                    )
                };
                // bumpless start at initial_pitch: the integral alone commands it (GK·K_I·∫e = β₀)
                if ki > 0.0 {
                    let gk = 1.0 / (1.0 + state.pitch / self.pitch_gain_halving);
                    state.integral = state.pitch / (gk * ki);
                }
                let blades = if sampled {
                    let Aerodynamics::Bem(bem) = &rotor else {
                        return Err(ParameterError::Conflict(
                            "wind_sampling = blades needs aerodynamics = bem: the analytic C_p has no blade elements to \
                             sample the field with"
                                .into(),
                        )
                        .into());
                    };
                    let (field, origin) = match file_field {
                        Some(f) => f,
                        None => {
                            let generated = blade_field::FieldRequest {
                                mean_wind,
                                sigma,
                                hub_height,
                                radius,
                                shear_exponent: self.shear_exponent,
                                period: self.turbulence_period,
                                variance: choices.period_variance,
                                seed: self.seed as u32 as u64,
                            };
                            (generated.generate()?, "the generated field".to_string())
                        }
                    };
                    let sampling = BladeSampling::new(bem, field, hub_height, 0.0, self.pitch_max)
                        .map_err(|e| SlaveError::new(format!("wind_sampling = blades, {origin}: {e}")))?;
                    Some(Box::new(sampling))
                } else {
                    None
                };
                Source::Aero {
                    rotor,
                    mean_wind,
                    turbulence,
                    pitch: PitchController {
                        kp,
                        ki,
                        gain_halving_pitch: self.pitch_gain_halving,
                        min_pitch: 0.0,
                        max_pitch: self.pitch_max,
                        max_rate: self.pitch_max_rate,
                    },
                    target,
                    tilt: TiltModel::new(radius, hub_height, self.shear_exponent, self.rotor_mass, self.overhang),
                    gear_ratio,
                    blades,
                }
            }
            "playback" => {
                let name = self.series.trim();
                if name.is_empty() {
                    return Err(ParameterError::Conflict(
                        "mode = playback needs the parameter series (a CSV file of time, torque)".into(),
                    )
                    .into());
                }
                let mut path = PathBuf::from(name);
                if path.is_relative()
                    && let Some(dir) = resources
                {
                    path = dir.join(name);
                }
                let per_unit = choices.per_unit;
                let d_source = self.source_rotor_diameter;
                // (torque per unit, rotor diameter) of the turbine the series was recorded on
                let (unit_scale, d_source) = if let Some((source, source_preset)) = &choices.source {
                    if d_source > 0.0 {
                        return Err(ParameterError::Conflict(
                            "give source_preset or source_rotor_diameter, not both".into(),
                        )
                        .into());
                    }
                    let (r_source, _) = preset_rotor(source, source_preset);
                    (if per_unit { source.rated_rotor_torque() } else { 1.0 }, 2.0 * r_source)
                } else {
                    if d_source > 0.0 && per_unit {
                        return Err(ParameterError::Conflict(
                            "source_rotor_diameter scales an absolute series (series_unit = N.m); a per-unit series \
                             is already scaled by the preset's rated rotor torque (or give source_preset)"
                                .into(),
                        )
                        .into());
                    }
                    (if per_unit { rated_torque } else { 1.0 }, d_source)
                };
                let diameter_scale = if d_source > 0.0 {
                    (2.0 * radius / d_source).powi(3)
                } else {
                    1.0
                };
                Source::Playback(read_series(&path, unit_scale * diameter_scale, choices.cubic)?)
            }
            other => return Err(ParameterError::invalid("mode", &other, "use aero or playback").into()),
        };
        Ok(Built {
            model: RotorModel {
                source: std::sync::Arc::new(source),
                shutdown,
                startup,
                state,
                sequence: SequenceState {
                    offline: startup.planned(),
                    brake_from: None,
                },
                time: 0.0,
                azimuth: 0.0,
            },
            rated_wind_speed: rated_wind,
            rated_tip_speed_ratio: rated_speed * radius / rated_wind,
            radius,
            rated_rotor_torque: rated_torque,
            sigma,
        })
    }
}

/// The rotor's enumerated String parameters, read.
struct Choices {
    /// IEC 61400-1 reference turbulence intensity of the turbulence class.
    i_ref: f64,
    turbulence: Option<TurbulenceModel>,
    /// The blades sample a full field (wind_sampling = blades).
    blades: bool,
    /// Turbulence averaged over the swept disc (the rotor-effective wind), not at the hub point.
    rotor_average: bool,
    /// What σ holds over when the series has a period of its own (turbulence_scaling).
    period_variance: Variance,
    /// Pitch to hold rated power (else rated generator speed).
    power_control: bool,
    /// A played-back series is in per-unit of a rated rotor torque (else N·m).
    per_unit: bool,
    cubic: bool,
    /// The drivetrain a played-back series was recorded on, and its preset letter.
    source: Option<(Drivetrain, String)>,
}

#[derive(Clone, Serialize, Deserialize)]
pub struct RotorSlave {
    /// Shared, copy-on-write, with the states taken while they are unchanged: taking or restoring a
    /// state compares a pointer instead of every parameter.
    pub params: std::sync::Arc<Params>,
    pub inputs: Inputs,
    resources: Option<PathBuf>,
    /// Rebuilt from the parameters when missing (after deserialising a state): a serialised state
    /// carries only `motion`, what changes.
    #[serde(skip)]
    built: Option<Built>,
    start_time: f64,
    /// The model's pitch state, clock and blade azimuth after the last step (None: at the start time).
    motion: Option<(PitchState, SequenceState, f64, f64)>,
    /// Outputs at (time, rotor speed, disc motion) last computed: a master reads several per step.
    #[serde(skip)]
    cache: Option<(f64, f64, DiscMotion, RotorOutputs)>,
}

impl RotorSlave {
    /// The outputs at the current time, rotor speed and disc motion: the cached ones if they are for
    /// those, else computed and cached.
    fn current_outputs(&mut self) -> SlaveResult<RotorOutputs> {
        let omega = self.inputs.rotor_speed.value();
        let disc = DiscMotion {
            tilt_rate: self.inputs.tilt_rate.value(),
            yaw_rate: self.inputs.yaw_rate.value(),
        };
        let cache = self.cache;
        let b = self.ensure()?;
        let out = match cache {
            Some((t, w, d, out)) if t == b.model.time && w == omega && d == disc => out,
            _ => b.model.outputs(omega, disc),
        };
        self.cache = Some((b.model.time, omega, disc, out));
        Ok(out)
    }

    /// A parameter change rebuilds the model; an input change only drops the cached outputs.
    fn changed(&mut self, what: Changed) {
        if what == Changed::Parameter {
            self.built = None;
            self.motion = None;
        }
        self.cache = None;
    }

    fn ensure(&mut self) -> SlaveResult<&mut Built> {
        if self.built.is_none() {
            let mut b = self.params.build(self.resources.as_deref())?;
            match self.motion {
                Some((state, sequence, time, azimuth)) => {
                    (b.model.state, b.model.sequence, b.model.time, b.model.azimuth) = (state, sequence, time, azimuth)
                }
                None => b.model.time = self.start_time,
            }
            self.built = Some(b);
        }
        Ok(self.built.as_mut().expect("just built"))
    }
}

impl Slave for RotorSlave {
    crate::slave_interface_from_xml!();

    /// A state shares the model (its blade, polars and series behind an `Arc`) and reuses an
    /// earlier snapshot's strings.
    fn snapshot_into(&self, into: &mut Self) {
        if !std::sync::Arc::ptr_eq(&into.params, &self.params) {
            into.params = std::sync::Arc::clone(&self.params);
        }
        into.inputs.clone_from(&self.inputs);
        into.resources.clone_from(&self.resources);
        into.built.clone_from(&self.built);
        into.start_time = self.start_time;
        into.motion = self.motion;
        into.cache = self.cache;
    }

    fn restore(&mut self, snap: &Self) {
        snap.snapshot_into(self);
    }

    fn instantiate(resources: Option<&Path>) -> Self {
        Self {
            params: std::sync::Arc::default(),
            inputs: Inputs::default(),
            resources: resources.map(Path::to_path_buf),
            built: None,
            start_time: 0.0,
            motion: None,
            cache: None,
        }
    }

    fn get_real(&mut self, r: u32) -> SlaveResult<f64> {
        let mut value = [0.0];
        self.get_reals(&[r], &mut value)?;
        Ok(value[0])
    }

    /// The rotor's outputs at the current inputs computed (or taken from the cache) once for all the
    /// values asked.
    fn get_reals(&mut self, vrs: &[u32], values: &mut [f64]) -> SlaveResult<()> {
        // the outputs once per array, and the model they came from, by reference for every value after
        let mut outputs = None;
        let omega = self.inputs.rotor_speed.value();
        for (&r, value) in vrs.iter().zip(values) {
            if let Some(v) = xml::get_real(&self.params, &self.inputs, r) {
                *value = v;
                continue;
            }
            if outputs.is_none() {
                outputs = Some(self.current_outputs()?);
            }
            let (Some(out), Some(b)) = (&outputs, &self.built) else {
                return Err(SlaveError::new("the model was not built"));
            };
            *value = match r {
                vr::RATED_WIND_SPEED => b.rated_wind_speed,
                vr::RATED_TIP_SPEED_RATIO => b.rated_tip_speed_ratio,
                vr::RADIUS_USED => b.radius,
                vr::RATED_ROTOR_TORQUE => b.rated_rotor_torque,
                vr::TURBULENCE_SIGMA => b.sigma,
                vr::ROTOR_TORQUE => out.torque,
                vr::PITCHING_MOMENT => out.pitching_moment,
                vr::BRAKE_COMMAND => b.model.brake_command(),
                vr::PITCH => out.pitch,
                vr::WIND_SPEED_HUB => out.wind_speed,
                vr::THRUST => out.thrust,
                vr::AERODYNAMIC_POWER => out.torque * omega,
                vr::TILT_MOMENT => out.tilt_moment,
                vr::YAW_MOMENT => out.yaw_moment,
                _ => return Err(xml::no_getter(VarType::Real, r)),
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
        if let Some(v) = xml::get_boolean(&self.params, &self.inputs, r) {
            return Ok(v);
        }
        match r {
            vr::GENERATOR_CONNECTED => {
                let b = self.ensure()?;
                Ok(b.model.generator_connected())
            }
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

    fn initialize(&mut self, start_time: f64, _log: &mut dyn Log) -> SlaveResult<()> {
        self.start_time = start_time;
        self.cache = None;
        // a model built in initialisation mode (a master reading the outputs before it exits) came from
        // the same parameters (setting one drops it) and has not moved: only its clock goes to the start
        // time. Building it again would synthesise its wind twice.
        match (self.built.as_mut(), self.motion) {
            (Some(b), None) => b.model.time = start_time,
            _ => self.built = None,
        }
        self.ensure().map(|_| ())
    }

    fn set_input_derivative(&mut self, r: u32, order: i32, value: f64) -> SlaveResult<()> {
        self.inputs.set_derivative(r, order, value)
    }

    fn do_step(&mut self, t: f64, h: f64, log: &mut dyn Log) -> SlaveResult<()> {
        let steps = (h / CONTROL_STEP).ceil();
        if steps > self.params.max_steps_per_call {
            return Err(crate::fmi2::fmu::error::err(format!(
                "the communication step of {h} s needs {steps:.0} pitch-control steps of {CONTROL_STEP} s, more than \
                 max_steps_per_call = {:.0}; take shorter communication steps or raise the limit",
                self.params.max_steps_per_call
            )));
        }
        let w = self.inputs.rotor_speed;
        let b = self.ensure()?;
        if let Some(end) = b.model.field_end()
            && t + h > end + 1e-9 * end.max(1.0)
        {
            // shown to the file's own precision: a .bts stores its time step as a 32-bit float
            return Err(crate::fmi2::fmu::error::err(format!(
                "wind_file = {:?} holds wind until t = {} s (not periodic): the step to t = {} s goes beyond it; \
                 use a longer or periodic file",
                self.params.wind_file.trim(),
                end as f32,
                (t + h) as f32
            )));
        }
        let sd = b.model.shutdown;
        let (before, after) = (t, t + h);
        if sd.time >= 0.0 {
            let crossed = |at: f64| before < at && at <= after;
            if crossed(sd.time) {
                log.event(&format!("shutdown at t = {} s", sd.time));
            }
            if crossed(sd.time + sd.pitch_delay) {
                log.event("pitching to feather");
            }
            if crossed(sd.time + sd.trip_delay) {
                log.event("generator tripped (generator_connected = false)");
            }
            if sd.brake_speed <= 0.0 && crossed(sd.time + sd.brake_delay) {
                log.event("HSS brake deploying");
            }
        }
        if b.model.startup.planned() && before < b.model.startup.time && b.model.startup.time <= after {
            log.event(&format!("start-up at t = {} s", b.model.startup.time));
        }
        let latched = b.model.sequence;
        // the controller sees the speed at the middle of the step (second order in h)
        b.model.advance(w.at(h / 2.0), h);
        if latched.offline && !b.model.sequence.offline {
            log.event(&format!("generator switched online at t ≈ {after} s"));
        }
        if latched.brake_from.is_none() && b.model.sequence.brake_from.is_some() {
            log.event(&format!(
                "rotor slowed to the brake speed: HSS brake deploying at t ≈ {after} s"
            ));
        }
        self.motion = Some((b.model.state, b.model.sequence, b.model.time, b.model.azimuth));
        self.inputs.advance(h);
        Ok(())
    }
}
