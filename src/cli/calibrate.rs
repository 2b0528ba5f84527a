//! `windrive calibrate`: fits the inputs of drivetrain C's scenes that no source gives (turbulence
//! intensity, brake torque, brake ramp, pitch rate towards feather, trip delay) to the statistics the
//! thesis measured on the field turbine ([`crate::studies::calibration`]), by Nelder–Mead over both
//! scenes run through the master; prints target, achieved and misfit per statistic, writes the table
//! as Markdown, and with `--apply` writes the fitted values into the scenes' parameter files.

use crate::cosim::Scene;
use crate::physics::drivetrain::Drivetrain;
use crate::studies::calibration::{self, Context, Runs};
use crate::studies::nelder_mead;
use anyhow::{Context as _, bail};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct CalibrateArgs {
    /// Most scene-pair evaluations of the optimiser (each runs 20 s normal operation and 30 s shutdown,
    /// about 1 s); the documented fit converged after 189
    #[arg(long, default_value_t = 250)]
    pub evaluations: usize,
    /// Evaluate the scenes' current values only, no fit
    #[arg(long)]
    pub no_fit: bool,
    /// Write the fitted values into scenes/c-normal and scenes/c-shutdown (rotor.ssv, torsional.ssv)
    #[arg(long)]
    pub apply: bool,
    /// Markdown table of target, achieved and misfit per statistic
    #[arg(long, default_value = "results/calibration-c.md")]
    pub out: PathBuf,
}

/// A free input: where it goes, its bounds, whether it is searched on a log scale.
struct Free {
    name: &'static str,
    file: &'static str,
    variable: &'static str,
    unit: &'static str,
    low: f64,
    high: f64,
    log: bool,
}

/// The brake torque is searched as a multiple of the rated generator torque and written in N·m.
const FREE: [Free; 5] = [
    Free {
        name: "turbulence intensity",
        file: "rotor.ssv",
        variable: "turbulence_intensity",
        unit: "",
        low: 0.005,
        high: 0.3,
        log: true,
    },
    Free {
        name: "brake torque / rated generator torque",
        file: "torsional.ssv",
        variable: "brake_torque_max",
        unit: "",
        low: 0.5,
        high: 4.0,
        log: true,
    },
    Free {
        name: "brake ramp time",
        file: "rotor.ssv",
        variable: "brake_ramp_time",
        unit: "s",
        low: 0.05,
        high: 3.0,
        log: true,
    },
    Free {
        name: "pitch rate towards feather",
        file: "rotor.ssv",
        variable: "feather_rate",
        unit: "rad/s",
        low: 0.017,
        high: 0.26,
        log: true,
    },
    Free {
        name: "trip delay",
        file: "rotor.ssv",
        variable: "trip_delay",
        unit: "s",
        low: 0.0,
        high: 2.0,
        log: false,
    },
];

impl Free {
    fn value(&self, u: f64) -> f64 {
        if self.log {
            self.low * (self.high / self.low).powf(u)
        } else {
            self.low + (self.high - self.low) * u
        }
    }

    fn unit_of(&self, v: f64) -> f64 {
        let u = if self.log {
            (v / self.low).ln() / (self.high / self.low).ln()
        } else {
            (v - self.low) / (self.high - self.low)
        };
        u.clamp(0.0, 1.0)
    }
}

/// The scenes' values of the free inputs (scene file, else the FMU default).
fn current_values(normal: &Scene, shutdown: &Scene, rated_generator: f64) -> Vec<f64> {
    let lookup =
        |scene: &Scene, file: &str, variable: &str| scene.real_parameter(file.trim_end_matches(".ssv"), variable);
    // the FMUs' defaults where a scene sets nothing: NTM class A at 16 m/s is 0.16·(0.75·16 + 5.6)/16
    let defaults = [0.176, 1.5, 0.6, 0.1396263, 0.2];
    FREE.iter()
        .zip(defaults)
        .map(|(f, default)| {
            let scene = if f.variable == "turbulence_intensity" {
                normal
            } else {
                shutdown
            };
            match lookup(scene, f.file, f.variable) {
                Some(v) if f.variable == "brake_torque_max" && v > 0.0 => v / rated_generator,
                Some(v) if v > 0.0 || !f.log => v,
                _ => default,
            }
        })
        .collect()
}

fn overrides(values: &[f64], rated_generator: f64) -> Vec<(String, String, String)> {
    FREE.iter()
        .zip(values)
        .map(|(f, v)| {
            let value = if f.variable == "brake_torque_max" {
                v * rated_generator
            } else {
                *v
            };
            (
                f.file.trim_end_matches(".ssv").to_string(),
                f.variable.to_string(),
                format!("{value}"),
            )
        })
        .collect()
}

const CHANNELS: [&str; 3] = [
    "torsional.lss_torque",
    "torsional.hss_torque",
    "torsional.mesh_force_sun_planet_1",
];

/// Runs a scene with Gauss–Seidel at 1 ms and returns time and the channels, in memory.
pub(crate) fn run_channels(
    scene: &Scene,
    overrides: &[(String, String, String)],
    channels: &[&str],
) -> anyhow::Result<Vec<Vec<f64>>> {
    crate::cosim::master::run_columns(scene, overrides, channels, None).map_err(|e| anyhow::anyhow!(e))
}

fn run_scene(scene: &Scene, overrides: &[(String, String, String)]) -> anyhow::Result<[Vec<f64>; 4]> {
    let c = run_channels(scene, overrides, &CHANNELS)?;
    let mut it = c.into_iter();
    let mut next = || it.next().unwrap_or_default();
    Ok([next(), next(), next(), next()])
}

struct Evaluation {
    values: Vec<f64>,
    statistics: Vec<(f64, f64)>,
    objective: f64,
}

fn evaluate(normal: &Scene, shutdown: &Scene, dt: &Drivetrain, values: &[f64]) -> anyhow::Result<Evaluation> {
    let rated_generator = dt.rated_generator_torque();
    let o = overrides(values, rated_generator);
    let [nt, nl, nh, ns] = run_scene(normal, &o)?;
    let [st, sl, sh, ss] = run_scene(shutdown, &o)?;
    let number = |name: &str, default: f64| shutdown.real_parameter("rotor", name).unwrap_or(default);
    let shutdown_s = number("shutdown_time", 5.0);
    let brake_delay = number("brake_delay", 0.5);
    let context = Context {
        rated_lss: dt.rated_rotor_torque(),
        brake_applied_s: shutdown_s
            + brake_delay
            + FREE
                .iter()
                .zip(values)
                .find(|(f, _)| f.variable == "brake_ramp_time")
                .map_or(0.6, |(_, v)| *v),
        shutdown_s,
    };
    let runs = Runs {
        normal_time: nt,
        normal_lss: nl,
        normal_hss: nh,
        normal_sun_planet: ns,
        shutdown_time: st,
        shutdown_lss: sl,
        shutdown_hss: sh,
        shutdown_sun_planet: ss,
    };
    let statistics = calibration::evaluate(&runs, &context);
    Ok(Evaluation {
        values: values.to_vec(),
        objective: calibration::objective(&statistics),
        statistics,
    })
}

fn table(e: &Evaluation, start: &Evaluation, evaluations: usize) -> String {
    let mut s = String::from(
        "# Drivetrain C's scene inputs fitted to the thesis's measurements\n\n\
         Written by `windrive calibrate` (the command and its reading: docs/DRIVETRAINS.md, \"Calibration\").\n\n",
    );
    let _ = writeln!(
        s,
        "Drivetrain C's scenes (scenes/c-normal, scenes/c-shutdown) against the thesis's measured statistics;\n\
         misfit = ln(achieved / target), 0 inside a stated bound. Objective (sum of squared misfits): {:.4} \
         ({evaluations} evaluations; {:.4} at the start).\n",
        e.objective, start.objective
    );
    let _ = writeln!(s, "| statistic | thesis | start | achieved | misfit |");
    let _ = writeln!(s, "|---|---|---|---|---|");
    for (stat, ((a, m), (a0, _))) in calibration::statistics()
        .iter()
        .zip(e.statistics.iter().zip(&start.statistics))
    {
        let shown = |x: f64| {
            if stat.unit.is_empty() {
                format!("{x:.3}")
            } else {
                format!("{:.1} k{}", x / 1e3, stat.unit)
            }
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:+.3} |",
            stat.name,
            stat.source,
            shown(*a0),
            shown(*a),
            m
        );
    }
    let _ = writeln!(s, "\n| input | start | fitted | search range |");
    let _ = writeln!(s, "|---|---|---|---|");
    for (f, (v, v0)) in FREE.iter().zip(e.values.iter().zip(&start.values)) {
        let _ = writeln!(
            s,
            "| {} (`{}`) | {v0:.4} {} | {v:.4} {} | {}–{} |",
            f.name, f.variable, f.unit, f.unit, f.low, f.high
        );
    }
    s
}

/// Sets `variable` in the parameter file, inserting it when absent.
fn write_parameter(path: &Path, variable: &str, value: f64) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(path).with_context(|| path.display().to_string())?;
    let line = format!("    <ssv:Parameter name=\"{variable}\"><ssv:Real value=\"{value}\"/></ssv:Parameter>");
    let key = format!("<ssv:Parameter name=\"{variable}\">");
    let out = if let Some(start) = text.find(&key) {
        let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[start..].find('\n').map_or(text.len(), |i| start + i);
        format!("{}{}{}", &text[..line_start], line, &text[line_end..])
    } else {
        let at = text
            .find("  </ssv:Parameters>")
            .with_context(|| format!("{}: no </ssv:Parameters>", path.display()))?;
        format!("{}{}\n{}", &text[..at], line, &text[at..])
    };
    std::fs::write(path, out).with_context(|| path.display().to_string())
}

/// The statistics of [`calibration::statistics`] (achieved, misfit) of C's scenes as they are.
pub(crate) fn current_statistics() -> anyhow::Result<Vec<(f64, f64)>> {
    let root = crate::pack::workspace_root()?;
    let normal = Scene::open(&root.join("scenes/c-normal"))?;
    let shutdown = Scene::open(&root.join("scenes/c-shutdown"))?;
    super::run::provide_own_fmus(&normal, false)?;
    super::run::provide_own_fmus(&shutdown, false)?;
    let dt = Drivetrain::preset("C").expect("preset C");
    let values = current_values(&normal, &shutdown, dt.rated_generator_torque());
    Ok(evaluate(&normal, &shutdown, &dt, &values)?.statistics)
}

pub fn run(args: &CalibrateArgs) -> anyhow::Result<()> {
    if !args.no_fit && args.evaluations < FREE.len() + 2 {
        bail!(
            "--evaluations {}: the simplex needs at least {}",
            args.evaluations,
            FREE.len() + 2
        );
    }
    let root = crate::pack::workspace_root()?;
    let (normal_dir, shutdown_dir) = (root.join("scenes/c-normal"), root.join("scenes/c-shutdown"));
    let normal = Scene::open(&normal_dir)?;
    let shutdown = Scene::open(&shutdown_dir)?;
    super::run::provide_own_fmus(&normal, false)?;
    super::run::provide_own_fmus(&shutdown, false)?;
    let dt = Drivetrain::preset("C").expect("preset C");
    let start_values = current_values(&normal, &shutdown, dt.rated_generator_torque());
    println!(
        "drivetrain C: fitting {} inputs to {} measured statistics",
        FREE.len(),
        calibration::statistics().len()
    );
    let started = std::time::Instant::now();
    let start = evaluate(&normal, &shutdown, &dt, &start_values)?;
    println!(
        "  start: objective {:.4} ({:.1} s a scene pair)",
        start.objective,
        started.elapsed().as_secs_f64()
    );
    let (best, evaluations) = if args.no_fit {
        (
            Evaluation {
                values: start.values.clone(),
                statistics: start.statistics.clone(),
                objective: start.objective,
            },
            1,
        )
    } else {
        let mut failure: Option<anyhow::Error> = None;
        let mut count = 0;
        let mut best_so_far = f64::INFINITY;
        let u0: Vec<f64> = FREE.iter().zip(&start_values).map(|(f, v)| f.unit_of(*v)).collect();
        let minimum = nelder_mead::minimise(
            |u| {
                count += 1;
                let values: Vec<f64> = FREE.iter().zip(u).map(|(f, x)| f.value(*x)).collect();
                match evaluate(&normal, &shutdown, &dt, &values) {
                    Ok(e) => {
                        best_so_far = best_so_far.min(e.objective);
                        eprint!(
                            "\r  evaluation {count:>4}/{}: objective {:.4}, best {best_so_far:.4}   ",
                            args.evaluations, e.objective
                        );
                        e.objective
                    }
                    Err(e) => {
                        failure.get_or_insert(e);
                        f64::INFINITY
                    }
                }
            },
            &u0,
            0.15,
            args.evaluations,
            1e-4,
        );
        eprintln!();
        if let Some(e) = failure.filter(|_| !minimum.value.is_finite()) {
            return Err(e.context("every evaluation failed"));
        }
        let values: Vec<f64> = FREE.iter().zip(&minimum.x).map(|(f, x)| f.value(*x)).collect();
        (evaluate(&normal, &shutdown, &dt, &values)?, minimum.evaluations)
    };
    let best = if args.apply {
        for dir in [&normal_dir, &shutdown_dir] {
            for (f, v) in FREE.iter().zip(&best.values) {
                let value = if f.variable == "brake_torque_max" {
                    v * dt.rated_generator_torque()
                } else {
                    *v
                };
                write_parameter(&dir.join(f.file), f.variable, value)?;
            }
        }
        println!(
            "fitted values written to {} and {}",
            normal_dir.display(),
            shutdown_dir.display()
        );
        // the table shows what the scenes now give, read back from their files
        let (normal, shutdown) = (Scene::open(&normal_dir)?, Scene::open(&shutdown_dir)?);
        let values = current_values(&normal, &shutdown, dt.rated_generator_torque());
        evaluate(&normal, &shutdown, &dt, &values)?
    } else {
        best
    };
    let report = table(&best, &start, evaluations);
    println!("\n{report}");
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).with_context(|| parent.display().to_string())?;
    }
    std::fs::write(&args.out, &report).with_context(|| args.out.display().to_string())?;
    println!("table written to {}", args.out.display());
    Ok(())
}
