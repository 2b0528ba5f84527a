//! `windrive bench gearbox`: the 6-DOF GRC gearbox in drivetrain D's 30 s shutdown scene
//! (scenes/d-shutdown-6dof) through the master with lamina bearings and 35, 11 and 5 slices per
//! mesh, with the main shaft as one element or rigid, with linear bearings and at internal steps of
//! 1 and 0.5 ms, with the FMU's other Newton iterations (`newton` = kept, predicted,
//! kept+predicted) and with the lamina law's roller sums by table (`bearing_model = lamina-table`),
//! each against the 35-slice lamina run at 0.25 ms without numerical damping (largest mesh forces,
//! bearing load and contact pressures, rollers in contact, HSS torque), with the FMU's time split by
//! the scene's phases (normal operation, the brake applied, the HSS held); the torsional
//! model in the same scene (scenes/d-shutdown) as the baseline measured in the same run; the
//! integrators at part load, where the teeth and rollers open and close (drivetrain C at cut-in wind,
//! scenes/c-normal-6dof); and the explicit alternative (RK4 at its stability limit) against the
//! implicit step on the bare physics, with the work per step that sets the speed.

use crate::cosim::{Algorithm, Master, Options, Record, Scene, System, param};
use crate::linear::modes::eigenpairs_of;
use crate::physics::gearbox::statics::equilibrium;
use crate::physics::gearbox::{Description, Gearbox};
use crate::solver::alpha::{Alpha, NEARLY_LINEAR_INCREMENT_TOLERANCE};
use crate::solver::{Driver, DynState, Method, rk4};
use std::fmt;
use std::path::Path;
use std::time::Instant;

/// A scene run's wall time, s, every component's part of it (its steps and output reads), s, the
/// gearbox's doStep calls alone, s, and the recorded columns.
struct SceneRun {
    wall_s: f64,
    units: Vec<(String, f64)>,
    gearbox_do_step_s: f64,
    cols: Vec<Vec<f64>>,
    /// The gearbox FMU's time (its steps and output reads), s, when the run passed each of [`PHASE_ENDS`].
    gearbox_marks: Vec<f64>,
}

/// The part of a run's wall time spent in the component `name` of `units`, s (0 for none of that name).
fn unit_s(units: &[(String, f64)], name: &str) -> f64 {
    units.iter().find(|(n, _)| n == name).map_or(0.0, |u| u.1)
}

/// A scene run (Gauss–Seidel, 1 ms), each component timed on its own.
fn run_scene(
    dir: &Path,
    overrides: &[(String, String, String)],
    channels: &[String],
    stop: f64,
) -> anyhow::Result<SceneRun> {
    let scene = Scene::open(dir)?;
    let mut system = System::build(&scene, overrides, &Record::Only(channels.to_vec()))?;
    system.initialize(Some(stop))?;
    crate::cosim::profile::start(&mut system);
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); channels.len()];
    let gearbox = system.units.iter().position(|u| u.name == "gearbox");
    let mut gearbox_marks = Vec::new();
    let start = Instant::now();
    let mut master = Master::new(&mut system, Options::new(Algorithm::GaussSeidel, 1e-3, stop))?;
    master.run(|time, sys| {
        crate::cosim::master::read_every_row(sys, time)?;
        for (k, (_, u, i)) in sys.recorded.iter().enumerate() {
            cols[k].push(sys.units[*u].values[*i]);
        }
        if let Some(g) = gearbox
            && let Some(&end) = PHASE_ENDS.get(gearbox_marks.len())
            && time >= end - 0.5e-3
        {
            gearbox_marks.push(sys.units[g].clock.unwrap_or_default().total().as_secs_f64());
        }
        Ok(())
    })?;
    let wall_s = start.elapsed().as_secs_f64();
    drop(master);
    let clock = |u: &crate::cosim::unit::Unit| u.clock.unwrap_or_default();
    let gearbox_do_step_s = system
        .units
        .iter()
        .find(|u| u.name == "gearbox")
        .map_or(0.0, |u| clock(u).do_step.as_secs_f64());
    let units = system
        .units
        .iter()
        .map(|u| (u.name.clone(), clock(u).total().as_secs_f64()))
        .collect();
    Ok(SceneRun {
        wall_s,
        units,
        gearbox_do_step_s,
        cols,
        gearbox_marks,
    })
}

/// d-shutdown-6dof's phases, each one's end, s: the brake is applied at 5 s (the trip), and by 10 s the
/// HSS is stopped and held while the rotor rocks (docs/PERFORMANCE.md, "Where the gearbox's steps go by
/// phase": a held step costs the gearbox's defaults 1.7 times a step of normal operation).
const PHASE_ENDS: [f64; 2] = [5.0, 10.0];

/// The FMU's ms per simulated second in each phase (up to 5 s, 5–10 s, after 10 s), from its time at the
/// phase ends the run passed, `marks` (s), and over the whole run, `total` (s), of `stop` s; NaN for a
/// phase the run did not reach.
fn phase_ms_per_s(marks: &[f64], total: f64, stop: f64) -> [f64; 3] {
    let mut out = [f64::NAN; 3];
    let (mut t0, mut clock0) = (0.0, 0.0);
    for (k, ms) in out.iter_mut().enumerate() {
        let t1 = PHASE_ENDS.get(k).map_or(stop, |&end| end.min(stop));
        if t1 <= t0 {
            break;
        }
        let clock1 = marks.get(k).copied().filter(|_| t1 < stop).unwrap_or(total);
        *ms = (clock1 - clock0) / (t1 - t0) * 1e3;
        (t0, clock0) = (t1, clock1);
    }
    out
}

fn peak(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

fn rms_error(x: &[f64], reference: &[f64]) -> f64 {
    let e: f64 = x.iter().zip(reference).map(|(a, b)| (a - b) * (a - b)).sum();
    let r: f64 = reference.iter().map(|b| b * b).sum();
    (e / r).sqrt()
}

/// The GRC's main shaft as the preset gives it (three beam elements with their mass), as one
/// massless element (exact for loads at its ends, six DOFs fewer per node), or rigid (one element,
/// its steel a thousand times stiffer: the bearings and the carrier take all the compliance).
#[derive(Clone, Copy)]
enum MainShaft {
    Preset,
    OneElement,
    Rigid,
}

impl MainShaft {
    /// A description file for the FMU's `gearbox` parameter, None for the preset itself.
    fn description(self) -> anyhow::Result<Option<std::path::PathBuf>> {
        let (name, stiffer) = match self {
            MainShaft::Preset => return Ok(None),
            MainShaft::OneElement => ("one-element", 1.0),
            MainShaft::Rigid => ("rigid", 1e3),
        };
        let mut d = Description::load("grc750")?;
        let beam = d
            .rotor
            .as_mut()
            .and_then(|r| r.shaft.as_mut())
            .and_then(|s| s.beam.as_mut())
            .ok_or_else(|| anyhow::anyhow!("grc750: the bench expects its main shaft as a beam"))?;
        beam.elements = 1;
        beam.youngs_modulus *= stiffer;
        beam.shear_modulus *= stiffer;
        let file = std::env::temp_dir().join(format!("windrive-bench-grc750-{name}-main-shaft.toml"));
        std::fs::write(&file, toml::to_string(&d)?)?;
        Ok(Some(file))
    }
}

/// One gearbox variant against the reference.
#[derive(Debug, Clone)]
pub struct VariantRow {
    pub label: &'static str,
    /// `lamina`, `lamina-table` or `linear`, and whether the row is the full model (35 slices, the preset's main
    /// shaft) at the FMU's default step and integrator (1 ms, HHT-α): the rows issue 33's targets are for.
    pub bearings: &'static str,
    pub full_model: bool,
    /// The whole scene's wall time and the gearbox FMU's part of it (its steps and output reads), s,
    /// and of that its doStep calls alone (the rest: its output reads, the loads' evaluation after each
    /// step among them).
    pub wall_s: f64,
    pub gearbox_s: f64,
    pub gearbox_do_step_s: f64,
    /// Peak differences against the reference, %: sun–planet and gear–pinion mesh force, planet 1's
    /// upwind bearing's radial load and inner-race pressure, the HSS mesh's contact pressure.
    pub sun_planet: f64,
    pub gear_pinion: f64,
    pub planet_upwind: f64,
    pub upwind_pressure: f64,
    pub hss_pressure: f64,
    /// The fewest rollers carrying planet 1's upwind bearing in normal operation, this run's and the
    /// reference's (NaN when the run ends before 1 s).
    pub fewest_rollers: f64,
    pub reference_fewest_rollers: f64,
    /// RMS difference of the HSS torque from the reference's, % of its RMS.
    pub hss_rms_error: f64,
    /// The gearbox FMU's ms per simulated second up to the brake's trip at 5 s, from 5 to 10 s, and after
    /// 10 s (NaN for a phase the run did not reach).
    pub phase_ms_per_s: [f64; 3],
}

/// What issue 33 asks of the gearbox FMU on its own (its steps and output reads in this scene), in
/// multiples of real time: 35 slices with lamina bearings, and linear bearings.
pub const LAMINA_TARGET: f64 = 20.0;
pub const LINEAR_TARGET: f64 = 50.0;

/// The head of the variants' table over `stop` s; each [`VariantRow`] renders as a row of it
/// ([`VariantRow::row`]).
pub fn variants_head(stop: f64) -> String {
    format!(
        "drivetrain D shutdown scene, {stop} s at 1 ms through the master (Gauss–Seidel); reference: 35 slices with \
         lamina bearings at a 0.25 ms internal step with Newmark's average acceleration (no numerical damping); rows: the \
         FMU's default HHT-α (ρ∞ = 0.8) at 1 ms unless named; baseline: torsional full fidelity\n\
         {:<24} {:>9} {:>7} {:>9} {:>7} {:>7} {:>11} {:>11} {:>11} {:>11} {:>9} {:>11} {:>11} {:>10}",
        "variant",
        "ms per s",
        "× real",
        "FMU ms/s",
        "reads",
        "FMU ×",
        "÷ torsional",
        "sun-planet",
        "gear-pinion",
        "planet UW",
        "min rollr",
        "UW p_max",
        "HSS p_H",
        "HSS RMS"
    )
}

/// The torsional baseline's scene: its wall time and each component's part of it, s.
#[derive(Debug, Clone)]
pub struct Baseline {
    pub wall_s: f64,
    pub units: Vec<(String, f64)>,
}

impl Baseline {
    /// The torsional FMU's part, s.
    pub fn fmu_s(&self) -> f64 {
        unit_s(&self.units, "torsional")
    }
}

/// The foot of the variants' table: the baseline over `stop` s, where its time goes, what bounds the
/// scene, the columns' meaning.
pub fn variants_foot(stop: f64, base: &Baseline) -> String {
    let ms = |s: f64| s / stop * 1e3;
    let rest = base.wall_s - base.fmu_s();
    let split: Vec<String> = base
        .units
        .iter()
        .map(|(name, s)| format!("{name} {:.2}", ms(*s)))
        .chain([format!(
            "master and recording {:.2}",
            ms(base.wall_s - base.units.iter().map(|u| u.1).sum::<f64>())
        )])
        .collect();
    format!(
        "torsional: {:.2} ms per simulated s ({:.0}× real time): {} ms per s; so no gearbox makes this scene faster \
         than {:.0}× real time; columns: ms per s and × real for the whole scene, FMU ms/s and FMU × for the gearbox \
         FMU's steps and output reads alone, reads the ms per s of its output reads among them (the loads of \
         the elements read, evaluated once per step, included), ÷ torsional the scene against the torsional scene, peak differences against \
         the reference (min rollr: fewest rollers carrying planet 1's upwind bearing in normal operation, the \
         reference's in brackets; linear bearings report none); the gearbox FMU's defaults are the row \"same, table, \
         kept+pred.\" with the FMU's own linear_solver, newton_tolerance, roller_update_distance and \
         newton_motion_floor (the rows \"same, FMU defaults\", which set none of them; \"same, rollers exact\" sets \
         roller_update_distance = 0 and \"same, motion floor 0\" newton_motion_floor = 0, as every other row does \
         both); \"same, table, kept+pred.\" takes grc750's lamina-table bearings and newton = \
         kept+predicted with dense LU and the tolerance {NEARLY_LINEAR_INCREMENT_TOLERANCE:e}, as every row that names \
         neither; rows that name no bearings or iteration take the lamina loop and newton = pattern; the rows \"same, \
         tolerance {LOOSER_TOLERANCE:e}\" and \"same, sparse J\" newton = kept+predicted with their section's \
         bearings and newton_tolerance = {LOOSER_TOLERANCE:e} or linear_solver = sparse\n",
        ms(base.wall_s),
        stop / base.wall_s,
        split.join(", "),
        stop / rest,
    )
}

/// Whether the gearbox FMU alone meets issue 33's targets in the rows `rows`: the fastest full-model row
/// ([`VariantRow::full_model`]) of each bearing model, named by its label (the lamina law by table counts
/// as lamina bearings: the same law, its accuracy in its row).
pub fn targets(rows: &[VariantRow], stop: f64) -> String {
    // the reference row's FMU time: a row's speed against it is what no phase of the machine moves
    let reference = rows.iter().find(|r| r.label == REFERENCE_LABEL).map(|r| r.gearbox_s);
    let fastest = |bearings: &[&str]| {
        rows.iter()
            .filter(|r| r.full_model && bearings.contains(&r.bearings))
            .min_by(|a, b| a.gearbox_s.total_cmp(&b.gearbox_s))
            .map_or((f64::NAN, "none", String::new()), |r| {
                let against = reference.map_or(String::new(), |s| {
                    format!("; {:.1}× the reference's speed", s / r.gearbox_s)
                });
                (stop / r.gearbox_s, r.label, against)
            })
    };
    let verdict = |x: f64, target: f64| if x >= target { "met" } else { "not met" };
    let ((lamina, lamina_row, lamina_ref), (linear, linear_row, linear_ref)) =
        (fastest(&["lamina", "lamina-table"]), fastest(&["linear"]));
    format!(
        "targets for the gearbox FMU alone (the fastest full-model row at 1 ms): 35 slices with lamina bearings \
         {lamina:.1}× real time ({lamina_row:?}; ≥ {LAMINA_TARGET}×: {}{lamina_ref}), linear bearings {linear:.1}× \
         ({linear_row:?}; ≥ {LINEAR_TARGET}×: {}{linear_ref}){}\n",
        verdict(lamina, LAMINA_TARGET),
        verdict(linear, LINEAR_TARGET),
        if reference.is_some() {
            "; real time moves with the machine's load and speed, a row's speed against the reference in the same \
             run does not"
        } else {
            ""
        },
    )
}

/// The gearbox FMU's time by phase of the scene for each row: where a row's `FMU ms/s` comes from.
pub fn phases(rows: &[VariantRow]) -> String {
    let mut out = format!(
        "the gearbox FMU's ms per simulated s by phase of the scene (its steps and output reads): normal operation up to \
         the trip at 5 s, the brake applied from 5 to 10 s, the HSS held after 10 s\n{:<24} {:>9} {:>9} {:>9}\n",
        "variant", "0-5 s", "5-10 s", "10 s on"
    );
    for r in rows {
        let [a, b, c] = r.phase_ms_per_s;
        out += &format!(
            "{:<24} {:>9} {:>9} {:>9}\n",
            r.label,
            or_dash(a, 1),
            or_dash(b, 1),
            or_dash(c, 1)
        );
    }
    out
}

/// A peak difference, %, with its sign.
fn percent(x: f64) -> String {
    format!("{x:+.2}%")
}

/// `x` with `digits` decimals, or "—" where the run did not reach what it measures (NaN): a roller count
/// outside normal operation's window, a phase after the run's end.
fn or_dash(x: f64, digits: usize) -> String {
    if x.is_nan() {
        "—".into()
    } else {
        format!("{x:.digits$}")
    }
}

impl VariantRow {
    /// The row of this variant over `stop` s, against the torsional baseline `base`.
    pub fn row(&self, stop: f64, base: &Baseline) -> String {
        format!(
            "{:<24} {:>9.1} {:>7.2} {:>9.1} {:>7.1} {:>7.2} {:>11.1} {:>11} {:>11} {:>11} {:>4} ({}) {:>11} {:>11} {:>9.3}%",
            self.label,
            self.wall_s / stop * 1e3,
            stop / self.wall_s,
            self.gearbox_s / stop * 1e3,
            (self.gearbox_s - self.gearbox_do_step_s) / stop * 1e3,
            stop / self.gearbox_s,
            self.wall_s / base.wall_s,
            percent(self.sun_planet),
            percent(self.gear_pinion),
            percent(self.planet_upwind),
            or_dash(self.fewest_rollers, 0),
            or_dash(self.reference_fewest_rollers, 0),
            percent(self.upwind_pressure),
            percent(self.hss_pressure),
            self.hss_rms_error,
        )
    }
}

/// The recorded channels of both models, component left out (the torsional model has the first three).
const CHANNELS: [&str; 7] = [
    "hss_torque",
    "mesh_force_sun_planet_1",
    "mesh_force_gear_pinion_2",
    "planet_1_uw_radial_load",
    "planet_1_uw_rollers_in_contact",
    "planet_1_uw_inner_race_pressure",
    "max_contact_pressure_gear_pinion_2",
];

fn channels(component: &str) -> Vec<String> {
    CHANNELS.iter().map(|n| format!("{component}.{n}")).collect()
}

/// The baseline: the torsional model in d-shutdown (the folder `dir`) over `stop` s.
pub fn torsional_baseline(dir: &Path, stop: f64) -> anyhow::Result<Baseline> {
    let run = run_scene(dir, &[], &channels("torsional")[..3], stop)?;
    Ok(Baseline {
        wall_s: run.wall_s,
        units: run.units,
    })
}

/// The label of the first row, the 0.25 ms reference every row's differences and the targets' ratios are
/// taken against.
const REFERENCE_LABEL: &str = "reference: 0.25 ms";

/// The looser Newton tolerance of the rows "same, tolerance 1e-7" (their labels spell it).
const LOOSER_TOLERANCE: f64 = 1e-7;

/// One row's settings; None: the FMU's start value.
struct Variant {
    label: &'static str,
    slices: usize,
    bearings: &'static str,
    step: f64,
    integrator: &'static str,
    shaft: MainShaft,
    newton: &'static str,
    tolerance: Option<f64>,
    solver: Option<&'static str>,
    /// `roller_update_distance`, m.
    rollers: Option<f64>,
    /// `newton_motion_floor`.
    floor: Option<f64>,
}

impl Variant {
    /// The scene's parameter settings of this row.
    fn params(&self) -> anyhow::Result<Vec<(String, String, String)>> {
        let mut o = vec![
            param("gearbox", "slices", self.slices),
            param("gearbox", "bearing_model", self.bearings),
            param("gearbox", "max_internal_step", self.step),
            param("gearbox", "integrator", self.integrator),
            param("gearbox", "newton", self.newton),
        ];
        o.extend(self.tolerance.map(|t| param("gearbox", "newton_tolerance", t)));
        o.extend(self.solver.map(|s| param("gearbox", "linear_solver", s)));
        o.extend(self.rollers.map(|d| param("gearbox", "roller_update_distance", d)));
        o.extend(self.floor.map(|f| param("gearbox", "newton_motion_floor", f)));
        if let Some(file) = self.shaft.description()? {
            o.push(param("gearbox", "gearbox", file.display()));
        }
        Ok(o)
    }
}

/// The variants in d-shutdown-6dof (the folder `six`) over `stop` s; `row` after each.
pub fn variants(six: &Path, stop: f64, mut row: impl FnMut(&VariantRow)) -> anyhow::Result<()> {
    let mut reference: Option<Vec<Vec<f64>>> = None;
    // the reference is the full model at a quarter of the FMU's default internal step (1 ms): its
    // differences are the errors of each row, the step's included; rows take the lamina loop, the
    // `pattern` iteration (the reference's, and the FMU's defaults until 2026-11-30), dense LU, the
    // tolerance 1e-8 (the FMU's defaults until 2026-12-01) and every roller set evaluated exactly
    // (until 2026-12-03) unless they name others: "same, table, kept+pred." is the FMU's defaults of
    // 2026-11-30, the rows ending in 1e-7 take a looser Newton tolerance (`newton_tolerance`), the rows
    // "same, sparse J" solve with J on its sparsity pattern (`linear_solver = sparse`), the rows "same,
    // FMU defaults" set none of the four (the FMU's start values: sparse, 3e-8 and 3e-7 m since
    // 2026-12-03, the motion floor 1e-3 since 2026-12-04), "same, rollers exact" is the defaults with
    // `roller_update_distance = 0` and "same, motion floor 0" the defaults with `newton_motion_floor = 0`,
    // the floor every other row takes
    let tol = Some(NEARLY_LINEAR_INCREMENT_TOLERANCE);
    let (dense, exact, no_floor) = (Some("dense"), Some(0.0), Some(0.0));
    let pattern = |label, slices, bearings, step, integrator, shaft| Variant {
        label,
        slices,
        bearings,
        step,
        integrator,
        shaft,
        newton: "pattern",
        tolerance: tol,
        solver: dense,
        rollers: exact,
        floor: no_floor,
    };
    let at = |label, bearings, newton, tolerance, solver, rollers| Variant {
        label,
        slices: 35,
        bearings,
        step: 1e-3,
        integrator: "hht",
        shaft: MainShaft::Preset,
        newton,
        tolerance,
        solver,
        rollers,
        floor: no_floor,
    };
    let newton = |label, bearings, newton| at(label, bearings, newton, tol, dense, exact);
    let looser = |label, bearings| at(label, bearings, "kept+predicted", Some(LOOSER_TOLERANCE), dense, exact);
    let sparse = |label, bearings| at(label, bearings, "kept+predicted", tol, Some("sparse"), exact);
    let defaults = |label, bearings| Variant {
        floor: None,
        ..at(label, bearings, "kept+predicted", None, None, None)
    };
    let variants: [Variant; 23] = [
        pattern(REFERENCE_LABEL, 35, "lamina", 2.5e-4, "implicit", MainShaft::Preset),
        pattern("35 slices, lamina", 35, "lamina", 1e-3, "hht", MainShaft::Preset),
        newton("same, Newton kept", "lamina", "kept"),
        newton("same, Newton predicted", "lamina", "predicted"),
        newton("same, kept+predicted", "lamina", "kept+predicted"),
        newton("same, lamina-table", "lamina-table", "pattern"),
        newton("same, table, kept+pred.", "lamina-table", "kept+predicted"),
        looser("same, tolerance 1e-7", "lamina-table"),
        sparse("same, sparse J", "lamina-table"),
        Variant {
            rollers: exact,
            ..defaults("same, rollers exact", "lamina-table")
        },
        defaults("same, FMU defaults", "lamina-table"),
        Variant {
            floor: no_floor,
            ..defaults("same, motion floor 0", "lamina-table")
        },
        pattern("same, Newmark", 35, "lamina", 1e-3, "implicit", MainShaft::Preset),
        pattern("same, 0.5 ms", 35, "lamina", 5e-4, "hht", MainShaft::Preset),
        pattern("11 slices, lamina", 11, "lamina", 1e-3, "hht", MainShaft::Preset),
        pattern("5 slices, lamina", 5, "lamina", 1e-3, "hht", MainShaft::Preset),
        pattern("main shaft 1 element", 35, "lamina", 1e-3, "hht", MainShaft::OneElement),
        pattern("rigid main shaft", 35, "lamina", 1e-3, "hht", MainShaft::Rigid),
        pattern("35 slices, linear", 35, "linear", 1e-3, "hht", MainShaft::Preset),
        newton("same, kept+predicted", "linear", "kept+predicted"),
        looser("same, tolerance 1e-7", "linear"),
        sparse("same, sparse J", "linear"),
        defaults("same, FMU defaults", "linear"),
    ];
    for v in variants {
        let o = v.params()?;
        let run = run_scene(six, &o, &channels("gearbox"), stop)?;
        let gearbox_s = unit_s(&run.units, "gearbox");
        let phases = phase_ms_per_s(&run.gearbox_marks, gearbox_s, stop);
        let (wall_s, gearbox_do_step_s, cols) = (run.wall_s, run.gearbox_do_step_s, run.cols);
        let r = reference.get_or_insert_with(|| cols.clone());
        let rel = |k: usize| 100.0 * (peak(&cols[k]) / peak(&r[k]) - 1.0);
        // the fewest rollers carrying the upwind planet bearing in normal operation (1 s to the trip
        // at 5 s; the shutdown takes every bearing through zero load); NaN for a run shorter than 1 s
        let fewest = |c: &[f64]| {
            c.iter()
                .take(5000)
                .skip(1000)
                .copied()
                .reduce(f64::min)
                .unwrap_or(f64::NAN)
        };
        row(&VariantRow {
            label: v.label,
            bearings: v.bearings,
            full_model: v.slices == 35
                && matches!(v.shaft, MainShaft::Preset)
                && v.step == 1e-3
                && v.integrator == "hht",
            wall_s,
            gearbox_s,
            gearbox_do_step_s,
            sun_planet: rel(1),
            gear_pinion: rel(2),
            planet_upwind: rel(3),
            upwind_pressure: rel(5),
            hss_pressure: rel(6),
            fewest_rollers: fewest(&cols[4]),
            reference_fewest_rollers: fewest(&r[4]),
            hss_rms_error: 100.0 * rms_error(&cols[0], &r[0]),
            phase_ms_per_s: phases,
        });
    }
    Ok(())
}

/// The part-load runs leave out the first half (the rotor slowing from rated speed), in 1 ms steps.
pub fn part_load_skipped_steps(stop: f64) -> usize {
    (stop * 1e3) as usize / 2
}

/// One integrator at part load.
pub struct PartLoadRow {
    pub label: &'static str,
    pub wall_s: f64,
    /// The HSS torque's 99th percentile and largest magnitude, N·m.
    pub hss_p99: f64,
    pub hss_max: f64,
    /// The first parallel stage's largest mesh force, N.
    pub mesh_max: f64,
    /// RMS change of the generator's speed from one millisecond to the next, rad/s.
    pub speed_jitter: f64,
}

/// The head of the part-load table over `stop` s; each [`PartLoadRow`] renders as a row of it.
pub fn part_load_head(stop: f64) -> String {
    format!(
        "part load: drivetrain C at 4 m/s (scenes/c-normal-6dof, c2mw), {stop} s, after {} s; reference: Newmark at 0.25 ms\n\
         {:<24} {:>9} {:>12} {:>12} {:>14} {:>16}",
        part_load_skipped_steps(stop) as f64 * 1e-3,
        "integrator",
        "ms per s",
        "HSS T p99",
        "HSS T max",
        "IMS mesh max",
        "gen speed jitter"
    )
}

/// The foot of the part-load table: what its columns are.
pub const PART_LOAD_FOOT: &str = "HSS T: HSS torque, N·m; IMS mesh: the first parallel stage's mesh force, N; gen speed \
    jitter: RMS change of the generator's speed per millisecond, rad/s\n";

impl PartLoadRow {
    /// The row of this run over `stop` s.
    pub fn row(&self, stop: f64) -> String {
        format!(
            "{:<24} {:>9.1} {:>12.0} {:>12.0} {:>14.0} {:>16.4}",
            self.label,
            self.wall_s / stop * 1e3,
            self.hss_p99,
            self.hss_max,
            self.mesh_max,
            self.speed_jitter,
        )
    }
}

/// Drivetrain C at cut-in wind (4 m/s, the rotor's torque under 1 % of rated) in the scene folder
/// `dir` (scenes/c-normal-6dof): the teeth and the roller sets open and close. Newmark's rule keeps
/// every mode's amplitude, so at 1 ms the contacts' stiff modes, which the step cannot resolve, ring
/// from step to step; HHT-α damps them. The reference is Newmark at 0.25 ms. `row` after each run.
pub fn part_load(dir: &Path, stop: f64, mut row: impl FnMut(&PartLoadRow)) -> anyhow::Result<()> {
    let channels = [
        "gearbox.hss_torque",
        "gearbox.mesh_force_gear_pinion_1",
        "gearbox.generator_speed",
    ]
    .map(String::from);
    let skip = part_load_skipped_steps(stop);
    for (label, integrator, step) in [
        ("reference: Newmark 0.25 ms", "implicit", 2.5e-4),
        ("HHT-α 0.8, 1 ms (default)", "hht", 1e-3),
        ("Newmark, 1 ms", "implicit", 1e-3),
    ] {
        let o = vec![
            param("rotor", "wind_speed", 4.0),
            param("rotor", "turbulence_intensity", 0.344),
            param("gearbox", "integrator", integrator),
            param("gearbox", "max_internal_step", step),
        ];
        let SceneRun { wall_s, cols, .. } = run_scene(dir, &o, &channels, stop)?;
        let cols: Vec<Vec<f64>> = cols.into_iter().map(|c| c[skip.min(c.len())..].to_vec()).collect();
        let p99 = |x: &[f64]| {
            let mut a: Vec<f64> = x.iter().map(|v| v.abs()).collect();
            a.sort_by(f64::total_cmp);
            a.get(a.len() * 99 / 100).copied().unwrap_or(0.0)
        };
        let jitter = |x: &[f64]| {
            let d: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
            (d.iter().map(|v| v * v).sum::<f64>() / d.len().max(1) as f64).sqrt()
        };
        row(&PartLoadRow {
            label,
            wall_s,
            hss_p99: p99(&cols[0]),
            hss_max: peak(&cols[0]),
            mesh_max: peak(&cols[1]),
            speed_jitter: jitter(&cols[2]),
        });
    }
    Ok(())
}

/// RK4 at its stability limit against the implicit step, and the work per implicit step.
pub struct ExplicitImplicit {
    /// The stiffest mode's angular frequency, rad/s, and RK4's stability limit there, s.
    pub omega_max: f64,
    pub rk4_limit_s: f64,
    /// Wall time per simulated second, ms: RK4 at 99 % of its limit, Newmark at 1 ms.
    pub rk4_ms_per_s: f64,
    pub implicit_ms_per_s: f64,
    /// Newton iterations and factorisations per implicit step.
    pub newton_per_step: f64,
    pub factorizations_per_step: f64,
    pub slices: f64,
    pub dofs: f64,
    /// Flops of the contact sums and the dense back-substitution per iteration, and of a
    /// factorisation.
    pub contact_flops: f64,
    pub solve_flops: f64,
    pub factor_flops: f64,
    /// The physical limit: kflop per step and Mflop per simulated second.
    pub kflop_per_step: f64,
    pub mflop_per_s: f64,
    /// Share of the implicit run's wall time in the model's code (forces, tangent, contact pattern);
    /// the rest is the solver's (factorisations, solves, the step).
    pub model_share: f64,
}

/// The two paragraphs `windrive bench gearbox` ends with.
impl fmt::Display for ExplicitImplicit {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        writeln!(
            f,
            "explicit against implicit (35 slices, linear bearings, rated torque, bare physics): the stiffest mode is {:.0} Hz, so RK4 \
             needs h ≤ {:.2e} s: {:.0} ms per simulated s; Newmark at 1 ms: {:.1} ms per s ({:.0}× faster; the default step)",
            self.omega_max / std::f64::consts::TAU,
            self.rk4_limit_s,
            self.rk4_ms_per_s,
            self.implicit_ms_per_s,
            self.rk4_ms_per_s / self.implicit_ms_per_s
        )?;
        writeln!(
            f,
            "work per implicit step: {:.2} Newton iterations, {:.3} factorisations; per iteration the contact \
             sums cost ≈ {:.0} flops ({} slices) and the dense back-substitution {:.0} flops ({} DOFs); a \
             factorisation {:.0} flops. Physical limit: ≈ {:.0} kflop per step, {:.1} Mflop per simulated s",
            self.newton_per_step,
            self.factorizations_per_step,
            self.contact_flops,
            self.slices,
            self.solve_flops,
            self.dofs,
            self.factor_flops,
            self.kflop_per_step,
            self.mflop_per_s,
        )?;
        writeln!(
            f,
            "where the implicit step's time goes: model (forces, tangent, contact pattern) {:.0} %, solver \
             (factorisations, solves, the step) {:.0} %",
            100.0 * self.model_share,
            100.0 * (1.0 - self.model_share)
        )
    }
}

/// RK4 at its stability limit against the implicit 1 ms step (the default step; Newmark, which at
/// rated torque costs what the default HHT-α costs), both on the bare 35-slice physics at rated
/// torque, and the work per implicit step.
pub fn explicit_against_implicit() -> anyhow::Result<ExplicitImplicit> {
    let mut d = Description::load("grc750")?;
    d.model.gravity = 9.81;
    // the stability limit comes from the linear model's modes: the lamina bearings' tangent is
    // stiffer under load, and RK4 at the linear limit would diverge
    d.model.bearings = crate::physics::gearbox::description::BearingModel::Linear;
    let g = Gearbox::new(&d).map_err(|e| anyhow::anyhow!(e))?;
    let lin = g.engaged_linearisation();
    let keep: Vec<usize> = (0..g.dofs()).collect();
    let (lambda, _) = eigenpairs_of(&lin.mass, &lin.stiffness, &keep);
    let omega_max = lambda.iter().fold(0.0f64, |m, &l| m.max(l)).sqrt();
    let h_rk4 = rk4::stability_limit(omega_max);
    let t = g.rated_rotor_torque.unwrap_or(0.0);
    let speed = d.rated_rotor_speed_rpm.unwrap_or(0.0) * std::f64::consts::TAU / 60.0;
    let (q, v) = equilibrium(&g, &[t, t / g.gear_ratio, 0.0], speed).map_err(|e| anyhow::anyhow!(e))?;
    let u = [t, t / g.gear_ratio, 0.0];
    let span: f64 = 0.05;
    let model = super::profile::Timed::new(&g);
    let timed = |method: Method, h: f64| -> anyhow::Result<(f64, Driver, f64)> {
        let mut st = DynState::new(q.clone(), v.clone());
        let mut driver = Driver::new(method);
        let in_model = model.model_s();
        let start = Instant::now();
        let steps = (span / 1e-3).round() as usize;
        for k in 0..steps {
            driver.advance(&model, &mut st, k as f64 * 1e-3, 1e-3, h, 3, |_, out| {
                out.copy_from_slice(&u)
            })?;
        }
        let wall = start.elapsed().as_secs_f64();
        Ok((wall / span * 1e3, driver, (model.model_s() - in_model) / wall))
    };
    let step = 1e-3;
    let (ms_implicit, implicit, model_share) = timed(Method::Implicit(Alpha::NEWMARK), step)?;
    let (ms_rk4, _, _) = timed(Method::Rk4 { stability_limit: h_rk4 }, 0.99 * h_rk4)?;
    let s = implicit.stats;
    let per_step = |x: u64| x as f64 / s.steps as f64;
    let n = g.dofs() as f64;
    let slices = g.slice_count() as f64;
    let contact = 12.0 * slices;
    let solve = 2.0 * n * n;
    let factor = 2.0 / 3.0 * n * n * n + slices * 0.0;
    Ok(ExplicitImplicit {
        omega_max,
        rk4_limit_s: h_rk4,
        rk4_ms_per_s: ms_rk4,
        implicit_ms_per_s: ms_implicit,
        newton_per_step: per_step(s.newton_iterations),
        factorizations_per_step: per_step(s.factorizations),
        slices,
        dofs: n,
        contact_flops: contact,
        solve_flops: solve,
        factor_flops: factor,
        kflop_per_step: (per_step(s.newton_iterations) * (contact + solve) + per_step(s.factorizations) * factor) / 1e3,
        mflop_per_s: (per_step(s.newton_iterations) * (contact + solve) + per_step(s.factorizations) * factor)
            / step
            / 1e6,
        model_share,
    })
}

#[cfg(test)]
mod tests {
    use super::{REFERENCE_LABEL, VariantRow, phase_ms_per_s, phases, targets};

    #[test]
    fn phases_split_the_fmu_time_at_the_marks_the_run_passed() {
        // 30 s: 1 s of FMU time in the first 5 s, 2 s in the next 5, 6 s in the last 20
        assert_eq!(phase_ms_per_s(&[1.0, 3.0], 9.0, 30.0), [200.0, 400.0, 300.0]);
        // a run that ends at a phase's end has no later phase; one that ends inside a phase splits at the end
        assert_eq!(phase_ms_per_s(&[1.0, 3.0], 3.0, 10.0)[..2], [200.0, 400.0]);
        assert!(phase_ms_per_s(&[1.0, 3.0], 3.0, 10.0)[2].is_nan());
        assert_eq!(phase_ms_per_s(&[1.0], 2.0, 7.0)[..2], [200.0, 500.0]);
        let short = phase_ms_per_s(&[], 0.5, 1.0);
        assert_eq!(short[0], 500.0);
        assert!(short[1].is_nan() && short[2].is_nan());
    }

    fn row(label: &'static str, bearings: &'static str, full_model: bool, gearbox_s: f64) -> VariantRow {
        VariantRow {
            label,
            bearings,
            full_model,
            wall_s: 2.0 * gearbox_s,
            gearbox_s,
            gearbox_do_step_s: 0.5 * gearbox_s,
            sun_planet: 0.0,
            gear_pinion: 0.0,
            planet_upwind: 0.0,
            upwind_pressure: 0.0,
            hss_pressure: 0.0,
            fewest_rollers: 6.0,
            reference_fewest_rollers: 6.0,
            hss_rms_error: 0.0,
            phase_ms_per_s: [f64::NAN; 3],
        }
    }

    #[test]
    fn targets_take_the_fastest_full_model_row_of_each_bearing_model() {
        let rows = [
            row("35 slices, lamina", "lamina", true, 2.0),
            row("same, kept", "lamina", true, 0.4),
            // faster, but not the full model: never counts
            row("5 slices, lamina", "lamina", false, 0.01),
            row("35 slices, linear", "linear", true, 0.25),
        ];
        let text = targets(&rows, 10.0);
        assert!(
            text.contains("lamina bearings 25.0× real time (\"same, kept\"; ≥ 20×: met)"),
            "{text}"
        );
        assert!(
            text.contains("linear bearings 40.0× (\"35 slices, linear\"; ≥ 50×: not met)"),
            "{text}"
        );
        // without a reference row, no ratio to it
        assert!(!text.contains("reference"), "{text}");
        // with one, each target's row against it
        let mut referenced = rows.to_vec();
        referenced.insert(0, row(REFERENCE_LABEL, "lamina", false, 4.0));
        let text = targets(&referenced, 10.0);
        assert!(text.contains("≥ 20×: met; 10.0× the reference's speed)"), "{text}");
        assert!(text.contains("≥ 50×: not met; 16.0× the reference's speed)"), "{text}");
        // the lamina law by table counts for the lamina target
        let mut more = rows.to_vec();
        more.push(row("same, lamina-table", "lamina-table", true, 0.2));
        let text = targets(&more, 10.0);
        assert!(
            text.contains("lamina bearings 50.0× real time (\"same, lamina-table\""),
            "{text}"
        );
    }

    #[test]
    fn the_phase_table_has_a_row_per_variant_and_a_dash_where_the_run_ended() {
        let mut r = row("same, table, kept+pred.", "lamina-table", true, 1.0);
        r.phase_ms_per_s = [110.04, 230.0, f64::NAN];
        let text = phases(&[r]);
        let line = text
            .lines()
            .find(|l| l.starts_with("same, table, kept+pred."))
            .expect("the row");
        assert_eq!(
            line.split_whitespace().rev().take(3).collect::<Vec<_>>(),
            ["—", "230.0", "110.0"]
        );
    }
}
