//! `windrive step-response`: the rated-torque step on a drivetrain, through its torsional FMU.
//!
//! The drivetrain turns at rated speed, unloaded; at `step_time` the rotor torque steps to rated and
//! the generator torque to rated/ratio, balanced, so the mean speed stays and the shafts twist into
//! their loaded deflection: the free–free torsional modes ring.

use crate::fmi2::import::{Fmu, Instance};
use crate::fmi2::slave::{Log, Slave};
use crate::models::torsional::vr;
use crate::slaves::torsional::TorsionalSlave;
use anyhow::{Context, anyhow};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct StepArgs {
    /// Drivetrain preset: A, B, C or D
    #[arg(long, default_value = "D")]
    pub preset: String,
    /// 2, 5 or full
    #[arg(long, default_value = "full")]
    pub fidelity: String,
    /// implicit or rk4
    #[arg(long, default_value = "implicit")]
    pub integrator: String,
    /// Simulated time, s
    #[arg(long, default_value_t = 5.0)]
    pub stop_time: f64,
    /// Communication step, s
    #[arg(long, default_value_t = 1e-3)]
    pub step: f64,
    /// When the torque steps, s
    #[arg(long, default_value_t = 0.5)]
    pub step_time: f64,
    /// CSV output (fmpy layout: time first, one column per variable)
    #[arg(long, default_value = "results/step-response.csv")]
    pub out: PathBuf,
    /// Also plot the HSS and LSS torque (.png or .svg)
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Use this .fmu instead of packing target/fmu/torsional.fmu
    #[arg(long)]
    pub fmu: Option<PathBuf>,
    /// Cycle through these communication step sizes (s) instead of --step, e.g. 0.5e-3,1e-3,2e-3
    #[arg(long, value_delimiter = ',')]
    pub step_pattern: Vec<f64>,
}

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

/// What one run of the scenario asks of the FMU.
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
}

/// Recorded rows: time followed by CHANNELS.
pub type Rows = Vec<[f64; 1 + CHANNELS.len()]>;

/// Opens the given FMU, or packs target/fmu/torsional.fmu from the workspace first.
pub fn torsional_fmu(path: Option<&Path>) -> anyhow::Result<Fmu> {
    let path = match path {
        Some(p) => p.to_path_buf(),
        None => {
            let root = crate::pack::workspace_root()?;
            crate::pack::pack(&root, "torsional")?
        }
    };
    Fmu::open(&path).with_context(|| format!("opening {}", path.display()))
}

fn rated(preset: &str) -> anyhow::Result<(f64, f64)> {
    let dt =
        crate::physics::drivetrain::Drivetrain::preset(preset).ok_or_else(|| anyhow!("unknown preset {preset:?}"))?;
    Ok((dt.rated_rotor_torque(), dt.rated_generator_torque()))
}

/// Runs the scenario through the FMI boundary. With `record` false only the HSS torque is read each
/// step (the benchmark's loop: set 3 inputs, step, get 1 output).
pub fn run_fmi(fmu: &Fmu, sc: &Scenario, record: bool) -> anyhow::Result<(Rows, f64)> {
    let (t_rotor, t_gen) = rated(&sc.preset)?;
    let mut inst: Instance = fmu.instantiate("torsional", false)?;
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
        let on = if t >= sc.step_time { 1.0 } else { 0.0 };
        inst.set_real(&inputs, &[on * t_rotor, on * t_gen, 0.0])?;
        inst.do_step(t, h).with_context(|| format!("at t = {t} s"))?;
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

struct Silent;
impl Log for Silent {
    fn warning(&mut self, _: &str) {}
    fn event(&mut self, _: &str) {}
}

/// The same scenario on the model directly, without FMI: returns the HSS torque series and wall time.
pub fn run_native(sc: &Scenario) -> anyhow::Result<(Vec<f64>, f64)> {
    let (t_rotor, t_gen) = rated(&sc.preset)?;
    let mut s = TorsionalSlave::instantiate(None);
    let e = |e: crate::fmi2::slave::SlaveError| anyhow!(e.0);
    s.set_string(vr::PRESET, &sc.preset, &mut Silent).map_err(e)?;
    s.set_string(vr::FIDELITY, &sc.fidelity, &mut Silent).map_err(e)?;
    s.set_string(vr::INTEGRATOR, &sc.integrator, &mut Silent).map_err(e)?;
    s.set_real(vr::MAX_INTERNAL_STEP, sc.max_internal_step, &mut Silent)
        .map_err(e)?;
    s.initialize(0.0, &mut Silent).map_err(e)?;
    let steps = sc.steps();
    let mut hss = Vec::with_capacity(steps.len() + 1);
    hss.push(s.get_real(vr::HSS_TORQUE).map_err(e)?);
    let started = std::time::Instant::now();
    for &(t, h) in &steps {
        let on = if t >= sc.step_time { 1.0 } else { 0.0 };
        s.set_real(vr::ROTOR_TORQUE, on * t_rotor, &mut Silent).map_err(e)?;
        s.set_real(vr::GENERATOR_TORQUE, on * t_gen, &mut Silent).map_err(e)?;
        s.do_step(t, h, &mut Silent).map_err(e)?;
        hss.push(s.get_real(vr::HSS_TORQUE).map_err(e)?);
    }
    Ok((hss, started.elapsed().as_secs_f64()))
}

/// Frequency of the largest spectral peak of `x` (sampled at dt) between f_lo and f_hi, by a direct
/// DFT scan on a fine grid after removing the mean.
pub fn dominant_frequency(x: &[f64], dt: f64, f_lo: f64, f_hi: f64) -> f64 {
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let duration = x.len() as f64 * dt;
    let df = 0.05 / duration;
    let mut best = (0.0, f_lo);
    let mut f = f_lo;
    while f <= f_hi {
        let w = std::f64::consts::TAU * f * dt;
        let (mut re, mut im) = (0.0, 0.0);
        for (i, v) in x.iter().enumerate() {
            let (s, c) = (w * i as f64).sin_cos();
            re += (v - mean) * c;
            im += (v - mean) * s;
        }
        let p = re * re + im * im;
        if p > best.0 {
            best = (p, f);
        }
        f += df;
    }
    best.1
}

pub fn write_csv(path: &Path, rows: &Rows) -> anyhow::Result<()> {
    use std::io::Write;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let mut w =
        std::io::BufWriter::new(std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?);
    writeln!(w, "time,{}", CHANNELS.map(|c| format!("torsional.{c}")).join(","))?;
    for r in rows {
        let cells: Vec<String> = r.iter().map(|v| format!("{v:.9e}")).collect();
        writeln!(w, "{}", cells.join(","))?;
    }
    Ok(())
}

pub fn run(args: &StepArgs) -> anyhow::Result<()> {
    let fmu = torsional_fmu(args.fmu.as_deref())?;
    let sc = Scenario {
        preset: args.preset.clone(),
        fidelity: args.fidelity.clone(),
        integrator: args.integrator.clone(),
        max_internal_step: args.step_pattern.iter().cloned().fold(args.step, f64::max),
        stop_time: args.stop_time,
        step: args.step,
        step_time: args.step_time,
        pattern: args.step_pattern.clone(),
    };
    let (rows, wall) = run_fmi(&fmu, &sc, true)?;
    write_csv(&args.out, &rows)?;
    let (t_rotor, t_gen) = rated(&args.preset)?;
    let col = |name: &str| CHANNELS.iter().position(|c| *c == name).unwrap() + 1;
    let after: Vec<&[f64; 9]> = rows.iter().filter(|r| r[0] > args.step_time).collect();
    let peak = |c: usize| after.iter().map(|r| r[c].abs()).fold(0.0, f64::max);
    let hss: Vec<f64> = after.iter().map(|r| r[col("hss_torque")]).collect();
    let f_dom = dominant_frequency(&hss, args.step, 0.2, 50.0);
    println!(
        "Rated-torque step on drivetrain {} ({} fidelity, {} integrator), {} s at {} s steps through the FMU: {:.0}x real time",
        args.preset,
        args.fidelity,
        args.integrator,
        args.stop_time,
        args.step,
        args.stop_time / wall
    );
    println!(
        "  rated LSS torque {:.4e} N·m, rated HSS torque {:.4e} N·m",
        t_rotor, t_gen
    );
    println!(
        "  peak LSS torque / rated: {:.3}   peak HSS torque / rated: {:.3}   (undamped step: 2.0)",
        peak(col("lss_torque")) / t_rotor,
        peak(col("hss_torque")) / t_gen
    );
    println!("  dominant HSS-torque frequency: {f_dom:.3} Hz");
    for boundary in ["disconnected", "connected", "locked"] {
        let (_, m) = super::modes::compute(&args.preset, &args.fidelity, boundary)?;
        let list: Vec<String> = m.frequencies_hz.iter().take(5).map(|f| format!("{f:.3}")).collect();
        println!("  modes, generator {boundary:<12}: {} Hz ...", list.join(", "));
    }
    println!("  CSV: {}", args.out.display());
    if let Some(plot) = &args.plot {
        let lss: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[col("lss_torque")] / t_rotor)).collect();
        let hss: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[col("hss_torque")] / t_gen)).collect();
        super::plot::lines(
            plot,
            &format!("Drivetrain {}: rated-torque step", args.preset),
            "time / s",
            "torque / rated",
            &[
                super::plot::Series {
                    label: "LSS".into(),
                    points: &lss,
                },
                super::plot::Series {
                    label: "HSS".into(),
                    points: &hss,
                },
            ],
            &[],
        )?;
        println!("  plot: {}", plot.display());
    }
    Ok(())
}
