//! The thesis's normal operation and shutdown of a drivetrain through the co-simulation master
//! (`windrive shutdown` prints and draws it): both scenes run at their own step and recorded to CSV,
//! the summary of [`crate::analysis::shutdown`] with the modes it is read against, and the charts a
//! drivetrain engineer reads: shaft torques, speeds, mesh forces (reversals visible), the HSS-torque
//! spectrum while braking with the computed modes marked, the rainflow range–mean cloud.

use crate::analysis::fatigue::rainflow;
use crate::analysis::shutdown::{self, Summary};
use crate::cosim::{Algorithm, Master, Options, Override, Record, Scene, System, param, recorder::Recorder};
use crate::linear::modes::Boundary;
use crate::physics::drivetrain::Drivetrain;
use crate::reference::modes::lowest_mode;
use anyhow::{Context, bail};
use std::path::{Path, PathBuf};

/// The scene folders of a preset's normal operation and shutdown under `scenes`: the spring scenes
/// (the thesis's electrical spring K_gen, the analytic C_p) with `spring`.
pub fn scene_dirs(scenes: &Path, preset: &str, spring: bool) -> (PathBuf, PathBuf) {
    let lower = preset.to_ascii_lowercase();
    let suffix = if spring { "-spring" } else { "" };
    (
        scenes.join(format!("{lower}-normal{suffix}")),
        scenes.join(format!("{lower}-shutdown{suffix}")),
    )
}

/// The rotor's parameters for an aerodynamics choice: scene (as the scene files say), bem (the
/// blade-element momentum rotor, trimmed start pitch: the parked rotor is damped by its blades) or
/// analytic (Heier's C_p, fine start pitch).
pub fn aerodynamics(choice: &str) -> anyhow::Result<Vec<Override>> {
    Ok(match choice {
        "bem" => vec![
            param("rotor", "aerodynamics", "bem"),
            param("rotor", "initial_pitch", "-1"),
        ],
        "analytic" => vec![
            param("rotor", "aerodynamics", "analytic"),
            param("rotor", "initial_pitch", "0"),
        ],
        "scene" => vec![],
        other => bail!("--aerodynamics {other:?}: use bem, analytic or scene"),
    })
}

/// One scene run with Gauss–Seidel at its own step, every output recorded to `csv`: the simulated
/// and the wall time, s.
pub fn run_scene(scene: &Scene, csv: &Path, overrides: &[Override]) -> anyhow::Result<(f64, f64)> {
    let mut system = System::build(scene, overrides, &Record::Outputs)?;
    let stop = scene.experiment.stop_time.context("the scene has no stop time")?;
    let step = scene.experiment.step_size.unwrap_or(1e-3);
    system.initialize(Some(stop))?;
    let mut recorder = Recorder::create(csv, &system, 1)?;
    let started = std::time::Instant::now();
    let mut master = Master::new(&mut system, Options::new(Algorithm::GaussSeidel, step, stop))?;
    master.run(|t, sys| recorder.observe(t, sys))?;
    let final_time = master.stats.final_time;
    recorder.finish(final_time, &mut system)?;
    let wall = started.elapsed().as_secs_f64();
    system.terminate();
    Ok((stop, wall))
}

/// The summary of the two runs' CSVs, with the lowest free–free and HSS-held modes, Hz, it reads the
/// braking frequencies against.
pub struct Reading {
    pub summary: Summary,
    pub free_hz: f64,
    pub held_hz: f64,
}

pub fn read_runs(
    preset: &str,
    drivetrain: &Drivetrain,
    normal_csv: &Path,
    shutdown_csv: &Path,
) -> anyhow::Result<Reading> {
    let free_hz = lowest_mode(preset, Boundary::Disconnected)?;
    let held_hz = lowest_mode(preset, Boundary::HssLocked)?;
    let summary = shutdown::summarise(preset, drivetrain, normal_csv, shutdown_csv, free_hz, held_hz)?;
    Ok(Reading {
        summary,
        free_hz,
        held_hz,
    })
}

/// One chart: its file name, titles, and named lines (or point clouds) with labelled x markers.
pub struct Chart {
    pub file: &'static str,
    pub title: String,
    pub x_label: &'static str,
    pub y_label: &'static str,
    pub lines: Vec<(String, Vec<(f64, f64)>)>,
    pub markers: Vec<(f64, String)>,
    /// Points, not lines.
    pub scatter: bool,
}

/// The charts of a read shutdown, in the order they are drawn.
pub fn charts(preset: &str, drivetrain: &Drivetrain, reading: &Reading) -> Vec<Chart> {
    let summary = &reading.summary;
    let s = &summary.series;
    let t = &s.time;
    let shafts = &summary.shafts;
    let pairs = |x: &[f64], scale: f64| -> Vec<(f64, f64)> { t.iter().zip(x).map(|(a, b)| (*a, b * scale)).collect() };
    let (lss_rated, hss_rated) = (shafts[0].rated_torque, shafts[shafts.len() - 1].rated_torque);
    let marks = vec![
        (shutdown::SHUTDOWN_TIME, "shutdown".to_string()),
        (summary.brake_applied_s, "brake on".into()),
    ];
    let over_time = |file, title: String, y_label, lines: Vec<(String, Vec<(f64, f64)>)>| Chart {
        file,
        title,
        x_label: "time [s]",
        y_label,
        lines,
        markers: marks.clone(),
        scatter: false,
    };
    let rpm = 30.0 / std::f64::consts::PI;
    let mut charts = vec![
        over_time(
            "shaft_torques.png",
            format!("Drivetrain {preset} shutdown: shaft torques"),
            "torque / rated",
            vec![
                ("HSS".into(), pairs(&s.hss_torque, 1.0 / hss_rated)),
                ("LSS".into(), pairs(&s.lss_torque, 1.0 / lss_rated)),
            ],
        ),
        over_time(
            "speeds.png",
            format!("Drivetrain {preset} shutdown: speeds"),
            "speed / rated",
            vec![
                (
                    "rotor".into(),
                    pairs(&s.rotor_speed, rpm / (drivetrain.rated_rotor_speed * rpm)),
                ),
                (
                    "generator".into(),
                    pairs(
                        &s.generator_speed,
                        1.0 / (drivetrain.rated_rotor_speed * drivetrain.gear_ratio()),
                    ),
                ),
            ],
        ),
        over_time(
            "mesh_forces.png",
            format!("Drivetrain {preset} shutdown: mesh forces (negative = flank reversal)"),
            "force along the line of action [kN]",
            vec![
                ("sun-planet 1".into(), pairs(&s.sun_planet, 1e-3)),
                (summary.last_mesh_label.into(), pairs(&s.last_mesh, 1e-3)),
            ],
        ),
    ];
    if let Some(r) = &summary.slipping {
        let pts: Vec<(f64, f64)> = r
            .frequencies
            .iter()
            .zip(&r.amplitudes)
            .take_while(|(f, _)| **f <= 10.0)
            .map(|(f, a)| (*f, *a))
            .collect();
        let (free, held) = (reading.free_hz, reading.held_hz);
        charts.push(Chart {
            file: "hss_spectrum.png",
            title: format!(
                "Drivetrain {preset}: HSS torque while the brake slips (peak {:.3} Hz)",
                r.frequency_hz
            ),
            x_label: "frequency [Hz]",
            y_label: "amplitude [N·m]",
            lines: vec![("HSS torque".into(), pts)],
            markers: vec![
                (free, format!("free-free {free:.2} Hz")),
                (held, format!("HSS locked {held:.2} Hz")),
            ],
            scatter: false,
        });
    }
    let cloud = |x: &[f64]| -> Vec<(f64, f64)> {
        rainflow::cycles(x)
            .iter()
            .map(|c| (c.mean / 1e3, c.range / 1e3))
            .collect()
    };
    charts.push(Chart {
        file: "rainflow.png",
        title: format!("Drivetrain {preset}: rainflow cycles of HSS torque"),
        x_label: "cycle mean [kN·m]",
        y_label: "cycle range [kN·m]",
        lines: vec![
            ("shutdown".into(), cloud(&s.hss_torque)),
            ("normal operation".into(), cloud(&s.normal_hss_torque)),
        ],
        markers: Vec::new(),
        scatter: true,
    });
    charts
}
