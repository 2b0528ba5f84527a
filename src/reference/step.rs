//! The rated-torque step on a drivetrain: it turns at rated speed, unloaded; at `step_time` the rotor
//! torque steps to rated and the generator torque to rated/ratio, balanced, so the mean speed stays
//! and the shafts twist into their loaded deflection: the free–free torsional modes ring.
//!
//! Run on the model directly ([`run_native`]) it is the reference the FMU is timed and checked
//! against; [`run_fmi`] runs the same scenario through the FMI boundary.

use super::ReferenceError;
use crate::fmi2::fmu::slave::{NoLog, Slave};
use crate::models::torsional::vr;
use crate::physics::drivetrain::Drivetrain;
use crate::slaves::torsional::TorsionalSlave;

/// Channels recorded by the step response, in CSV order.
pub const CHANNELS: [&str; 8] = [
    "rotor_speed",
    "generator_speed",
    "lss_torque",
    "is1_torque",
    "hss_torque",
    "mesh_force_sun_planet_1",
    "mesh_force_gear_pinion_2",
    "stored_energy",
];

/// Column of `name` in a row of [`Rows`] (time is column 0).
pub fn column(name: &str) -> Option<usize> {
    CHANNELS.iter().position(|c| *c == name).map(|i| i + 1)
}

/// Recorded rows: time followed by CHANNELS.
pub type Rows = Vec<[f64; 1 + CHANNELS.len()]>;

/// What one run of the scenario asks of the model.
#[derive(Debug, Clone)]
pub struct Scenario {
    pub preset: String,
    pub fidelity: String,
    pub integrator: String,
    pub max_internal_step: f64,
    pub stop_time: f64,
    pub step: f64,
    pub step_time: f64,
    /// Step sizes to cycle through; empty = constant `step`.
    pub pattern: Vec<f64>,
}

impl Scenario {
    /// The communication steps (t, h) up to stop_time: constant `step`, or `pattern` cycled, the
    /// last one shortened to end exactly at stop_time; times accumulate as a master's would.
    pub fn steps(&self) -> Vec<(f64, f64)> {
        if self.pattern.is_empty() {
            let n = (self.stop_time / self.step).round() as usize;
            return (0..n).map(|i| (i as f64 * self.step, self.step)).collect();
        }
        let mut out = Vec::new();
        let mut t = 0.0;
        while t < self.stop_time - 1e-12 {
            let h = self.pattern[out.len() % self.pattern.len()].min(self.stop_time - t);
            out.push((t, h));
            t += h;
        }
        out
    }

    /// Rated rotor and generator torque of the preset, N·m: the step's size.
    pub fn rated_torques(&self) -> Result<(f64, f64), ReferenceError> {
        let dt = Drivetrain::preset(&self.preset).ok_or_else(|| ReferenceError::UnknownPreset(self.preset.clone()))?;
        Ok((dt.rated_rotor_torque(), dt.rated_generator_torque()))
    }

    /// Rotor and generator torque inputs of the step starting at `t`.
    fn inputs(&self, t: f64, rated: (f64, f64)) -> (f64, f64) {
        let on = if t >= self.step_time { 1.0 } else { 0.0 };
        (on * rated.0, on * rated.1)
    }
}

/// Runs the scenario through the FMI boundary of a torsional FMU. With `record` false only the HSS
/// torque is read each step (the benchmark's loop: set 3 inputs, step, get 1 output). Returns the
/// rows and the wall time of the stepping, s.
#[cfg(feature = "cli")]
pub fn run_fmi(
    fmu: &crate::fmi2::host::import::Fmu,
    sc: &Scenario,
    record: bool,
) -> Result<(Rows, f64), ReferenceError> {
    let rated = sc.rated_torques()?;
    let mut inst = fmu.instantiate("torsional", false)?;
    inst.setup_experiment(0.0, Some(sc.stop_time))?;
    inst.set_string(
        &[vr::PRESET, vr::FIDELITY, vr::INTEGRATOR],
        &[&sc.preset, &sc.fidelity, &sc.integrator],
    )?;
    inst.set_real(&[vr::MAX_INTERNAL_STEP], &[sc.max_internal_step])?;
    inst.enter_initialization_mode()?;
    inst.exit_initialization_mode()?;
    let vrs: Vec<u32> = CHANNELS.iter().map(|c| fmu.vr(c)).collect::<Result<_, _>>()?;
    let inputs = [vr::ROTOR_TORQUE, vr::GENERATOR_TORQUE, vr::BRAKE_COMMAND];
    let steps = sc.steps();
    let mut rows = Rows::with_capacity(if record { steps.len() + 1 } else { 0 });
    let mut row = [0.0; 1 + CHANNELS.len()];
    let mut hss = [0.0];
    if record {
        inst.get_real(&vrs, &mut row[1..])?;
        rows.push(row);
    }
    let started = std::time::Instant::now();
    for &(t, h) in &steps {
        let (rotor, generator) = sc.inputs(t, rated);
        inst.set_real(&inputs, &[rotor, generator, 0.0])?;
        inst.do_step(t, h)
            .map_err(|source| ReferenceError::Step { time: t, source })?;
        if record {
            row[0] = t + h;
            inst.get_real(&vrs, &mut row[1..])?;
            rows.push(row);
        } else {
            inst.get_real(&[vr::HSS_TORQUE], &mut hss)?;
        }
    }
    let wall = started.elapsed().as_secs_f64();
    inst.terminate()?;
    Ok((rows, wall))
}

/// The same scenario on the model directly, without FMI: the HSS torque at every communication point
/// (the start included) and the wall time of the stepping, s.
pub fn run_native(sc: &Scenario) -> Result<(Vec<f64>, f64), ReferenceError> {
    let rated = sc.rated_torques()?;
    let mut s = TorsionalSlave::instantiate(None);
    s.set_string(vr::PRESET, &sc.preset, &mut NoLog)?;
    s.set_string(vr::FIDELITY, &sc.fidelity, &mut NoLog)?;
    s.set_string(vr::INTEGRATOR, &sc.integrator, &mut NoLog)?;
    s.set_real(vr::MAX_INTERNAL_STEP, sc.max_internal_step, &mut NoLog)?;
    s.initialize(0.0, &mut NoLog)?;
    let steps = sc.steps();
    let mut hss = Vec::with_capacity(steps.len() + 1);
    hss.push(s.get_real(vr::HSS_TORQUE)?);
    let started = std::time::Instant::now();
    for &(t, h) in &steps {
        let (rotor, generator) = sc.inputs(t, rated);
        s.set_real(vr::ROTOR_TORQUE, rotor, &mut NoLog)?;
        s.set_real(vr::GENERATOR_TORQUE, generator, &mut NoLog)?;
        s.do_step(t, h, &mut NoLog)?;
        hss.push(s.get_real(vr::HSS_TORQUE)?);
    }
    Ok((hss, started.elapsed().as_secs_f64()))
}

/// The RK4 stability limit of the default torsional model (drivetrain D, full fidelity), s: the
/// explicit baselines are set as fractions of it.
pub fn rk4_step_limit() -> Result<f64, ReferenceError> {
    let mut s = TorsionalSlave::instantiate(None);
    Ok(s.built()?.rk4_step_limit)
}

/// What a step response shows: the rated torques, N·m, the peak LSS and HSS torque after the step over
/// them, and the HSS torque's dominant frequency after the step, Hz (NaN if it has none).
#[derive(Debug, Clone, Copy)]
pub struct Response {
    pub rated_lss_nm: f64,
    pub rated_hss_nm: f64,
    pub peak_lss_ratio: f64,
    pub peak_hss_ratio: f64,
    pub dominant_hz: f64,
}

/// The response of `sc` recorded in `rows`.
pub fn response(sc: &Scenario, rows: &Rows) -> Result<Response, ReferenceError> {
    let (t_rotor, t_gen) = sc.rated_torques()?;
    let col = |name: &str| column(name).expect("a recorded channel");
    let after: Vec<&[f64; 1 + CHANNELS.len()]> = rows.iter().filter(|r| r[0] > sc.step_time).collect();
    let peak = |c: usize| after.iter().map(|r| r[c].abs()).fold(0.0, f64::max);
    let (t, hss): (Vec<f64>, Vec<f64>) = rows.iter().map(|r| (r[0], r[col("hss_torque")])).unzip();
    // the ringing after the step; 0.2 Hz keeps the spectrum's lowest bins (the step itself) out
    let dominant_hz =
        crate::analysis::signal::spectrum::dominant_in_window(&t, &hss, sc.step_time + 1e-12, f64::INFINITY, 0.2)
            .map_or(f64::NAN, |d| d.0);
    Ok(Response {
        rated_lss_nm: t_rotor,
        rated_hss_nm: t_gen,
        peak_lss_ratio: peak(col("lss_torque")) / t_rotor,
        peak_hss_ratio: peak(col("hss_torque")) / t_gen,
        dominant_hz,
    })
}

/// The rows as a CSV in fmpy's layout, columns named `torsional.<channel>`.
#[cfg(feature = "cli")]
pub fn write_csv(path: &std::path::Path, rows: &Rows) -> std::io::Result<()> {
    let names = CHANNELS.map(|c| format!("torsional.{c}"));
    let mut w = crate::cosim::recorder::CsvWriter::create(path, names.iter().map(String::as_str))?;
    for r in rows {
        w.row(r[0], r[1..].iter().copied())?;
    }
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scenario(pattern: Vec<f64>) -> Scenario {
        Scenario {
            preset: "D".into(),
            fidelity: "2".into(),
            integrator: "implicit".into(),
            max_internal_step: 1e-3,
            stop_time: 0.01,
            step: 1e-3,
            step_time: 0.0,
            pattern,
        }
    }

    /// A step pattern tiles the run and ends exactly at the stop time; a constant step has n steps.
    #[test]
    fn steps_end_at_the_stop_time() {
        assert_eq!(scenario(Vec::new()).steps().len(), 10);
        let steps = scenario(vec![3e-3, 4e-3]).steps();
        let hs: Vec<f64> = steps.iter().map(|s| s.1).collect();
        assert_eq!(hs.len(), 3);
        assert!((hs.iter().sum::<f64>() - 0.01).abs() < 1e-15, "{hs:?}");
        let mut bad = scenario(Vec::new());
        bad.preset = "Q".into();
        assert!(matches!(run_native(&bad), Err(ReferenceError::UnknownPreset(p)) if p == "Q"));
    }
}
