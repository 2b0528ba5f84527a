//! The rotor as the drivetrain's input: aerodynamic torque from wind (mean + Kaimal turbulence),
//! a blade-element momentum rotor (or the analytic C_p) and a PI pitch controller, or a played-back
//! torque series; plus the shutdown sequence (pitch to feather, generator trip, HSS brake deployment).

use super::aero::{AIR_DENSITY, PitchController, PitchState, Rotor, power_coefficient};
use super::bem::BemRotor;
use super::blades::{BladeSampling, DiscMotion};
use super::drivetrain::Drivetrain;
use super::turbulence::TurbulenceSeries;
use serde::{Deserialize, Serialize};

/// A torque series read from a file, already in N·m (per-unit values scaled on loading).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TorqueSeries {
    pub time: Vec<f64>,
    pub torque: Vec<f64>,
    pub pitching_moment: Option<Vec<f64>>,
    pub cubic: bool,
}

impl TorqueSeries {
    /// Values at `t`: held at the first and last sample outside the series; inside it, linear or
    /// cubic (Catmull–Rom: through every sample, continuous slope) interpolation.
    pub fn at(&self, t: f64) -> (f64, f64) {
        let pm = |i: usize| self.pitching_moment.as_ref().map_or(0.0, |p| p[i]);
        let n = self.time.len();
        if t <= self.time[0] {
            return (self.torque[0], pm(0));
        }
        if t >= self.time[n - 1] {
            return (self.torque[n - 1], pm(n - 1));
        }
        let i = self.time.partition_point(|&x| x <= t) - 1;
        let (t0, t1) = (self.time[i], self.time[i + 1]);
        let w = (t - t0) / (t1 - t0);
        let interpolate = |y: &dyn Fn(usize) -> f64| -> f64 {
            if !self.cubic {
                return y(i) * (1.0 - w) + y(i + 1) * w;
            }
            // Catmull–Rom with end slopes from one-sided differences
            let slope = |k: usize| -> f64 {
                let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
                (y(b) - y(a)) / (self.time[b] - self.time[a]) * (t1 - t0)
            };
            let (p0, p1, m0, m1) = (y(i), y(i + 1), slope(i), slope(i + 1));
            let (w2, w3) = (w * w, w * w * w);
            (2.0 * w3 - 3.0 * w2 + 1.0) * p0 + (w3 - 2.0 * w2 + w) * m0 + (-2.0 * w3 + 3.0 * w2) * p1 + (w3 - w2) * m1
        };
        (interpolate(&|k| self.torque[k]), interpolate(&|k| pm(k)))
    }
}

/// Shutdown: from `time` on, pitch to feather at `feather_rate` (after `pitch_delay`: a grid loss
/// trips the generator at once and the controller only reacts once it has detected it); trip the
/// generator after `trip_delay`; deploy the HSS brake after `brake_delay`, its command ramping 0 → 1
/// over `brake_ramp_time` (as OpenFAST's HSS brake deployment time). A normal stop brakes only once
/// the rotor has slowed: with `brake_speed` > 0 the brake waits, after `brake_delay`, for the rotor
/// speed to fall to it (rad/s). Negative `time` = never.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Shutdown {
    pub time: f64,
    pub feather_rate: f64,
    pub pitch_delay: f64,
    pub trip_delay: f64,
    pub brake_delay: f64,
    pub brake_ramp_time: f64,
    pub brake_speed: f64,
}

impl Shutdown {
    pub fn active(&self, t: f64) -> bool {
        self.time >= 0.0 && t >= self.time
    }

    pub fn feathering(&self, t: f64) -> bool {
        self.time >= 0.0 && t >= self.time + self.pitch_delay
    }

    pub fn generator_connected(&self, t: f64) -> bool {
        !(self.time >= 0.0 && t >= self.time + self.trip_delay)
    }

    /// Brake command at `t` when the deployment began at `from` (None: not yet).
    fn ramp(&self, t: f64, from: Option<f64>) -> f64 {
        let Some(from) = from else { return 0.0 };
        let since = t - from;
        if since < 0.0 {
            0.0
        } else if self.brake_ramp_time <= 0.0 {
            1.0
        } else {
            (since / self.brake_ramp_time).min(1.0)
        }
    }

    /// The time-triggered brake command (`brake_speed` = 0).
    pub fn brake_command(&self, t: f64) -> f64 {
        if self.time < 0.0 {
            return 0.0;
        }
        self.ramp(t, Some(self.time + self.brake_delay))
    }
}

/// Start-up: until `time` the rotor idles at its initial pitch with the generator off-line; from then
/// the pitch controller runs, no faster than `pitch_rate` towards fine pitch, and the generator is
/// switched online once the rotor reaches `connect_speed` (rad/s), as the thesis's field start-up
/// (ch. 3.1: accelerated without grid connection to rated rotor speed, then switched online).
/// Negative `time` = never (the turbine starts in operation).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Startup {
    pub time: f64,
    pub pitch_rate: f64,
    pub connect_speed: f64,
}

impl Startup {
    pub const NONE: Startup = Startup {
        time: -1.0,
        pitch_rate: 0.0,
        connect_speed: 0.0,
    };

    pub fn planned(&self) -> bool {
        self.time >= 0.0
    }
}

/// What the event sequences have latched: the generator still off-line in a start-up, and when a
/// speed-triggered brake began to deploy.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct SequenceState {
    pub offline: bool,
    pub brake_from: Option<f64>,
}

/// Pitching (tilt) moment at the hub: rotor weight on the overhang plus the thrust's offset under
/// power-law shear V(z) = V_hub (z/z_hub)^α. With thrust per disc area ∝ V², the thrust acts at
/// e = ∫∫ V² (z − z_hub) dA / ∫∫ V² dA above the hub, so M = T·e + m_rotor·g·overhang.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TiltModel {
    /// e, m (computed once from radius, hub height and α).
    pub thrust_offset: f64,
    pub weight_moment: f64,
}

impl TiltModel {
    pub fn new(radius: f64, hub_height: f64, shear_exponent: f64, rotor_mass: f64, overhang: f64) -> Self {
        let (nr, npsi) = (40, 72);
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..nr {
            let r = (i as f64 + 0.5) / nr as f64 * radius;
            for j in 0..npsi {
                let psi = (j as f64 + 0.5) / npsi as f64 * std::f64::consts::TAU;
                let z = r * psi.sin();
                let v2 = ((hub_height + z).max(0.0) / hub_height).powf(2.0 * shear_exponent);
                num += v2 * z * r;
                den += v2 * r;
            }
        }
        Self {
            thrust_offset: num / den,
            weight_moment: rotor_mass * 9.81 * overhang,
        }
    }

    pub fn moment(&self, thrust: f64) -> f64 {
        thrust * self.thrust_offset + self.weight_moment
    }
}

/// The rotor's aerodynamics: a blade-element momentum rotor, or Heier's analytic C_p(λ, β).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Aerodynamics {
    Bem(BemRotor),
    Analytic(Rotor),
}

impl Aerodynamics {
    pub fn radius(&self) -> f64 {
        match self {
            Aerodynamics::Bem(b) => b.radius(),
            Aerodynamics::Analytic(r) => r.radius,
        }
    }

    /// Torque (N·m, positive driving) and thrust (N) at rotor speed `omega` (rad/s), wind (m/s) and
    /// pitch (rad).
    pub fn torque_thrust(&self, omega: f64, wind: f64, pitch: f64) -> (f64, f64) {
        match self {
            Aerodynamics::Bem(b) => b.torque_thrust(wind, omega, pitch),
            Aerodynamics::Analytic(r) => {
                let deg = pitch.to_degrees();
                (r.torque(omega, wind, deg), r.thrust(omega, wind, deg))
            }
        }
    }

    pub fn torque(&self, omega: f64, wind: f64, pitch: f64) -> f64 {
        match self {
            Aerodynamics::Bem(b) => b.torque_thrust(wind, omega, pitch).0,
            Aerodynamics::Analytic(r) => r.torque(omega, wind, pitch.to_degrees()),
        }
    }
}

/// What the pitch controller regulates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum PitchTarget {
    /// Generator-side speed (rad/s): variable-speed turbines.
    Speed(f64),
    /// Aerodynamic power (W), in per unit of it: fixed-speed turbines.
    Power(f64),
}

/// Where the torque comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Source {
    Aero {
        rotor: Aerodynamics,
        mean_wind: f64,
        turbulence: Option<TurbulenceSeries>,
        pitch: PitchController,
        target: PitchTarget,
        tilt: TiltModel,
        /// generator-side speed over rotor speed, for the pitch controller's error
        gear_ratio: f64,
        /// The blades sampling a full field (BEM only); None: the rotor-averaged series above. Boxed: its
        /// load table would make every `Source` (a playback too) that large.
        blades: Option<Box<BladeSampling>>,
    },
    Playback(TorqueSeries),
}

/// Outputs at one communication point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RotorOutputs {
    pub torque: f64,
    pub pitching_moment: f64,
    pub wind_speed: f64,
    pub thrust: f64,
    pub pitch: f64,
    /// Aerodynamic tilt moment at the hub (thrust above the hub positive), N·m.
    pub tilt_moment: f64,
    /// Aerodynamic yaw moment at the hub (right-handed about the vertical), N·m.
    pub yaw_moment: f64,
}

/// The model: what never changes once built (`source`: blade, polars, the synthesised turbulence or
/// the played-back series, hundreds of kB) is shared, so a copy of the model (an FMU state taken at
/// every macro step for rollback) costs a pointer, not the data.
#[derive(Debug, PartialEq)]
pub struct RotorModel {
    pub source: std::sync::Arc<Source>,
    pub shutdown: Shutdown,
    pub startup: Startup,
    pub state: PitchState,
    pub sequence: SequenceState,
    pub time: f64,
    /// Blade 1's azimuth, rad (0 = up), advanced with the rotor speed: where the blades read the field.
    pub azimuth: f64,
}

impl Clone for RotorModel {
    fn clone(&self) -> Self {
        Self {
            source: std::sync::Arc::clone(&self.source),
            shutdown: self.shutdown,
            startup: self.startup,
            state: self.state,
            sequence: self.sequence,
            time: self.time,
            azimuth: self.azimuth,
        }
    }

    /// Keeps the shared source when it is already the same one: a state updated at every macro step
    /// costs no reference counting.
    fn clone_from(&mut self, other: &Self) {
        if !std::sync::Arc::ptr_eq(&self.source, &other.source) {
            self.source = std::sync::Arc::clone(&other.source);
        }
        self.shutdown = other.shutdown;
        self.startup = other.startup;
        self.state = other.state;
        self.sequence = other.sequence;
        self.time = other.time;
        self.azimuth = other.azimuth;
    }
}

/// Pitch control runs at this rate at most, whatever the communication step.
pub const CONTROL_STEP: f64 = 0.01;

impl RotorModel {
    /// The hub-height wind at `t`: the rotor-averaged series, or the full field at the hub point.
    pub fn wind(&self, t: f64) -> f64 {
        match &*self.source {
            Source::Aero { blades: Some(b), .. } => b.field.velocity_at(t, 0.0, b.hub_height)[0],
            Source::Aero {
                mean_wind, turbulence, ..
            } => (mean_wind + turbulence.as_ref().map_or(0.0, |s| s.at(t))).max(0.0),
            Source::Playback(_) => 0.0,
        }
    }

    /// The last time a non-periodic full field holds (None: no field, or one that wraps round).
    pub fn field_end(&self) -> Option<f64> {
        self.sampled().and_then(|(b, _)| b.field.end_time())
    }

    /// The blades and their BEM when the rotor samples a full field.
    fn sampled(&self) -> Option<(&BladeSampling, &BemRotor)> {
        match &*self.source {
            Source::Aero {
                blades: Some(b),
                rotor: Aerodynamics::Bem(bem),
                ..
            } => Some((b, bem)),
            _ => None,
        }
    }

    /// Outputs at the model's time with the rotor turning at `rotor_speed` (rad/s) and its disc moving
    /// as `disc` (read by the sampling blades only: a rotor-averaged wind has no elements to move).
    pub fn outputs(&self, rotor_speed: f64, disc: DiscMotion) -> RotorOutputs {
        let t = self.time;
        let pitch = self.state.pitch;
        if let (Some((blades, bem)), Source::Aero { tilt, .. }) = (self.sampled(), &*self.source) {
            let l = blades.loads(bem, t, self.azimuth, rotor_speed, pitch, disc);
            return RotorOutputs {
                torque: l.torque,
                pitching_moment: l.tilt + tilt.weight_moment,
                wind_speed: l.hub_wind,
                thrust: l.thrust,
                pitch,
                tilt_moment: l.tilt,
                yaw_moment: l.yaw,
            };
        }
        match &*self.source {
            Source::Aero { rotor, tilt, .. } => {
                let v = self.wind(t);
                let (torque, thrust) = rotor.torque_thrust(rotor_speed, v, pitch);
                RotorOutputs {
                    torque,
                    pitching_moment: tilt.moment(thrust),
                    wind_speed: v,
                    thrust,
                    pitch,
                    tilt_moment: thrust * tilt.thrust_offset,
                    yaw_moment: 0.0,
                }
            }
            Source::Playback(series) => {
                let (torque, pitching_moment) = series.at(t);
                RotorOutputs {
                    torque,
                    pitching_moment,
                    ..RotorOutputs::default()
                }
            }
        }
    }

    /// Advances the pitch (controller, idling before a start-up, or feathering once the shutdown
    /// began), the sequences' latches and the clock.
    pub fn advance(&mut self, rotor_speed: f64, h: f64) {
        let n = (h / CONTROL_STEP).ceil().max(1.0) as usize;
        let dt = h / n as f64;
        for k in 0..n {
            let t = self.time + k as f64 * dt;
            self.latch(t, rotor_speed);
            let Source::Aero {
                rotor,
                pitch,
                target,
                gear_ratio,
                ..
            } = &*self.source
            else {
                continue;
            };
            if self.shutdown.feathering(t) {
                let max = pitch.max_pitch;
                self.state.pitch = (self.state.pitch + self.shutdown.feather_rate * dt).min(max);
            } else if self.startup.planned() && t < self.startup.time {
                // idling at the initial pitch: the controller waits for the start command
            } else {
                let e = match *target {
                    PitchTarget::Speed(setpoint) => rotor_speed * gear_ratio - setpoint,
                    PitchTarget::Power(rated) => {
                        let torque = match self.sampled() {
                            Some((blades, bem)) => {
                                let azimuth = self.azimuth + rotor_speed * (t - self.time);
                                // a fixed disc: in uniform wind the first-order parts of the tilt and yaw rates
                                // cancel in the torque over three or more blades
                                blades
                                    .loads(bem, t, azimuth, rotor_speed, self.state.pitch, DiscMotion::default())
                                    .torque
                            }
                            None => rotor.torque(rotor_speed, self.wind(t), self.state.pitch),
                        };
                        torque * rotor_speed / rated - 1.0
                    }
                };
                if self.sequence.offline {
                    let slow = PitchController {
                        max_rate: pitch.max_rate.min(self.startup.pitch_rate),
                        ..*pitch
                    };
                    slow.step(&mut self.state, e, dt);
                } else {
                    pitch.step(&mut self.state, e, dt);
                }
            }
        }
        self.time += h;
        self.azimuth = (self.azimuth + rotor_speed * h).rem_euclid(std::f64::consts::TAU);
    }

    /// The start-up's switch online and the normal stop's speed-triggered brake.
    fn latch(&mut self, t: f64, rotor_speed: f64) {
        let (startup, shutdown) = (self.startup, self.shutdown);
        if self.sequence.offline && t >= startup.time && rotor_speed >= startup.connect_speed {
            self.sequence.offline = false;
        }
        if shutdown.brake_speed > 0.0
            && self.sequence.brake_from.is_none()
            && shutdown.active(t)
            && t >= shutdown.time + shutdown.brake_delay
            && rotor_speed.abs() <= shutdown.brake_speed
        {
            self.sequence.brake_from = Some(t);
        }
    }

    /// HSS brake command 0..1 of the shutdown sequence now.
    pub fn brake_command(&self) -> f64 {
        if self.shutdown.brake_speed > 0.0 {
            self.shutdown.ramp(self.time, self.sequence.brake_from)
        } else {
            self.shutdown.brake_command(self.time)
        }
    }

    /// False while a start-up holds the generator off-line and once a shutdown tripped it.
    pub fn generator_connected(&self) -> bool {
        !self.sequence.offline && self.shutdown.generator_connected(self.time)
    }
}

/// Radius of drivetrain C's rotor, the only one the sources give (thesis Table 3.1: 80 m).
const RADIUS_C: f64 = 40.0;

/// Tip-speed ratio of C's rotor at rated power and speed under the analytic C_p: the design rule
/// for the presets whose rotor the sources do not give.
fn design_tip_speed_ratio() -> f64 {
    let c = Drivetrain::preset("C").expect("preset C");
    let rotor = Rotor {
        radius: RADIUS_C,
        lambda_min: 0.5,
    };
    let v = rated_wind_speed(&Aerodynamics::Analytic(rotor), c.rated_power, c.rated_rotor_speed)
        .expect("C reaches rated power");
    c.rated_rotor_speed * RADIUS_C / v
}

/// Preset rotor (radius, hub height), m. C: the thesis's 80 m rotor; P: the paper's 70 m rotor. A, B, D: the radius at which the
/// analytic C_p gives rated power at rated speed at C's rated tip-speed ratio (6.69). D's real NM48
/// rotor is 48.2 m but stall-regulated, which this C_p does not describe. Hub heights are estimates.
pub fn preset_rotor(d: &Drivetrain, name: &str) -> (f64, f64) {
    let hub = match name.trim().to_ascii_uppercase().as_str() {
        "A" | "B" => 90.0,
        "C" => 80.0,
        _ => 55.0,
    };
    if name.trim().eq_ignore_ascii_case("C") {
        return (RADIUS_C, hub);
    }
    // the paper's turbine: 70 m rotor, 80 m hub (paper Table 1)
    if name.trim().eq_ignore_ascii_case("P") {
        return (35.0, 80.0);
    }
    // P = ½ρπR²V³C_p with V = ωR/λ  ⇒  R⁵ = 2P / (ρπ C_p (ω/λ)³)
    let lambda = design_tip_speed_ratio();
    let cp = power_coefficient(lambda, 0.0);
    let k = AIR_DENSITY * std::f64::consts::PI * cp * (d.rated_rotor_speed / lambda).powi(3);
    ((2.0 * d.rated_power / k).powf(0.2), hub)
}

/// Wind speed at which the rotor gives rated power at rated rotor speed and zero pitch: the lowest
/// root of P(V) = P_rated (P rises with V until λ falls past C_p's useful range). For the BEM rotor
/// this is how a scaled reference blade is fitted to a preset's rated point: its geometry is fixed
/// by the radius, its fine pitch is the reference's 0°, and the rated wind speed is what is chosen.
pub fn rated_wind_speed(rotor: &Aerodynamics, rated_power: f64, rated_speed: f64) -> Result<f64, String> {
    let power = |v: f64| rotor.torque(rated_speed, v, 0.0) * rated_speed;
    let mut v = 2.0;
    while power(v) < rated_power {
        v += 0.25;
        if v > 40.0 {
            return Err(format!(
                "a rotor of radius {} m at {rated_speed:.3} rad/s never reaches rated power {rated_power} W: give wind_speed or a larger radius",
                rotor.radius()
            ));
        }
    }
    let (mut lo, mut hi) = (v - 0.25, v);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if power(mid) < rated_power { lo = mid } else { hi = mid }
    }
    Ok(0.5 * (lo + hi))
}

/// Pitch (rad) at which the rotor gives rated power at rated speed in steady wind `wind`: 0 below
/// rated wind, otherwise the root of P(β) = P_rated on [0, max_pitch] (P falls as the blade pitches
/// towards feather). A scene that starts above rated wind starts here instead of at fine pitch,
/// where the controller would first have to wind up through seconds of overpower.
pub fn trim_pitch(rotor: &Aerodynamics, wind: f64, rated_power: f64, rated_speed: f64, max_pitch: f64) -> f64 {
    let power = |pitch: f64| rotor.torque(rated_speed, wind, pitch) * rated_speed;
    // at the rated wind itself P(0) is rated to rounding; near λ_opt P first rises with pitch, so
    // without this margin the search would find the second root on the falling side
    if power(0.0) <= rated_power * (1.0 + 1e-9) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, max_pitch);
    if power(hi) > rated_power {
        return max_pitch;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if power(mid) > rated_power { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests;
