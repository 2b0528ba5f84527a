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
    /// scene with lamina bearings (their law by loop and by table) and 35, 11 and 5 slices, the main shaft as one element or rigid, and linear bearings, against torsional and RK4), rainflow (counting and DELs), solvers (explicit
    /// inverse, dense LU and sparse LU on gearbox-shaped iteration matrices), coupling (every
    /// co-simulation algorithm on scenes/d-grid-step against its exact solution), states (each FMU's
    /// state size and cost, iterative against gauss-seidel on scenes/c-shutdown-spring), master (our
    /// master's overhead per FMU-step against the bare FMI calls), isolate (`run --isolate`, each FMU
    /// in its own process, against in-process on the same scenes), rotor (the blades sampling a full
    /// field against the rotor-averaged BEM, µs a step)
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
        "rotor" => {
            let blades = crate::pack::workspace_root()?.join("fmus/rotor/resources/blades");
            let setup = bench::rotor::setup(&blades.join("windpact-1.5mw"))?;
            print!("{}", bench::rotor::run(&setup)?);
            Ok(())
        }
        "master" => {
            let scene = args
                .scene
                .clone()
                .unwrap_or_else(|| std::path::PathBuf::from("scenes/bench-d-grid"));
            master(&scene, args.macro_steps)
        }
        other => {
            bail!(
                "unknown benchmark {other:?}: available: torsional, gearbox, rainflow, coupling, master, solvers, states, isolate, rotor"
            )
        }
    }
}

fn torsional(args: &BenchArgs) -> anyhow::Result<()> {
    let fmu = torsional_fmu(args.fmu.as_deref())?;
    let b = bench::torsional::run(&fmu, &args.preset, args.stop_time, args.step)?;
    print!("{b}");
    let Some(path) = &args.work_precision else {
        return Ok(());
    };
    println!("\n{}", bench::torsional::sweep_head());
    let curves = bench::torsional::work_precision(&b, |p| println!("{p}"))?;
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
    println!("{}", bench::rainflow::run(&x).to_json(x.len()));
    Ok(())
}

fn solvers() {
    println!("{}", bench::solvers::head());
    bench::solvers::run(|r| println!("{r}"));
}

fn coupling(stop_time: f64, plot: Option<&Path>) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let scene_dir = root.join("scenes").join("d-grid-step");
    provide_own_fmus(&Scene::open(&scene_dir)?, true)?;
    println!("{}", bench::coupling::head(stop_time));
    let series = bench::coupling::run(
        &scene_dir,
        stop_time,
        |label, h, o| println!("{}", bench::coupling::fixed_row(label, h, o)),
        |tol, o| println!("{}", bench::coupling::adaptive_row(tol, o)),
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
    let base = bench::gearbox::torsional_baseline(tor, stop)?;
    println!("{}", bench::gearbox::variants_head(stop));
    let mut rows = Vec::new();
    bench::gearbox::variants(six, stop, |r| {
        println!("{}", r.row(stop, &base));
        rows.push(r.clone());
    })?;
    println!("{}", bench::gearbox::variants_foot(stop, &base));
    println!("{}", bench::gearbox::targets(&rows, stop));
    println!("{}", bench::gearbox::phases(&rows));
    let stop = stop.min(30.0);
    println!("{}", bench::gearbox::part_load_head(stop));
    bench::gearbox::part_load(part, stop, |r| println!("{}", r.row(stop)))?;
    println!("{}", bench::gearbox::PART_LOAD_FOOT);
    print!("{}", bench::gearbox::explicit_against_implicit()?);
    Ok(())
}

fn states(stop: f64) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let dir = root.join("scenes").join("c-shutdown-spring");
    provide_own_fmus(&Scene::open(&dir)?, true)?;
    println!("{}", bench::states::head());
    for name in bench::states::FMUS {
        let c = bench::states::state_cost(&root.join("target").join("fmu").join(format!("{name}.fmu")))?;
        println!("{}", c.row(name));
    }
    let r = bench::states::coupled(&Scene::open(&dir)?, stop)?;
    println!("\n{}", r.report("scenes/c-shutdown-spring", stop));
    Ok(())
}

fn isolate(stop: f64) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let host = std::env::current_exe()?;
    println!("{}", bench::isolate::head());
    for (name, algorithm) in bench::isolate::CASES {
        let scene = Scene::open(&root.join("scenes").join(name))?;
        provide_own_fmus(&scene, false)?;
        let c = bench::isolate::compare(name, &scene, algorithm, stop, &host)?;
        println!("{}", c.row(name, algorithm));
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
    println!("{}", bench::master::run(&scene, steps)?.to_json(&scene.name));
    Ok(())
}
