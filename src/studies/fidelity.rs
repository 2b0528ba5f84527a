//! The fidelity a scene needs (`windrive fidelity` prints it): the ladder of its drivetrain model
//! (torsional 2-mass, 5-mass, full; gearbox6dof with few and many slices, linear and lamina bearings),
//! each level's CPU time and error on the scene's quantities of interest against the top of the
//! ladder, the cheapest level within every tolerance; beside it the modal reasoning: which of the full
//! model's modes lie inside the band the scene's inputs excite, and how well each reduced model keeps
//! them.

use super::scene_study::{Measured, Study, component_of};
use crate::analysis::signal::spectrum::amplitude_spectrum;
use crate::cosim::{Algorithm, Options, Override, Scene, param as p};
use crate::linear::modes::{Boundary, modes};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::torsional::{Fidelity, ModelOptions, TorsionalModel};
use anyhow::{anyhow, bail};
use std::fmt::{self, Write as _};

/// A rung of the ladder: its name and the parameters that make it.
pub struct Level {
    pub name: String,
    overrides: Vec<Override>,
}

/// The ladder of a scene, cheapest first, and the top level's parameters (the reference's).
pub fn ladder(scene: &Scene) -> anyhow::Result<(Vec<Level>, Vec<Override>)> {
    if let Some(c) = component_of(scene, "torsional") {
        let levels = [("2-mass", "2"), ("5-mass", "5"), ("full torsional", "full")]
            .iter()
            .map(|(name, f)| Level {
                name: name.to_string(),
                overrides: vec![p(&c, "fidelity", f)],
            })
            .collect();
        return Ok((levels, vec![p(&c, "fidelity", "full")]));
    }
    if let Some(c) = component_of(scene, "gearbox6dof") {
        let mut levels = Vec::new();
        for slices in ["5", "35"] {
            // the lamina levels take the law as the presets run it (its roller sums by table); the
            // reference sums every lamina
            for (bearings, model) in [("linear", "linear"), ("lamina", "lamina-table")] {
                levels.push(Level {
                    name: format!("gearbox6dof {slices} slices, {bearings} bearings"),
                    overrides: vec![p(&c, "slices", slices), p(&c, "bearing_model", model)],
                });
            }
        }
        return Ok((levels, vec![p(&c, "slices", "35"), p(&c, "bearing_model", "lamina")]));
    }
    bail!(
        "scene {}: no torsional or gearbox6dof component, so no fidelity ladder",
        scene.name
    )
}

/// Every level run `repeat` times at the scene's macro step (Gauss–Seidel); `starting(k, level)`
/// before level k. A level that fails ends the study, named.
pub fn measure_ladder(
    study: &Study,
    levels: &[Level],
    repeat: usize,
    mut starting: impl FnMut(usize, &Level),
) -> anyhow::Result<Vec<Measured>> {
    let opts = Options::new(Algorithm::GaussSeidel, study.scene_step, study.stop_time);
    let mut measured = Vec::new();
    for (k, level) in levels.iter().enumerate() {
        starting(k, level);
        let m = study.measure(&level.overrides, &opts, repeat);
        if let Some(f) = &m.failure {
            bail!("{}: {f}", level.name);
        }
        measured.push(m);
    }
    Ok(measured)
}

/// CPU times closer than this fraction are the same cost: timing noise. Runs of one scene on a 2-core VM
/// vary by ±15 % (docs/SPEED-ACCURACY.md); at 5 % the pick between two levels whose cost is the other
/// FMUs' (C's 5-mass and full models) changed from run to run, at 15 % the more accurate one wins each time.
pub const SAME_COST: f64 = 0.15;

/// The level to recommend from (CPU s, within tolerance, error in tolerances) per level: the cheapest
/// within tolerance; among levels as cheap as it within [`SAME_COST`], the most accurate (when the
/// drivetrain's share of the cost is small, a finer model costs nothing).
pub fn recommend(levels: &[(f64, bool, f64)]) -> Option<usize> {
    let ok: Vec<usize> = (0..levels.len()).filter(|&i| levels[i].1).collect();
    let cheapest = ok.iter().map(|&i| levels[i].0).fold(f64::INFINITY, f64::min);
    ok.into_iter()
        .filter(|&i| levels[i].0 <= cheapest * (1.0 + SAME_COST))
        .min_by(|&a, &b| levels[a].2.total_cmp(&levels[b].2))
}

/// [`recommend`] on the measured levels of `study`.
pub fn recommended(study: &Study, measured: &[Measured]) -> Option<usize> {
    let qs = &study.quantities;
    recommend(
        &measured
            .iter()
            .map(|m| (m.cpu_s, m.within(qs), m.worst_in_tolerances(qs)))
            .collect::<Vec<_>>(),
    )
}

/// The modal reasoning of a torsional ladder: the band the inputs excite and each fidelity's modes.
pub struct Modal {
    pub preset: String,
    /// The frequency below which 99 % of the spectral energy of every input lies, Hz.
    pub band_hz: f64,
    /// The inputs, as component.variable.
    pub inputs: Vec<String>,
    /// Free–free modes (Hz, the rigid mode left out) per fidelity, the full model last.
    pub modes: Vec<(&'static str, Vec<f64>)>,
}

impl Modal {
    /// The scene's modal reasoning when its drivetrain is torsional, else None.
    pub fn of(study: &Study) -> anyhow::Result<Option<Self>> {
        let Some(c) = component_of(&study.scene, "torsional") else {
            return Ok(None);
        };
        let preset = study.scene.string_parameter(&c, "preset").unwrap_or("D").to_string();
        let (band_hz, inputs) = excitation_band(study, &c)?;
        let modes = modes_by_fidelity(&preset)?;
        Ok(Some(Self {
            preset,
            band_hz,
            inputs,
            modes,
        }))
    }

    /// The full model's modes.
    pub fn full(&self) -> &[f64] {
        self.modes.last().map_or(&[], |(_, f)| f)
    }

    /// How many of `modes` lie inside the band.
    pub fn inside(&self, modes: &[f64]) -> usize {
        modes.iter().filter(|x| **x <= self.band_hz).count()
    }

    /// The largest relative difference of any fidelity's first mode from the full model's.
    pub fn first_mode_spread(&self) -> f64 {
        let full = self.full();
        self.modes
            .iter()
            .map(|(_, f)| (f[0] - full[0]).abs() / full[0])
            .fold(0.0, f64::max)
    }

    /// The largest relative difference of `modes` from the full model's, over the first `kept`.
    pub fn kept_error(&self, modes: &[f64], kept: usize) -> f64 {
        let full = self.full();
        (0..kept)
            .map(|i| (modes[i] - full[i]).abs() / full[i])
            .fold(0.0, f64::max)
    }
}

/// The measured ladder as `windrive fidelity --json` prints it: the recommended level, each level's CPU
/// time and errors, and with `modal` the band and each fidelity's modes.
pub fn to_json(
    study: &Study,
    levels: &[Level],
    measured: &[Measured],
    recommended: Option<&str>,
    modal: Option<&Modal>,
) -> serde_json::Value {
    let qs = &study.quantities;
    let levels_json: Vec<serde_json::Value> = levels
        .iter()
        .zip(measured)
        .map(|(l, m)| {
            serde_json::json!({
                "name": l.name,
                "cpu_s": m.cpu_s,
                "error": m.worst(),
                "error_in_tolerances": m.worst_in_tolerances(qs),
                "within_tolerance": m.within(qs),
                "errors": qs.iter().zip(&m.errors).map(|(q, e)| serde_json::json!({"quantity": q.name, "error": e, "tolerance": q.tolerance})).collect::<Vec<_>>(),
            })
        })
        .collect();
    let mut out = serde_json::json!({ "recommended": recommended, "levels": levels_json, "reference_step_s": study.reference.step });
    if let Some(modal) = modal {
        out["excitation_band_hz"] = serde_json::json!(modal.band_hz);
        out["excitation_inputs"] = serde_json::json!(modal.inputs);
        out["preset"] = serde_json::json!(modal.preset);
        out["modes_hz"] = serde_json::json!(
            modal
                .modes
                .iter()
                .map(|(n, f)| (n.to_string(), f.clone()))
                .collect::<std::collections::BTreeMap<_, _>>()
        );
    }
    out
}

/// The measured ladder as `windrive fidelity` prints it: a row per level (CPU time, largest error,
/// within tolerance, the quantity nearest its tolerance), then the recommendation.
pub fn table(study: &Study, levels: &[Level], measured: &[Measured], recommended: Option<&str>) -> String {
    let qs = &study.quantities;
    let mut s = format!(
        "\n{:<40} {:>9} {:>14} {:>12}  worst quantity\n",
        "level", "CPU [s]", "max rel err", "within tol"
    );
    for (l, m) in levels.iter().zip(measured) {
        let worst = m
            .errors
            .iter()
            .zip(qs)
            .max_by(|a, b| (a.0 / a.1.tolerance).total_cmp(&(b.0 / b.1.tolerance)))
            .map(|(e, q)| format!("{} ({:.2} % of {:.1} %)", q.name, e * 100.0, q.tolerance * 100.0))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "{:<40} {:>9.3} {:>14.3e} {:>12}  {worst}",
            l.name,
            m.cpu_s,
            m.worst(),
            if m.within(qs) { "yes" } else { "no" }
        );
    }
    let _ = match recommended {
        Some(r) => writeln!(
            s,
            "\nrecommended: {r} (the cheapest level with every quantity within its tolerance; levels within {:.0} % of its CPU time count as as cheap, the most accurate of them wins)",
            SAME_COST * 100.0
        ),
        None => writeln!(
            s,
            "\nno level is within every tolerance at the scene's macro step: refine the step or widen the tolerances"
        ),
    };
    s
}

/// The modal reasoning as `windrive fidelity` prints it: the band, each fidelity's modes and how
/// many lie inside it, what each reduced model keeps, and what modes cannot tell.
impl fmt::Display for Modal {
    fn fmt(&self, out: &mut fmt::Formatter) -> fmt::Result {
        let band = self.band_hz;
        writeln!(
            out,
            "\nexcitation: 99 % of the spectral energy of {} lies below {band:.2} Hz",
            self.inputs.join(" and ")
        )?;
        writeln!(
            out,
            "free-free modes of drivetrain {} [Hz] (rigid mode left out):",
            self.preset
        )?;
        let full = self.full();
        for (name, f) in &self.modes {
            let shown: Vec<String> = f.iter().take(6).map(|x| format!("{x:.2}")).collect();
            writeln!(
                out,
                "  {name:<16} {}{}   ({} inside the band)",
                shown.join(", "),
                if f.len() > 6 { ", ..." } else { "" },
                self.inside(f)
            )?;
        }
        let inside_full = self.inside(full);
        if inside_full == 0 {
            writeln!(
                out,
                "  no elastic mode lies inside the band: the drivetrain follows these inputs quasi-statically, and every level \
                 keeps the first mode ({:.2} Hz in the full model) within {:.1} %",
                full[0],
                self.first_mode_spread() * 100.0
            )?;
        }
        for (name, f) in &self.modes[..self.modes.len() - 1] {
            let kept = f.len().min(inside_full);
            if inside_full > 0 && kept == inside_full {
                writeln!(
                    out,
                    "  {name}: keeps every full-model mode inside the band ({inside_full}) within {:.1} %; condenses the {} above it",
                    self.kept_error(f, kept) * 100.0,
                    full.len() - inside_full
                )?;
            } else if inside_full > 0 {
                writeln!(
                    out,
                    "  {name}: has {} elastic modes, the band holds {inside_full} of the full model's: it cannot follow the rest",
                    f.len()
                )?;
            }
        }
        writeln!(
            out,
            "  what modes cannot tell: the transients (brake engagement, lock, mesh reversal) ring modes far above the band, \
             and a lumped model's HSS torque is its one shaft's torque over the gear ratio, carrying the gear stages' inertia \
             that the real HSS does not: the errors above say whether that matters for the scene's quantities"
        )
    }
}

/// The band the scene's drivetrain inputs excite: the frequency below which 99 % of the spectral
/// energy of each input (detrended) lies, the largest over the inputs, Hz.
fn excitation_band(study: &Study, torsional: &str) -> anyhow::Result<(f64, Vec<String>)> {
    let inputs: Vec<String> = study
        .scene
        .connections
        .iter()
        .filter(|c| c.end_element == torsional && c.end_connector.ends_with("_torque"))
        .map(|c| format!("{}.{}", c.start_element, c.start_connector))
        .collect();
    if inputs.is_empty() {
        bail!(
            "scene {}: no torque input of {torsional} is connected",
            study.scene.name
        );
    }
    let names: Vec<&str> = inputs.iter().map(|s| s.as_str()).collect();
    let opts = Options::new(Algorithm::GaussSeidel, study.scene_step, study.stop_time);
    let run = crate::cosim::master::run_columns_with(&study.scene, &study.reference_overrides, &names, opts)
        .map_err(|e| anyhow!("scene {}: {e}", study.scene.name))?;
    let dt = run.columns[0][1] - run.columns[0][0];
    let mut band: f64 = 0.0;
    for x in &run.columns[1..] {
        let (f, a) = amplitude_spectrum(x, dt);
        let energy: Vec<f64> = a.iter().skip(1).map(|v| v * v).collect();
        let total: f64 = energy.iter().sum();
        if total <= 0.0 {
            continue;
        }
        let mut cumulative = 0.0;
        for (k, e) in energy.iter().enumerate() {
            cumulative += e;
            if cumulative >= 0.99 * total {
                band = band.max(f[k + 1]);
                break;
            }
        }
    }
    Ok((band, inputs))
}

/// Free–free modes (Hz, the rigid mode left out) of a preset at each fidelity.
fn modes_by_fidelity(preset: &str) -> anyhow::Result<Vec<(&'static str, Vec<f64>)>> {
    let dt = Drivetrain::preset(preset).ok_or_else(|| anyhow!("unknown preset {preset:?}"))?;
    let mut out = Vec::new();
    for (name, f) in [
        ("2-mass", Fidelity::Two),
        ("5-mass", Fidelity::Five),
        ("full torsional", Fidelity::Full),
    ] {
        let model = TorsionalModel::new(&dt, f, &ModelOptions::default()).map_err(|e| anyhow!(e))?;
        let m = modes(&model, Boundary::Disconnected, dt.k_generator);
        out.push((name, m.frequencies_hz.into_iter().filter(|f| *f > 1e-6).collect()));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::recommend;

    #[test]
    fn the_cheapest_within_tolerance_and_the_most_accurate_among_equally_cheap() {
        // (CPU s, within, error in tolerances)
        assert_eq!(
            recommend(&[(0.1, false, 2.0), (0.5, true, 0.5), (1.0, true, 0.1)]),
            Some(1)
        );
        assert_eq!(
            recommend(&[(0.376, false, 2.1), (0.372, true, 0.04), (0.368, true, 0.007)]),
            Some(2)
        );
        assert_eq!(
            recommend(&[(0.370, true, 0.5), (0.372, true, 0.04), (0.9, true, 0.0)]),
            Some(1)
        );
        // 12 % dearer is timing noise: the more accurate level; 20 % dearer is a cost
        assert_eq!(recommend(&[(1.0, true, 0.5), (1.12, true, 0.1)]), Some(1));
        assert_eq!(recommend(&[(1.0, true, 0.5), (1.2, true, 0.1)]), Some(0));
        assert_eq!(recommend(&[(0.1, false, 2.0)]), None);
    }
}
