//! `windrive bench gearbox`: the 6-DOF GRC gearbox in drivetrain D's 30 s shutdown scene
//! (scenes/d-shutdown-6dof) through the master with lamina bearings and 35, 11 and 5 slices per
//! mesh, with the main shaft as one element or rigid, with linear bearings and at internal steps of
//! 1 and 0.5 ms, each against the 35-slice
//! lamina run at 0.25 ms without numerical damping (largest mesh forces,
//! bearing load and contact pressures, rollers in contact, HSS torque); the torsional model in the same scene
//! (scenes/d-shutdown) as the baseline measured in the same run; the integrators at part load, where
//! the teeth and rollers open and close (drivetrain C at cut-in wind, scenes/c-normal-6dof); and the
//! explicit alternative (RK4 at its stability limit) against the implicit step on the bare physics,
//! with the work per step that sets the speed.

use crate::cosim::{Algorithm, Master, Options, Record, Scene, System, param};
use crate::linear::modes::eigenpairs_of;
use crate::physics::gearbox::statics::equilibrium;
use crate::physics::gearbox::{Description, Gearbox};
use crate::solver::alpha::Alpha;
use crate::solver::{Driver, DynState, Method, rk4};
use std::path::Path;
use std::time::Instant;

/// Wall time and recorded columns of a scene run (Gauss–Seidel, 1 ms).
fn run_scene(
    dir: &Path,
    overrides: &[(String, String, String)],
    channels: &[String],
    stop: f64,
) -> anyhow::Result<(f64, Vec<Vec<f64>>)> {
    let scene = Scene::open(dir)?;
    let mut system = System::build(&scene, overrides, &Record::Only(channels.to_vec()))?;
    system.initialize(Some(stop))?;
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); channels.len()];
    let start = Instant::now();
    let mut master = Master::new(&mut system, Options::new(Algorithm::GaussSeidel, 1e-3, stop))?;
    master.run(|time, sys| {
        crate::cosim::master::read_recorded(sys, time)?;
        for (k, (_, u, i)) in sys.recorded.iter().enumerate() {
            cols[k].push(sys.units[*u].values[*i]);
        }
        Ok(())
    })?;
    Ok((start.elapsed().as_secs_f64(), cols))
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

pub fn run(stop: f64) -> anyhow::Result<()> {
    let six = Path::new("scenes/d-shutdown-6dof");
    let tor = Path::new("scenes/d-shutdown");
    for dir in [six, tor] {
        super::run::provide_own_fmus(&Scene::open(dir)?, true)?;
    }
    let names = [
        "hss_torque",
        "mesh_force_sun_planet_1",
        "mesh_force_gear_pinion_2",
        "planet_1_uw_radial_load",
        "planet_1_uw_rollers_in_contact",
        "planet_1_uw_inner_race_pressure",
        "max_contact_pressure_gear_pinion_2",
    ];
    let channels = |c: &str| names.iter().map(|n| format!("{c}.{n}")).collect::<Vec<_>>();
    let (t_tor, _) = run_scene(tor, &[], &channels("torsional")[..3], stop)?;
    println!(
        "drivetrain D shutdown scene, {stop} s at 1 ms through the master (Gauss–Seidel); reference: 35 slices with \
         lamina bearings at a 0.25 ms internal step with Newmark's average acceleration (no numerical damping); rows: the \
         FMU's default HHT-α (ρ∞ = 0.8) at 1 ms unless named; baseline: torsional full fidelity"
    );
    println!(
        "{:<24} {:>9} {:>7} {:>11} {:>11} {:>11} {:>11} {:>9} {:>11} {:>11} {:>10}",
        "variant",
        "ms per s",
        "× real",
        "÷ torsional",
        "sun-planet",
        "gear-pinion",
        "planet UW",
        "min rollr",
        "UW p_max",
        "HSS p_H",
        "HSS RMS"
    );
    let mut reference: Option<Vec<Vec<f64>>> = None;
    // the reference is the full model at a quarter of the FMU's default internal step (1 ms): its
    // differences are the errors of each row, the step's included
    let variants: [(&str, usize, &str, f64, &str, MainShaft); 9] = [
        (
            "reference: 0.25 ms",
            35,
            "lamina",
            2.5e-4,
            "implicit",
            MainShaft::Preset,
        ),
        ("35 slices, lamina", 35, "lamina", 1e-3, "hht", MainShaft::Preset),
        ("same, Newmark", 35, "lamina", 1e-3, "implicit", MainShaft::Preset),
        ("same, 0.5 ms", 35, "lamina", 5e-4, "hht", MainShaft::Preset),
        ("11 slices, lamina", 11, "lamina", 1e-3, "hht", MainShaft::Preset),
        ("5 slices, lamina", 5, "lamina", 1e-3, "hht", MainShaft::Preset),
        ("main shaft 1 element", 35, "lamina", 1e-3, "hht", MainShaft::OneElement),
        ("rigid main shaft", 35, "lamina", 1e-3, "hht", MainShaft::Rigid),
        ("35 slices, linear", 35, "linear", 1e-3, "hht", MainShaft::Preset),
    ];
    for (label, slices, bearings, step, integrator, shaft) in variants {
        let mut o = vec![
            param("gearbox", "slices", slices),
            param("gearbox", "bearing_model", bearings),
            param("gearbox", "max_internal_step", step),
            param("gearbox", "integrator", integrator),
        ];
        if let Some(file) = shaft.description()? {
            o.push(param("gearbox", "gearbox", file.display()));
        }
        let (wall, cols) = run_scene(six, &o, &channels("gearbox"), stop)?;
        let r = reference.get_or_insert_with(|| cols.clone());
        let rel = |k: usize| format!("{:+.2}%", 100.0 * (peak(&cols[k]) / peak(&r[k]) - 1.0));
        // the fewest rollers carrying the upwind planet bearing in normal operation (1 s to the trip
        // at 5 s; the shutdown takes every bearing through zero load)
        let fewest = |c: &[f64]| c.iter().take(5000).skip(1000).fold(f64::MAX, |m, &x| m.min(x));
        println!(
            "{label:<24} {:>9.1} {:>7.2} {:>11.0} {:>11} {:>11} {:>11} {:>4.0} ({:.0}) {:>11} {:>11} {:>9.3}%",
            wall / stop * 1e3,
            stop / wall,
            wall / t_tor,
            rel(1),
            rel(2),
            rel(3),
            fewest(&cols[4]),
            fewest(&r[4]),
            rel(5),
            rel(6),
            100.0 * rms_error(&cols[0], &r[0]),
        );
    }
    println!(
        "torsional: {:.2} ms per simulated s ({:.0}× real time); columns: peak differences against the reference \
         (min rollr: fewest rollers carrying planet 1's upwind bearing in normal operation, the reference's in \
         brackets; linear bearings report none)\n",
        t_tor / stop * 1e3,
        stop / t_tor
    );
    part_load(stop.min(30.0))?;
    explicit_against_implicit()
}

/// Drivetrain C at cut-in wind (4 m/s, the rotor's torque under 1 % of rated): the teeth and the
/// roller sets open and close. Newmark's rule keeps every mode's amplitude, so at 1 ms the contacts'
/// stiff modes, which the step cannot resolve, ring from step to step; HHT-α damps them. The
/// reference is Newmark at 0.25 ms. The first half of the run (15 s of the default 30 s: the rotor
/// slowing from rated speed) is left out.
fn part_load(stop: f64) -> anyhow::Result<()> {
    let dir = Path::new("scenes/c-normal-6dof");
    super::run::provide_own_fmus(&Scene::open(dir)?, true)?;
    let channels = [
        "gearbox.hss_torque",
        "gearbox.mesh_force_gear_pinion_1",
        "gearbox.generator_speed",
    ]
    .map(String::from);
    let skip = (stop * 1e3) as usize / 2;
    println!(
        "part load: drivetrain C at 4 m/s (scenes/c-normal-6dof, c2mw), {stop} s, after {} s; reference: Newmark at 0.25 ms",
        skip as f64 * 1e-3
    );
    println!(
        "{:<24} {:>9} {:>12} {:>12} {:>14} {:>16}",
        "integrator", "ms per s", "HSS T p99", "HSS T max", "IMS mesh max", "gen speed jitter"
    );
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
        let (wall, cols) = run_scene(dir, &o, &channels, stop)?;
        let cols: Vec<Vec<f64>> = cols.into_iter().map(|c| c[skip.min(c.len())..].to_vec()).collect();
        let p99 = |x: &[f64]| {
            let mut a: Vec<f64> = x.iter().map(|v| v.abs()).collect();
            a.sort_by(f64::total_cmp);
            a.get(a.len() * 99 / 100).copied().unwrap_or(0.0)
        };
        // the step-to-step change of the generator's speed: rad/s from one millisecond to the next
        let jitter = |x: &[f64]| {
            let d: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
            (d.iter().map(|v| v * v).sum::<f64>() / d.len().max(1) as f64).sqrt()
        };
        println!(
            "{label:<24} {:>9.1} {:>12.0} {:>12.0} {:>14.0} {:>16.4}",
            wall / stop * 1e3,
            p99(&cols[0]),
            peak(&cols[0]),
            peak(&cols[1]),
            jitter(&cols[2]),
        );
    }
    println!(
        "HSS T: HSS torque, N·m; IMS mesh: the first parallel stage's mesh force, N; gen speed jitter: RMS \
         change of the generator's speed per millisecond, rad/s\n"
    );
    Ok(())
}

/// RK4 at its stability limit against the implicit 1 ms step (the default step; Newmark, which at
/// rated torque costs what the default HHT-α costs), both on the bare 35-slice physics at rated
/// torque, and the work per implicit step.
fn explicit_against_implicit() -> anyhow::Result<()> {
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
    let timed = |method: Method, h: f64| -> anyhow::Result<(f64, Driver)> {
        let mut st = DynState::new(q.clone(), v.clone());
        let mut driver = Driver::new(method);
        let start = Instant::now();
        let steps = (span / 1e-3).round() as usize;
        for k in 0..steps {
            driver.advance(&g, &mut st, k as f64 * 1e-3, 1e-3, h, 3, |_, out| {
                out.copy_from_slice(&u)
            })?;
        }
        Ok((start.elapsed().as_secs_f64() / span * 1e3, driver))
    };
    let step = 1e-3;
    let (ms_implicit, implicit) = timed(Method::Implicit(Alpha::NEWMARK), step)?;
    let (ms_rk4, _) = timed(Method::Rk4 { stability_limit: h_rk4 }, 0.99 * h_rk4)?;
    println!(
        "explicit against implicit (35 slices, linear bearings, rated torque, bare physics): the stiffest mode is {:.0} Hz, so RK4 \
         needs h ≤ {:.2e} s: {:.0} ms per simulated s; Newmark at 1 ms: {:.1} ms per s ({:.0}× faster; the default step)",
        omega_max / std::f64::consts::TAU,
        h_rk4,
        ms_rk4,
        ms_implicit,
        ms_rk4 / ms_implicit
    );
    let s = implicit.stats;
    let per_step = |x: u64| x as f64 / s.steps as f64;
    let n = g.dofs() as f64;
    let slices = g.slice_count() as f64;
    let contact = 12.0 * slices;
    let solve = 2.0 * n * n;
    let factor = 2.0 / 3.0 * n * n * n + slices * 0.0;
    println!(
        "work per implicit step: {:.2} Newton iterations, {:.3} factorisations; per iteration the contact \
         sums cost ≈ {:.0} flops ({} slices) and the dense back-substitution {:.0} flops ({} DOFs); a \
         factorisation {:.0} flops. Physical limit: ≈ {:.0} kflop per step, {:.1} Mflop per simulated s",
        per_step(s.newton_iterations),
        per_step(s.factorizations),
        contact,
        slices,
        solve,
        n,
        factor,
        (per_step(s.newton_iterations) * (contact + solve) + per_step(s.factorizations) * factor) / 1e3,
        (per_step(s.newton_iterations) * (contact + solve) + per_step(s.factorizations) * factor) / step / 1e6,
    );
    Ok(())
}
