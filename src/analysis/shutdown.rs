//! The summary a drivetrain engineer reads after a normal-operation and a shutdown run (thesis Ch. 7):
//! each shaft's largest torque against rated and the 1.35 design factor, the shutdown's torque ranges
//! against normal operation, when the brake is fully applied and when the HSS locks, the HSS torque's
//! dominant frequency while the brake slips and once it holds (beside the modes they should match),
//! and the mesh-force reversals.

use super::signal::metrics::{peak, range};
use super::signal::series::{SeriesError, read_channels};
use super::signal::spectrum::dominant_in_window;
use crate::physics::drivetrain::{Drivetrain, Stage};
use std::path::Path;

/// The design load factor the thesis compares peak shutdown torques with.
pub const DESIGN_FACTOR: f64 = 1.35;

/// When the shutdown starts in the scenes, s (scenes/*-shutdown).
pub const SHUTDOWN_TIME: f64 = 5.0;

/// Spectra ignore content below this frequency (the slow speed decay), Hz.
pub const F_MIN_HZ: f64 = 0.3;

/// One shaft's line of the summary.
#[derive(Debug, Clone, PartialEq)]
pub struct ShaftLoad {
    /// lss, is1, is2 or hss
    pub name: &'static str,
    pub rated_torque: f64,
    /// max |T| in the shutdown / rated
    pub peak_ratio: f64,
    /// max |T| in normal operation / rated
    pub normal_peak_ratio: f64,
    /// torque range in the shutdown / in normal operation
    pub range_ratio: f64,
}

/// A dominant frequency and the amplitude spectrum it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Ringing {
    pub frequency_hz: f64,
    pub frequencies: Vec<f64>,
    pub amplitudes: Vec<f64>,
}

/// The shutdown's channels the summary and its plots are made of, all on `time`.
#[derive(Debug, Clone, PartialEq)]
pub struct ShutdownSeries {
    pub time: Vec<f64>,
    pub lss_torque: Vec<f64>,
    pub hss_torque: Vec<f64>,
    pub rotor_speed: Vec<f64>,
    pub generator_speed: Vec<f64>,
    pub sun_planet: Vec<f64>,
    pub last_mesh: Vec<f64>,
    /// The HSS torque of normal operation (on its own time axis).
    pub normal_hss_torque: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    pub preset: String,
    pub shafts: Vec<ShaftLoad>,
    /// First time the brake command reaches 1, s.
    pub brake_applied_s: f64,
    /// First time the brake holds the HSS, s.
    pub locked_s: Option<f64>,
    /// Lowest free–free and HSS-locked natural frequencies, Hz (given).
    pub free_mode_hz: f64,
    pub locked_mode_hz: f64,
    pub slipping: Option<Ringing>,
    pub held: Option<Ringing>,
    /// Label of the last stage's first mesh ("last gear-pinion" or "2nd-stage sun-planet").
    pub last_mesh_label: &'static str,
    /// Smallest mesh forces, N: (sun-planet 1, last stage's mesh) in the shutdown and in normal operation.
    pub shutdown_min_mesh: (f64, f64),
    pub normal_min_mesh: (f64, f64),
    /// Mesh-force ranges in the shutdown over those in normal operation: (sun-planet 1, last stage's mesh).
    pub mesh_range_ratio: (f64, f64),
    /// The dominant HSS-torque frequency of normal operation, Hz (None: too short a record).
    pub normal_dominant_hz: Option<f64>,
    /// The held rotor's rocking, largest |rotor speed| (rad/s) over the first and the last 2 s of the
    /// held phase: how much damping the parked rotor has (its blades, the shafts).
    pub held_rocking: Option<(f64, f64)>,
    pub series: ShutdownSeries,
}

/// The first mesh of the last stage, as a torsional output name and a label: the last parallel stage's
/// gear–pinion mesh, or the second planetary stage's sun–planet 1 (drivetrain A).
pub fn last_stage_mesh(dt: &Drivetrain) -> (String, &'static str) {
    let parallel = dt.stages.iter().filter(|s| matches!(s, Stage::Parallel(_))).count();
    match dt.stages.last() {
        Some(Stage::Parallel(_)) => (format!("mesh_force_gear_pinion_{parallel}"), "last gear-pinion"),
        _ => ("mesh_force_sun_planet2_1".into(), "2nd-stage sun-planet"),
    }
}

/// Shaft names of a drivetrain with their rated torques: the LSS carries the rotor's, each stage
/// divides by its ratio; the last shaft is the HSS.
pub fn shafts(dt: &Drivetrain) -> Vec<(&'static str, f64)> {
    let mut shafts = vec![("lss", dt.rated_rotor_torque())];
    let mut rated = dt.rated_rotor_torque();
    for (k, stage) in dt.stages.iter().enumerate() {
        rated /= stage.ratio();
        let name = if k + 1 == dt.stages.len() {
            "hss"
        } else if k == 0 {
            "is1"
        } else {
            "is2"
        };
        shafts.push((name, rated));
    }
    shafts
}

fn min(x: &[f64]) -> f64 {
    x.iter().cloned().fold(f64::MAX, f64::min)
}

/// Reads the two recordings (component `torsional` and `rotor` outputs, as the scenes record them) and
/// summarises them; `free_mode_hz` and `locked_mode_hz` are the modes the ringing is compared with.
pub fn summarise(
    preset: &str,
    dt: &Drivetrain,
    normal_csv: &Path,
    shutdown_csv: &Path,
    free_mode_hz: f64,
    locked_mode_hz: f64,
) -> Result<Summary, SeriesError> {
    let shafts = shafts(dt);
    let (last_mesh, last_mesh_label) = last_stage_mesh(dt);
    let mut names: Vec<String> = shafts.iter().map(|(s, _)| format!("torsional.{s}_torque")).collect();
    let n_shafts = names.len();
    for extra in [
        "torsional.mesh_force_sun_planet_1".to_string(),
        format!("torsional.{last_mesh}"),
        "torsional.brake_locked".into(),
        "rotor.brake_command".into(),
        "torsional.rotor_speed".into(),
        "torsional.generator_speed".into(),
    ] {
        names.push(extra);
    }
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    // normal operation has no brake: only the shafts and meshes are read from it
    let (normal_t, mut normal) = read_channels(normal_csv, &names[..n_shafts + 2])?;
    let (t, mut shut) = read_channels(shutdown_csv, &names)?;
    let rows = shafts
        .iter()
        .enumerate()
        .map(|(k, (name, rated))| ShaftLoad {
            name,
            rated_torque: *rated,
            peak_ratio: peak(&shut[k]) / rated,
            normal_peak_ratio: peak(&normal[k]) / rated,
            range_ratio: range(&shut[k]) / range(&normal[k]),
        })
        .collect();
    let (locked, brake) = (&shut[n_shafts + 2], &shut[n_shafts + 3]);
    let brake_applied_s = t[brake.iter().position(|&b| b >= 1.0).unwrap_or(0)];
    let locked_s = locked.iter().position(|&l| l > 0.5).map(|i| t[i]);
    let hss = &shut[n_shafts - 1];
    let end = t[t.len() - 1];
    let ringing = |from: f64, to: f64| {
        dominant_in_window(&t, hss, from, to, F_MIN_HZ).map(|(frequency_hz, frequencies, amplitudes)| Ringing {
            frequency_hz,
            frequencies,
            amplitudes,
        })
    };
    let slipping = ringing(brake_applied_s + 0.1, locked_s.map_or(end, |l| l - 0.1));
    let held = locked_s.and_then(|l| ringing(l + 0.5, end));
    let speed = &shut[n_shafts + 4];
    let peak_speed = |from: f64, to: f64| {
        t.iter()
            .zip(speed)
            .filter(|(x, _)| **x >= from && **x < to)
            .fold(0.0f64, |m, (_, w)| m.max(w.abs()))
    };
    let held_rocking = locked_s
        .filter(|&l| end - l >= 4.0)
        .map(|l| (peak_speed(l, l + 2.0), peak_speed(end - 2.0, end + 1.0)));
    let shutdown_min_mesh = (min(&shut[n_shafts]), min(&shut[n_shafts + 1]));
    let normal_min_mesh = (min(&normal[n_shafts]), min(&normal[n_shafts + 1]));
    let mesh_range_ratio = (
        range(&shut[n_shafts]) / range(&normal[n_shafts]),
        range(&shut[n_shafts + 1]) / range(&normal[n_shafts + 1]),
    );
    let normal_end = normal_t.last().copied().unwrap_or(0.0);
    let normal_dominant_hz =
        dominant_in_window(&normal_t, &normal[n_shafts - 1], 0.0, normal_end + 1.0, F_MIN_HZ).map(|(f, _, _)| f);
    let mut take = |k: usize| std::mem::take(&mut shut[k]);
    let series = ShutdownSeries {
        lss_torque: take(0),
        hss_torque: take(n_shafts - 1),
        sun_planet: take(n_shafts),
        last_mesh: take(n_shafts + 1),
        rotor_speed: take(n_shafts + 4),
        generator_speed: take(n_shafts + 5),
        normal_hss_torque: std::mem::take(&mut normal[n_shafts - 1]),
        time: t,
    };
    Ok(Summary {
        preset: preset.to_string(),
        shafts: rows,
        brake_applied_s,
        locked_s,
        free_mode_hz,
        locked_mode_hz,
        slipping,
        held,
        last_mesh_label,
        shutdown_min_mesh,
        normal_min_mesh,
        mesh_range_ratio,
        normal_dominant_hz,
        held_rocking,
        series,
    })
}

impl std::fmt::Display for Summary {
    /// The summary as the main job prints it and writes summary.txt.
    fn fmt(&self, out: &mut std::fmt::Formatter) -> std::fmt::Result {
        writeln!(out, "drivetrain {}, shutdown vs normal operation\n", self.preset)?;
        writeln!(
            out,
            "{:<6} {:>14} {:>16} {:>16} {:>18}",
            "shaft", "rated [N·m]", "max |T| / rated", "vs 1.35 design", "range shut/normal"
        )?;
        for s in &self.shafts {
            writeln!(
                out,
                "{:<6} {:>14.1} {:>16.3} {:>16} {:>18.2}",
                s.name,
                s.rated_torque,
                s.peak_ratio,
                if s.peak_ratio > DESIGN_FACTOR {
                    "exceeds"
                } else {
                    "within"
                },
                s.range_ratio
            )?;
        }
        let hz = |r: &Option<Ringing>| r.as_ref().map_or("-".into(), |r| format!("{:.3} Hz", r.frequency_hz));
        writeln!(
            out,
            "\nbrake fully applied at {:.2} s, HSS locked at {}",
            self.brake_applied_s,
            self.locked_s.map_or("never".into(), |l| format!("{l:.2} s"))
        )?;
        writeln!(
            out,
            "dominant HSS-torque frequency while the brake slips: {} (lowest free-free mode {:.3} Hz{})",
            hz(&self.slipping),
            self.free_mode_hz,
            if self.preset == "D" { "; thesis 2.61 Hz" } else { "" }
        )?;
        writeln!(
            out,
            "dominant HSS-torque frequency with the HSS held:    {} (lowest HSS-locked mode {:.3} Hz)",
            hz(&self.held),
            self.locked_mode_hz
        )?;
        if let Some((first, last)) = self.held_rocking {
            writeln!(
                out,
                "held rotor rocking, max |rotor speed|:              {first:.4} rad/s in the first 2 s held, {last:.4} rad/s in the last 2 s"
            )?;
        }
        writeln!(
            out,
            "mesh-force reversal: sun-planet min {:.1} kN, {} min {:.1} kN (normal operation min {:.1} / {:.1} kN)",
            self.shutdown_min_mesh.0 / 1e3,
            self.last_mesh_label,
            self.shutdown_min_mesh.1 / 1e3,
            self.normal_min_mesh.0 / 1e3,
            self.normal_min_mesh.1 / 1e3,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rated torques divide by each stage's ratio down to the HSS, which carries the generator's.
    #[test]
    fn shafts_step_down_to_the_generator_torque() {
        for preset in ["A", "B", "C", "D"] {
            let dt = Drivetrain::preset(preset).unwrap();
            let s = shafts(&dt);
            assert_eq!(s.len(), dt.stages.len() + 1);
            assert_eq!((s[0].0, s[s.len() - 1].0), ("lss", "hss"));
            let hss = s[s.len() - 1].1;
            assert!(
                (hss / dt.rated_generator_torque() - 1.0).abs() < 1e-9,
                "{preset}: {hss}"
            );
        }
    }
}
