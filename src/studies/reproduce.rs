//! Every number of the thesis this project computes, beside ours (`windrive reproduce` prints it as
//! docs/REPRODUCTION.md's table). The thesis's values are data, not code: data/thesis.toml lists each
//! with where it stands in the thesis, the tolerance within which we claim to reproduce it, the reason
//! where they differ, and which of our computations it is set beside ([`Ours`]). This file computes
//! ours: modes, gear ratios, mesh orders, operating hours and rated speeds directly; braking
//! frequencies, peaks, ratios and speeds from the scenes run through the master.

use crate::analysis::fatigue::operating_hours::WindDistribution;
use crate::analysis::shutdown::F_MIN_HZ;
use crate::analysis::signal::spectrum::dominant_in_window;
use crate::cosim::Scene;
use crate::cosim::master::run_columns;
use crate::physics::drivetrain::{Drivetrain, Stage};
use crate::studies::calibration::{self, fit::Scenes};
use crate::studies::preset_modes::preset_modes;
use anyhow::{Context, anyhow};
use serde::Deserialize;
use std::collections::HashMap;
use std::fmt::Write as _;

/// The thesis's numbers, in the order of the table.
const THESIS: &str = include_str!("data/thesis.toml");

/// One number of the thesis beside ours.
#[derive(Debug, Clone)]
pub struct Row {
    pub quantity: String,
    /// Where it stands in the thesis: a table, figure or chapter.
    pub source: String,
    pub thesis: f64,
    pub ours: f64,
    /// Relative tolerance within which we claim to reproduce it; None: shown, not claimed.
    pub claimed: Option<f64>,
    pub reason: String,
}

impl Row {
    pub fn difference(&self) -> f64 {
        self.ours / self.thesis - 1.0
    }

    pub fn reproduced(&self) -> bool {
        self.claimed.is_some_and(|t| self.difference().abs() <= t)
    }
}

/// A row of data/thesis.toml.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    quantity: String,
    source: String,
    thesis: f64,
    claimed: Option<f64>,
    #[serde(default)]
    reason: String,
    ours: Ours,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entries {
    row: Vec<Entry>,
}

/// Which of our numbers a thesis value is set beside.
#[derive(Debug, Clone, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Ours {
    /// The preset's overall ratio from its tooth counts.
    GearRatio { preset: String },
    /// Stage `stage` (from 1)'s mesh order in the thesis's convention (its Table 4.8).
    MeshOrder { preset: String, stage: usize },
    /// Natural frequency number `number` (1: the lowest, the rigid mode counted) of the preset's
    /// model at `fidelity` with the generator `generator` (as `windrive modes` names them), Hz.
    Mode {
        preset: String,
        fidelity: String,
        generator: String,
        number: usize,
    },
    /// Hours out of `hours` in the wind bin (bin − width, bin] of a Rayleigh climate.
    OperatingHours {
        rayleigh_mean_m_s: f64,
        bin_m_s: f64,
        bin_width_m_s: f64,
        hours: f64,
    },
    /// The generator's rated speed over the tooth-count ratio, rpm.
    RatedRotorSpeedRpm { preset: String },
    /// The dominant HSS-torque frequency of a shutdown scene while the brake slips, Hz.
    BrakingFrequency { scene: String },
    /// A shutdown scene's peak LSS torque over the preset's rated rotor torque.
    PeakLssTorqueRatio { scene: String, preset: String },
    /// A statistic of drivetrain C's scenes (the names of [`calibration::statistics`]).
    Calibration { statistic: String },
    /// One statistic of C's scenes over another.
    CalibrationRatio { statistic: String, over: String },
    /// A scene's mean generator speed, rpm.
    MeanGeneratorSpeedRpm { scene: String },
}

impl Ours {
    /// Whether this number needs a scene run through the master.
    pub fn runs_a_scene(&self) -> bool {
        matches!(
            self,
            Ours::BrakingFrequency { .. }
                | Ours::PeakLssTorqueRatio { .. }
                | Ours::Calibration { .. }
                | Ours::CalibrationRatio { .. }
                | Ours::MeanGeneratorSpeedRpm { .. }
        )
    }
}

fn entries() -> anyhow::Result<Vec<Entry>> {
    let e: Entries = toml::from_str(THESIS).map_err(|e| anyhow!("src/studies/data/thesis.toml: {e}"))?;
    Ok(e.row)
}

/// Opens a repository scene by name (e.g. "c-shutdown"), its FMUs in place.
pub type OpenScene<'a> = &'a dyn Fn(&str) -> anyhow::Result<Scene>;

/// Every row: the thesis's value beside ours, in the table's order. `open` opens the scenes the
/// rows run; each runs once.
pub fn rows(open: OpenScene) -> anyhow::Result<Vec<Row>> {
    let mut ours = Computed::new(open);
    entries()?
        .into_iter()
        .map(|e| {
            Ok(Row {
                ours: ours.of(&e.ours)?,
                quantity: e.quantity,
                source: e.source,
                thesis: e.thesis,
                claimed: e.claimed,
                reason: e.reason,
            })
        })
        .collect()
}

/// The thesis's values of the rows whose quantity starts with `prefix`, in the table's order (for
/// the commands that quote them).
pub fn thesis_values(prefix: &str) -> anyhow::Result<Vec<f64>> {
    Ok(entries()?
        .into_iter()
        .filter(|e| e.quantity.starts_with(prefix))
        .map(|e| e.thesis)
        .collect())
}

fn preset(name: &str) -> anyhow::Result<Drivetrain> {
    Drivetrain::preset(name).ok_or_else(|| anyhow!("unknown preset {name:?}"))
}

/// Our numbers, with each scene's runs kept for the rows that share them.
struct Computed<'a> {
    open: OpenScene<'a>,
    /// Per shutdown scene: the braking frequency, Hz, and the peak |LSS torque|, N·m.
    shutdowns: HashMap<String, (f64, f64)>,
    /// C's statistics (achieved, misfit), in the order of [`calibration::statistics`].
    calibration: Option<Vec<(f64, f64)>>,
}

impl<'a> Computed<'a> {
    fn new(open: OpenScene<'a>) -> Self {
        Self {
            open,
            shutdowns: HashMap::new(),
            calibration: None,
        }
    }

    fn of(&mut self, ours: &Ours) -> anyhow::Result<f64> {
        Ok(match ours {
            Ours::GearRatio { preset: p } => preset(p)?.gear_ratio(),
            Ours::MeshOrder { preset: p, stage } => *thesis_mesh_orders(&preset(p)?)
                .get(stage.wrapping_sub(1))
                .ok_or_else(|| anyhow!("preset {p} has no stage {stage}"))?,
            Ours::Mode {
                preset,
                fidelity,
                generator,
                number,
            } => {
                let (_, m) = preset_modes(preset, fidelity, generator, "physical")?;
                *m.frequencies_hz
                    .get(number.wrapping_sub(1))
                    .ok_or_else(|| anyhow!("drivetrain {preset} has no mode {number}"))?
            }
            Ours::OperatingHours {
                rayleigh_mean_m_s,
                bin_m_s,
                bin_width_m_s,
                hours,
            } => WindDistribution::Rayleigh {
                mean: *rayleigh_mean_m_s,
            }
            .hours_per_bin(&[*bin_m_s], *bin_width_m_s, *hours)[0],
            Ours::RatedRotorSpeedRpm { preset: p } => preset(p)?.rated_rotor_speed * 30.0 / std::f64::consts::PI,
            Ours::BrakingFrequency { scene } => self.shutdown(scene)?.0,
            Ours::PeakLssTorqueRatio { scene, preset: p } => {
                let rated = preset(p)?.rated_rotor_torque();
                self.shutdown(scene)?.1 / rated
            }
            Ours::Calibration { statistic } => self.statistic(statistic)?,
            Ours::CalibrationRatio { statistic, over } => self.statistic(statistic)? / self.statistic(over)?,
            Ours::MeanGeneratorSpeedRpm { scene } => {
                let scene = (self.open)(scene)?;
                let speed = run_columns(&scene, &[], &["torsional.generator_speed"], None).map_err(|e| anyhow!(e))?;
                speed[1].iter().sum::<f64>() / speed[1].len() as f64 * 30.0 / std::f64::consts::PI
            }
        })
    }

    /// Dominant HSS-torque frequency while the brake slips, Hz, and the peak |LSS torque|, N·m, of a
    /// shutdown scene.
    fn shutdown(&mut self, name: &str) -> anyhow::Result<(f64, f64)> {
        if let Some(known) = self.shutdowns.get(name) {
            return Ok(*known);
        }
        let scene = (self.open)(name)?;
        let channels = ["torsional.hss_torque", "torsional.brake_locked", "torsional.lss_torque"];
        let c = run_columns(&scene, &[], &channels, None).map_err(|e| anyhow!(e))?;
        let (t, hss, locked, lss) = (&c[0], &c[1], &c[2], &c[3]);
        // the FMUs' defaults where the scene sets nothing
        let param = |n: &str, d: f64| scene.real_parameter("rotor", n).unwrap_or(d);
        let applied = param("shutdown_time", 5.0) + param("brake_delay", 0.5) + param("brake_ramp_time", 0.6);
        let end = t.last().copied().unwrap_or(0.0);
        let lock = locked.iter().position(|&l| l > 0.5).map_or(end, |i| t[i]);
        let (f, _, _) = dominant_in_window(t, hss, applied + 0.1, lock - 0.1, F_MIN_HZ)
            .with_context(|| format!("{}: no slipping phase to analyse", scene.root.display()))?;
        let peak = lss.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        self.shutdowns.insert(name.to_string(), (f, peak));
        Ok((f, peak))
    }

    /// The achieved value of one of C's statistics, its scenes as they are.
    fn statistic(&mut self, name: &str) -> anyhow::Result<f64> {
        let index = calibration::statistics()
            .iter()
            .position(|s| s.name == name)
            .ok_or_else(|| anyhow!("no statistic {name:?} in studies::calibration"))?;
        if self.calibration.is_none() {
            let scenes = Scenes::new((self.open)("c-normal")?, (self.open)("c-shutdown")?);
            self.calibration = Some(scenes.evaluate(&scenes.current_values())?.statistics);
        }
        Ok(self.calibration.as_ref().expect("just evaluated")[index].0)
    }
}

/// The rows as docs/REPRODUCTION.md's Markdown table, with its heading.
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "# The thesis's numbers beside ours\n\nWritten by `windrive reproduce`. \"claimed\" rows are asserted by \
         tests/it/reproduction.rs within the tolerance shown; the others are shown with the reason they differ.\n\n\
         | quantity | thesis | where | ours | difference | claimed | reason |\n|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let claim = match r.claimed {
            Some(t) if r.reproduced() => format!("yes, ±{:.1} %", t * 100.0),
            Some(t) => format!("**no** (±{:.1} %)", t * 100.0),
            None => "—".into(),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:+.2} % | {} | {} |",
            r.quantity,
            r.thesis,
            r.source,
            format_ours(r.ours),
            r.difference() * 100.0,
            claim,
            r.reason
        );
    }
    s
}

fn format_ours(x: f64) -> String {
    if x.abs() >= 100.0 {
        format!("{x:.1}")
    } else {
        format!("{x:.4}")
    }
}

/// Mesh orders in the thesis's convention (Table 4.8): teeth of the sun or pinion times its speed
/// over the rotor's.
fn thesis_mesh_orders(dt: &Drivetrain) -> Vec<f64> {
    let mut speed = 1.0;
    dt.stages
        .iter()
        .map(|s| {
            speed *= s.ratio();
            speed
                * match s {
                    Stage::Planetary(p) => p.z_sun as f64,
                    Stage::Parallel(p) => p.z_pinion as f64,
                }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The data file parses, and every row that runs no scene computes.
    #[test]
    fn the_thesis_values_parse_and_the_static_rows_compute() {
        let entries = entries().unwrap();
        assert_eq!(entries.len(), 37);
        let no_scene: OpenScene = &|name| Err(anyhow!("{name}: no scene in this test"));
        let mut ours = Computed::new(no_scene);
        for e in entries.iter().filter(|e| !e.ours.runs_a_scene()) {
            let x = ours.of(&e.ours).unwrap();
            assert!(x.is_finite() && x > 0.0, "{}: {x}", e.quantity);
        }
        let names: Vec<&str> = calibration::statistics().iter().map(|s| s.name).collect();
        for e in &entries {
            if let Ours::Calibration { statistic } | Ours::CalibrationRatio { statistic, .. } = &e.ours {
                assert!(names.contains(&statistic.as_str()), "{statistic}");
            }
        }
    }
}
