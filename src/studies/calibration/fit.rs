//! Fitting drivetrain C's scene inputs that no source gives to the thesis's measured statistics
//! (`windrive calibrate` prints it): the free inputs with their search ranges, one evaluation (both
//! scenes through the master, every statistic's misfit), the Nelder–Mead fit over the inputs mapped
//! onto the unit cube, and writing the fitted values into the scenes' parameter files.

use super::{Context, Runs};
use crate::cosim::Scene;
use crate::physics::drivetrain::Drivetrain;
use crate::studies::nelder_mead;
use anyhow::Context as _;
use std::fmt::Write as _;
use std::path::Path;

/// A free input: where it goes, its bounds, whether it is searched on a log scale.
pub struct Free {
    pub name: &'static str,
    pub file: &'static str,
    pub variable: &'static str,
    pub unit: &'static str,
    pub low: f64,
    pub high: f64,
    log: bool,
}

/// The brake torque is searched as a multiple of the rated generator torque and written in N·m.
pub const FREE: [Free; 5] = [
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
    /// The input at `u` ∈ [0, 1] of its search range.
    fn value(&self, u: f64) -> f64 {
        if self.log {
            self.low * (self.high / self.low).powf(u)
        } else {
            self.low + (self.high - self.low) * u
        }
    }

    /// Where `v` lies in the search range, clamped to [0, 1].
    fn unit_of(&self, v: f64) -> f64 {
        let u = if self.log {
            (v / self.low).ln() / (self.high / self.low).ln()
        } else {
            (v - self.low) / (self.high - self.low)
        };
        u.clamp(0.0, 1.0)
    }

    /// The value written into the scene: the brake torque in N·m, the rest as searched.
    fn scene_value(&self, v: f64, rated_generator: f64) -> f64 {
        if self.variable == "brake_torque_max" {
            v * rated_generator
        } else {
            v
        }
    }
}

/// Drivetrain C's two scenes, opened with their FMUs in place, and its description.
pub struct Scenes {
    pub normal: Scene,
    pub shutdown: Scene,
    pub drivetrain: Drivetrain,
}

impl Scenes {
    pub fn new(normal: Scene, shutdown: Scene) -> Self {
        Self {
            normal,
            shutdown,
            drivetrain: Drivetrain::preset("C").expect("preset C"),
        }
    }

    /// The scenes' values of the free inputs (scene file, else the FMU default).
    pub fn current_values(&self) -> Vec<f64> {
        let rated_generator = self.drivetrain.rated_generator_torque();
        let lookup =
            |scene: &Scene, file: &str, variable: &str| scene.real_parameter(file.trim_end_matches(".ssv"), variable);
        // the FMUs' defaults where a scene sets nothing: NTM class A at 16 m/s is 0.16·(0.75·16 + 5.6)/16
        let defaults = [0.176, 1.5, 0.6, 0.1396263, 0.2];
        FREE.iter()
            .zip(defaults)
            .map(|(f, default)| {
                let scene = if f.variable == "turbulence_intensity" {
                    &self.normal
                } else {
                    &self.shutdown
                };
                match lookup(scene, f.file, f.variable) {
                    Some(v) if f.variable == "brake_torque_max" && v > 0.0 => v / rated_generator,
                    Some(v) if v > 0.0 || !f.log => v,
                    _ => default,
                }
            })
            .collect()
    }

    /// Both scenes run with the free inputs at `values`: every statistic and the objective.
    pub fn evaluate(&self, values: &[f64]) -> anyhow::Result<Evaluation> {
        let dt = &self.drivetrain;
        let o = overrides(values, dt.rated_generator_torque());
        let [nt, nl, nh, ns] = run_scene(&self.normal, &o)?;
        let [st, sl, sh, ss] = run_scene(&self.shutdown, &o)?;
        let number = |name: &str, default: f64| self.shutdown.real_parameter("rotor", name).unwrap_or(default);
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
        let statistics = super::evaluate(&runs, &context);
        Ok(Evaluation {
            values: values.to_vec(),
            objective: super::objective(&statistics),
            statistics,
        })
    }

    /// Nelder–Mead from `start` over at most `evaluations` scene pairs; `progress(count, objective,
    /// best so far)` after every evaluation that ran. The best inputs evaluated, and the evaluations used.
    pub fn fit(
        &self,
        start: &[f64],
        evaluations: usize,
        mut progress: impl FnMut(usize, f64, f64),
    ) -> anyhow::Result<(Evaluation, usize)> {
        let mut failure: Option<anyhow::Error> = None;
        let mut count = 0;
        let mut best_so_far = f64::INFINITY;
        let u0: Vec<f64> = FREE.iter().zip(start).map(|(f, v)| f.unit_of(*v)).collect();
        let minimum = nelder_mead::minimise(
            |u| {
                count += 1;
                let values: Vec<f64> = FREE.iter().zip(u).map(|(f, x)| f.value(*x)).collect();
                match self.evaluate(&values) {
                    Ok(e) => {
                        best_so_far = best_so_far.min(e.objective);
                        progress(count, e.objective, best_so_far);
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
            evaluations,
            1e-4,
        );
        if let Some(e) = failure.filter(|_| !minimum.value.is_finite()) {
            return Err(e.context("every evaluation failed"));
        }
        let values: Vec<f64> = FREE.iter().zip(&minimum.x).map(|(f, x)| f.value(*x)).collect();
        Ok((self.evaluate(&values)?, minimum.evaluations))
    }
}

/// One evaluation: the free inputs, each statistic's (achieved, misfit), the objective.
#[derive(Debug, Clone)]
pub struct Evaluation {
    pub values: Vec<f64>,
    pub statistics: Vec<(f64, f64)>,
    pub objective: f64,
}

fn overrides(values: &[f64], rated_generator: f64) -> Vec<(String, String, String)> {
    FREE.iter()
        .zip(values)
        .map(|(f, v)| {
            (
                f.file.trim_end_matches(".ssv").to_string(),
                f.variable.to_string(),
                format!("{}", f.scene_value(*v, rated_generator)),
            )
        })
        .collect()
}

const CHANNELS: [&str; 3] = [
    "torsional.lss_torque",
    "torsional.hss_torque",
    "torsional.mesh_force_sun_planet_1",
];

/// Time and the statistics' channels of one scene run (Gauss–Seidel at 1 ms), in memory.
fn run_scene(scene: &Scene, overrides: &[(String, String, String)]) -> anyhow::Result<[Vec<f64>; 4]> {
    let c = crate::cosim::master::run_columns(scene, overrides, &CHANNELS, None).map_err(|e| anyhow::anyhow!(e))?;
    let mut it = c.into_iter();
    let mut next = || it.next().unwrap_or_default();
    Ok([next(), next(), next(), next()])
}

/// Writes the free inputs at `values` into the parameter files of each scene folder in `dirs`.
pub fn write_values(dirs: &[&Path], values: &[f64], rated_generator: f64) -> anyhow::Result<()> {
    for dir in dirs {
        for (f, v) in FREE.iter().zip(values) {
            write_parameter(&dir.join(f.file), f.variable, f.scene_value(*v, rated_generator))?;
        }
    }
    Ok(())
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

/// The fit as docs/calibration-c.md's Markdown: each statistic's target, start and achieved value
/// and misfit, each input's start, fitted value and search range.
pub fn markdown(e: &Evaluation, start: &Evaluation, evaluations: usize) -> String {
    let mut s = String::from(
        "# Drivetrain C's scene inputs fitted to the thesis's measurements\n\n\
         Written by `windrive calibrate` (the command and its reading: docs/DRIVETRAINS.md, \"Calibration\").\n\n",
    );
    let _ = writeln!(
        s,
        "Drivetrain C's scenes (scenes/c-normal, scenes/c-shutdown) against the thesis's statistics (ch. 3: \
         measured on the field turbine; §6.2: its simulations of drivetrain C);\n\
         misfit = ln(achieved / target), 0 inside a stated bound. Objective (sum of squared misfits): {:.4} \
         ({evaluations} evaluations; {:.4} at the start).\n",
        e.objective, start.objective
    );
    let _ = writeln!(s, "| statistic | thesis | start | achieved | misfit |");
    let _ = writeln!(s, "|---|---|---|---|---|");
    for (stat, ((a, m), (a0, _))) in super::statistics()
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
