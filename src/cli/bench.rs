//! `windrive bench TARGET`: parses, runs one of the benchmarks of [`crate::bench`] and prints its
//! table (and, for torsional and coupling, draws its work-precision chart).

use super::run::provide_own_fmus;
use super::step::torsional_fmu;
use crate::bench;
use crate::cosim::Scene;
use crate::plot;
use anyhow::bail;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct BenchArgs {
    /// What to benchmark: torsional (the FMU), gearbox (the 6-DOF gearbox in drivetrain D's shutdown
    /// scene with lamina bearings and 35, 11 and 5 slices, the main shaft as one element or rigid, and linear bearings, against torsional and RK4), rainflow (counting and DELs), solvers (explicit
    /// inverse, dense LU and sparse LU on gearbox-shaped iteration matrices), coupling (every
    /// co-simulation algorithm on scenes/d-grid-step against its exact solution), states (each FMU's
    /// state size and cost, iterative against gauss-seidel on scenes/c-shutdown-spring), master (our
    /// master's overhead per FMU-step against the bare FMI calls), isolate (`run --isolate`, each FMU
    /// in its own process, against in-process on the same scenes)
    pub target: String,
    #[arg(long, default_value = "D")]
    pub preset: String,
    #[arg(long, default_value_t = 30.0)]
    pub stop_time: f64,
    #[arg(long, default_value_t = 1e-3)]
    pub step: f64,
    /// Use this .fmu instead of packing target/fmu/torsional.fmu
    #[arg(long)]
    pub fmu: Option<PathBuf>,
    /// Also sweep internal step sizes of both integrators and plot error against CPU time (.png/.svg)
    #[arg(long)]
    pub work_precision: Option<PathBuf>,
    /// rainflow: the series as raw little-endian f64 (benches/rainflow.py writes it and compares
    /// with the Python packages); without it a seeded random walk of --samples points
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// master: the scene [default: scenes/bench-d-grid]
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// master: macro steps per run
    #[arg(long, default_value_t = 100_000)]
    pub macro_steps: u64,
    /// rainflow: length of the generated random walk
    #[arg(long, default_value_t = 10_000_000)]
    pub samples: usize,
}

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    match args.target.as_str() {
        "torsional" => torsional(args),
        "rainflow" => rainflow(args),
        "solvers" => {
            solvers();
            Ok(())
        }
        "coupling" => coupling(args.stop_time, args.work_precision.as_deref()),
        "gearbox" => gearbox(args.stop_time),
        "states" => states(args.stop_time),
        "isolate" => isolate(args.stop_time),
        "master" => {
            let scene = args
                .scene
                .clone()
                .unwrap_or_else(|| std::path::PathBuf::from("scenes/bench-d-grid"));
            master(&scene, args.macro_steps)
        }
        other => {
            bail!(
                "unknown benchmark {other:?}: available: torsional, gearbox, rainflow, coupling, master, solvers, states, isolate"
            )
        }
    }
}

fn torsional(args: &BenchArgs) -> anyhow::Result<()> {
    let fmu = torsional_fmu(args.fmu.as_deref())?;
    let b = bench::torsional::run(&fmu, &args.preset, args.stop_time, args.step)?;
    println!(
        "Drivetrain {} full fidelity, rated-torque step, {} s at {} s communication steps ({} steps)",
        args.preset, args.stop_time, args.step, b.steps
    );
    println!(
        "reference: RK4 at {:.1} µs; against RK4 at {:.1} µs it differs by {:.1e} of its peak (trajectory)",
        0.25 * b.rk4_limit * 1e6,
        0.5 * b.rk4_limit * 1e6,
        b.reference_check
    );
    println!();
    println!(
        "{:<44} {:>12} {:>14} {:>12} {:>12}",
        "run", "real time x", "steps/s", "peak error", "RMS error"
    );
    for (label, t) in [
        ("FMU through FMI (implicit, default settings)".to_string(), &b.fmi),
        ("same model, no FMI boundary".to_string(), &b.native),
        (
            format!("RK4 at 0.9 x stability limit ({:.1} µs)", 0.9 * b.rk4_limit * 1e6),
            &b.rk4,
        ),
    ] {
        println!(
            "{:<44} {:>12.0} {:>14.0} {:>12.2e} {:>12.2e}",
            label,
            b.real_time_factor(t),
            b.steps / t.wall_s,
            t.peak_error,
            t.rms_error
        );
    }
    let met = |yes: bool| if yes { "met" } else { "NOT met" };
    println!();
    println!(
        "ratios: FMI overhead {:.2}x the bare model; implicit {:.1}x faster than RK4; target >= {}x real time: {}",
        b.fmi.wall_s / b.native.wall_s,
        b.rk4.wall_s / b.fmi.wall_s,
        bench::torsional::REAL_TIME_TARGET,
        met(b.real_time_factor(&b.fmi) >= bench::torsional::REAL_TIME_TARGET)
    );
    let target = bench::torsional::ACCURACY_TARGET;
    println!(
        "accuracy target: HSS torque peak and RMS within {} % of the reference: {}",
        target * 100.0,
        met(b.fmi.peak_error <= target && b.fmi.rms_error <= target)
    );
    let Some(path) = &args.work_precision else {
        return Ok(());
    };
    println!();
    println!("work-precision sweep (bare model, best of 3 per point)");
    println!(
        "{:<10} {:>14} {:>12} {:>12}",
        "integrator", "internal step", "CPU time / s", "max error"
    );
    let curves = bench::torsional::work_precision(&b, |p| {
        println!(
            "{:<10} {:>11.1} µs {:>12.4} {:>12.2e}",
            p.integrator,
            p.step_s * 1e6,
            p.wall_s,
            p.error
        )
    })?;
    let title = bench::torsional::work_precision_title(&b.scenario.preset, b.scenario.stop_time);
    let axes = ("log10 CPU time / s", "log10 (max |error| / peak)");
    match plot::named_lines(path, &title, axes.0, axes.1, &curves, &[]) {
        Ok(()) => println!("work-precision chart: {}", path.display()),
        Err(e) => println!("work-precision chart skipped: {e:#}"),
    }
    Ok(())
}

/// One JSON line: seconds (best of 3, counting and DELs only), cycle count and checksums.
fn rainflow(args: &BenchArgs) -> anyhow::Result<()> {
    let x = match &args.input {
        Some(path) => bench::rainflow::read_series(path)?,
        None => bench::rainflow::random_walk(args.samples),
    };
    let c = bench::rainflow::run(&x);
    let dels = &c.dels;
    println!(
        "{}",
        serde_json::json!({"samples": x.len(), "seconds": c.seconds, "cycles": c.cycles, "sum_count_range": c.sum_count_range,
            "sum_count": c.sum_count, "del": {"3": dels[0], "6": dels[1], "9": dels[2]}})
    );
    Ok(())
}

/// Times per call, and ratios against dense LU (> 1: faster).
fn solvers() {
    println!("block-sparse iteration matrices of 6-DOF bodies; times per call, ratios against dense LU (> 1: faster)");
    println!(
        "{:>5} {:>6} {:>13} {:>10} {:>10} {:>12} {:>10} {:>10}  chosen (reused / once)",
        "DOFs", "fill", "LU f+s / µs", "inverse", "sparse", "LU s / µs", "inverse", "sparse"
    );
    bench::solvers::run(|r| {
        let (fs, s) = (&r.factor_solve, &r.solve);
        println!(
            "{:>5} {:>5.1}% {:>13.1} {:>10.2} {:>10.2} {:>12.2} {:>10.2} {:>10.2}  {:?} / {:?}",
            r.dofs,
            r.fill_percent,
            fs[0] * 1e6,
            fs[0] / fs[1],
            fs[0] / fs[2],
            s[0] * 1e6,
            s[0] / s[1],
            s[0] / s[2],
            r.chosen_reused,
            r.chosen_once
        );
    });
}

fn coupling(stop_time: f64, plot: Option<&Path>) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let scene_dir = root.join("scenes").join("d-grid-step");
    provide_own_fmus(&Scene::open(&scene_dir)?, true)?;
    println!(
        "d-grid-step: drivetrain D (2-mass, undamped) + generator spring K_gen = 2.81e4 N·m/rad, {} s;\n\
         error = max |T_gen − exact| / max |exact| (exact: modal solution); stiffest coupled mode 5.89 Hz (ω = 37.0 rad/s)\n",
        stop_time
    );
    println!(
        "{:<17} {:>9} {:>8} {:>12} {:>10} {:>8}",
        "algorithm", "step [s]", "H·ω", "error", "wall [ms]", "sweeps"
    );
    let series = bench::coupling::run(
        &scene_dir,
        stop_time,
        |label, h, o| {
            let error = match (&o.error, &o.failure) {
                (Some(e), _) if *e < 1.0 => format!("{e:.3e}"),
                (Some(e), _) => format!("unstable ({e:.1e})"),
                (None, Some(f)) => format!("failed: {}", f.chars().take(50).collect::<String>()),
                _ => unreachable!(),
            };
            println!(
                "{label:<17} {h:>9} {:>8.3} {error:>12} {:>10.2} {:>8}",
                h * bench::coupling::OMEGA_RAD_S,
                o.wall_s * 1e3,
                o.stats.sweeps
            );
        },
        |tol, o| {
            println!(
                "{:<17} {:>9} {:>8} {:>12} {:>10.2} {:>8}  ({} steps, {} rejected)",
                format!("adaptive {tol:.0e}"),
                "-",
                "-",
                o.error.map_or("failed".into(), |e| format!("{e:.3e}")),
                o.wall_s * 1e3,
                o.stats.sweeps,
                o.stats.steps,
                o.stats.rejected
            );
        },
    )?;
    if let Some(path) = plot {
        plot::named_lines(
            path,
            "d-grid-step (drivetrain D + generator spring): co-simulation error vs wall time",
            "log10 wall time / s",
            "log10 (max |error| / peak), stable runs",
            &series,
            &[],
        )?;
        println!("\nwork-precision chart: {}", path.display());
    }
    Ok(())
}

fn gearbox(stop: f64) -> anyhow::Result<()> {
    let six = Path::new("scenes/d-shutdown-6dof");
    let tor = Path::new("scenes/d-shutdown");
    let part = Path::new("scenes/c-normal-6dof");
    for dir in [six, tor, part] {
        provide_own_fmus(&Scene::open(dir)?, true)?;
    }
    let t_tor = bench::gearbox::torsional_baseline(tor, stop)?;
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
    bench::gearbox::variants(six, stop, |r| {
        println!(
            "{:<24} {:>9.1} {:>7.2} {:>11.0} {:>11} {:>11} {:>11} {:>4.0} ({:.0}) {:>11} {:>11} {:>9.3}%",
            r.label,
            r.wall_s / stop * 1e3,
            stop / r.wall_s,
            r.wall_s / t_tor,
            percent(r.sun_planet),
            percent(r.gear_pinion),
            percent(r.planet_upwind),
            r.fewest_rollers,
            r.reference_fewest_rollers,
            percent(r.upwind_pressure),
            percent(r.hss_pressure),
            r.hss_rms_error,
        )
    })?;
    println!(
        "torsional: {:.2} ms per simulated s ({:.0}× real time); columns: peak differences against the reference \
         (min rollr: fewest rollers carrying planet 1's upwind bearing in normal operation, the reference's in \
         brackets; linear bearings report none)\n",
        t_tor / stop * 1e3,
        stop / t_tor
    );
    let stop = stop.min(30.0);
    println!(
        "part load: drivetrain C at 4 m/s (scenes/c-normal-6dof, c2mw), {stop} s, after {} s; reference: Newmark at 0.25 ms",
        bench::gearbox::part_load_skipped_steps(stop) as f64 * 1e-3
    );
    println!(
        "{:<24} {:>9} {:>12} {:>12} {:>14} {:>16}",
        "integrator", "ms per s", "HSS T p99", "HSS T max", "IMS mesh max", "gen speed jitter"
    );
    bench::gearbox::part_load(part, stop, |r| {
        println!(
            "{:<24} {:>9.1} {:>12.0} {:>12.0} {:>14.0} {:>16.4}",
            r.label,
            r.wall_s / stop * 1e3,
            r.hss_p99,
            r.hss_max,
            r.mesh_max,
            r.speed_jitter,
        )
    })?;
    println!(
        "HSS T: HSS torque, N·m; IMS mesh: the first parallel stage's mesh force, N; gen speed jitter: RMS \
         change of the generator's speed per millisecond, rad/s\n"
    );
    let e = bench::gearbox::explicit_against_implicit()?;
    println!(
        "explicit against implicit (35 slices, linear bearings, rated torque, bare physics): the stiffest mode is {:.0} Hz, so RK4 \
         needs h ≤ {:.2e} s: {:.0} ms per simulated s; Newmark at 1 ms: {:.1} ms per s ({:.0}× faster; the default step)",
        e.omega_max / std::f64::consts::TAU,
        e.rk4_limit_s,
        e.rk4_ms_per_s,
        e.implicit_ms_per_s,
        e.rk4_ms_per_s / e.implicit_ms_per_s
    );
    println!(
        "work per implicit step: {:.2} Newton iterations, {:.3} factorisations; per iteration the contact \
         sums cost ≈ {:.0} flops ({} slices) and the dense back-substitution {:.0} flops ({} DOFs); a \
         factorisation {:.0} flops. Physical limit: ≈ {:.0} kflop per step, {:.1} Mflop per simulated s",
        e.newton_per_step,
        e.factorizations_per_step,
        e.contact_flops,
        e.slices,
        e.solve_flops,
        e.dofs,
        e.factor_flops,
        e.kflop_per_step,
        e.mflop_per_s,
    );
    Ok(())
}

/// A peak difference, %, with its sign.
fn percent(x: f64) -> String {
    format!("{x:+.2}%")
}

fn states(stop: f64) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let dir = root.join("scenes").join("c-shutdown-spring");
    provide_own_fmus(&Scene::open(&dir)?, true)?;
    println!(
        "{:<12} {:>16} {:>15} {:>26} {:>21}",
        "FMU", "serialised bytes", "get + free, µs", "update in place + set, µs", "serialise + load, µs"
    );
    for name in bench::states::FMUS {
        let c = bench::states::state_cost(&root.join("target").join("fmu").join(format!("{name}.fmu")))?;
        println!(
            "{name:<12} {:>16} {:>15.3} {:>26.3} {:>21.1}",
            c.bytes, c.take_us, c.roll_back_us, c.round_trip_us
        );
    }
    let r = bench::states::coupled(&Scene::open(&dir)?, stop)?;
    let (gs, gs1, it, it0) = (r.gauss_seidel, r.gauss_seidel_order_1, r.iterative, r.iterative_order_0);
    let sweeps = it.sweeps_per_step();
    println!(
        "\nscenes/c-shutdown-spring, {stop} s at 1 ms, best of 7 each:\n  gauss-seidel (order 0, the default; the baseline) {:.4} s\n  \
         gauss-seidel with order-1 inputs                  {:.4} s\n  iterative (order 1, the default)                  {:.4} s, \
         {sweeps:.2} sweeps per step\niterative / gauss-seidel: {:.2}× ({:.2}× per sweep); against gauss-seidel with the same \
         order-1 inputs: {:.2}×\niterative with order-0 inputs: {:.4} s, {:.2} sweeps per step, {:.2}× gauss-seidel at the same order",
        gs.wall_s,
        gs1.wall_s,
        it.wall_s,
        it.wall_s / gs.wall_s,
        it.wall_s / gs.wall_s / sweeps,
        it.wall_s / gs1.wall_s,
        it0.wall_s,
        it0.sweeps_per_step(),
        it0.wall_s / gs.wall_s,
    );
    Ok(())
}

fn isolate(stop: f64) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let host = std::env::current_exe()?;
    println!(
        "{:<18} {:<13} {:>5} {:>22} {:>20} {:>12} {:>8}",
        "scene", "algorithm", "FMUs", "in-process µs/FMU-step", "isolated µs/FMU-step", "added µs", "ratio"
    );
    for (name, algorithm) in bench::isolate::CASES {
        let scene = Scene::open(&root.join("scenes").join(name))?;
        provide_own_fmus(&scene, false)?;
        let c = bench::isolate::compare(name, &scene, algorithm, stop, &host)?;
        println!(
            "{name:<18} {:<13} {:>5} {:>22.2} {:>20.2} {:>12.2} {:>7.2}×",
            algorithm.name(),
            c.fmus,
            c.per_fmu_step_us(c.in_process_s),
            c.per_fmu_step_us(c.isolated_s),
            c.per_fmu_step_us(c.isolated_s - c.in_process_s),
            c.isolated_s / c.in_process_s
        );
    }
    println!("({stop} s of each scene, best of 5, runs alternating; results identical both ways)");
    Ok(())
}

/// One JSON line.
fn master(scene_dir: &Path, steps: u64) -> anyhow::Result<()> {
    let scene = Scene::open(scene_dir)?;
    if scene_dir.is_dir() {
        provide_own_fmus(&scene, false)?;
    }
    let o = bench::master::run(&scene, steps)?;
    let per = |s: f64| o.per_fmu_step_us(s);
    println!(
        "{}",
        serde_json::json!({
            "scene": scene.name, "fmus": o.fmus, "macro_steps": o.macro_steps, "step_s": o.step_s,
            "master_s": o.master_s, "bare_fmi_loop_s": o.bare_fmi_loop_s,
            "master_us_per_fmu_step": per(o.master_s), "bare_us_per_fmu_step": per(o.bare_fmi_loop_s),
            "overhead_us_per_fmu_step": per(o.master_s - o.bare_fmi_loop_s),
        })
    );
    Ok(())
}
