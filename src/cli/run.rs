//! `windrive run` and `windrive pack-scene`: SSP scenes through the co-simulation master.

use crate::analysis::case::CaseSpec;
use crate::cosim::recorder::Recorder;
use crate::cosim::settings::{Missing, Settings};
use crate::cosim::summary::Summary;
use crate::cosim::{Acceleration, Algorithm, Master, Record, Scene, System};
use anyhow::{Context, anyhow, bail};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args)]
pub struct RunArgs {
    /// Scene: a folder with SystemStructure.ssd, a .ssd file or a .ssp archive
    pub scene: PathBuf,
    /// Stop time, s [default: the scene's DefaultExperiment stopTime]
    #[arg(long)]
    pub stop_time: Option<f64>,
    /// Macro (communication) step, s [default: the scene's osp:FixedStepAlgorithm baseStepSize,
    /// else the smallest DefaultExperiment stepSize of its FMUs]
    #[arg(long)]
    pub step: Option<f64>,
    /// jacobi: all FMUs step from the same inputs (threads allowed); gauss-seidel: in scene order,
    /// each FMU sees its predecessors' new outputs; iterative: Gauss–Seidel sweeps repeated from a
    /// saved FMU state until the coupled outputs settle; adaptive: the macro step follows the
    /// coupling error, rejected steps are rolled back
    #[arg(long, default_value = "gauss-seidel", value_parser = parse_algorithm)]
    pub algorithm: Algorithm,
    /// Input extrapolation order: 0 hold, 1 linear, 2 quadratic (sent as input derivatives to FMUs
    /// that can interpolate inputs, as the mean over the step to the others) [default: 0 for jacobi
    /// and gauss-seidel, 1 for iterative and adaptive]
    #[arg(long)]
    pub order: Option<usize>,
    /// Relative coupling tolerance (iterative, adaptive)
    #[arg(long, default_value_t = 1e-6)]
    pub tolerance: f64,
    /// Absolute coupling tolerance (iterative, adaptive)
    #[arg(long, default_value_t = 1e-9)]
    pub abs_tolerance: f64,
    /// Most sweeps per macro step (iterative)
    #[arg(long, default_value_t = 10)]
    pub max_iterations: usize,
    /// How iterative picks the next iterate: none (plain fixed point), aitken (dynamic
    /// relaxation) or iqn-ils (interface quasi-Newton, as preCICE); the last two converge where
    /// plain iteration diverges (a stiff split at a large step)
    #[arg(long, default_value = "none", value_parser = parse_acceleration)]
    pub acceleration: Acceleration,
    /// Stop the run as a diverging coupling when a coupled variable's amplitude grows geometrically by
    /// this factor (window peaks over 20 macro steps, each at least 1.5× the last); the message names
    /// the coupling and the remedy, every row so far is kept; inf turns the check off (fixed-step
    /// algorithms; adaptive bounds its coupling error itself)
    #[arg(long, default_value_t = crate::cosim::divergence::DEFAULT_GROWTH, value_parser = parse_growth)]
    pub divergence_growth: f64,
    /// Smallest and largest macro step (adaptive) [default: step/1000 and 100×step]
    #[arg(long)]
    pub min_step: Option<f64>,
    #[arg(long)]
    pub max_step: Option<f64>,
    /// Worker threads for the jacobi algorithm
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Results file: CSV, or Parquet when the name ends in .parquet (same columns; read as is by pandas,
    /// polars and pyarrow, and by windrive rainflow, del, ldd, spectrum, gears, bearings and life)
    /// [default: results/<scene name>.csv; with --analyse, none unless given]
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// After the run, analyse the recorded series in this process and print one JSON object on stdout:
    /// {"statistics": {...}, "simulation_s": ..., "analysis_s": ...}. SPEC is a JSON file or inline JSON
    /// naming the transient, f_eq, the channels with their Wöhler slopes and LDD bins, and optionally
    /// [gears] and [bearings] tables to rate (format: docs/CAMPAIGNS.md, "One case, one process"). The
    /// series stays in memory: no file is written unless --out is given
    #[arg(long, value_name = "SPEC")]
    pub analyse: Option<String>,
    /// Record only these variables (component.variable, comma-separated) [default: every output]
    #[arg(long, value_delimiter = ',')]
    pub record: Vec<String>,
    /// Keep every N-th communication point (the last is always kept)
    #[arg(long, default_value_t = 1)]
    pub every: u64,
    /// Set a parameter, e.g. --param torsional.preset=C (repeatable; after the scene's bindings)
    #[arg(long = "param")]
    pub params: Vec<String>,
    /// No progress bar and no summary
    #[arg(long)]
    pub quiet: bool,
    /// Run every FMU instance in a process of its own (shared-memory calls): an FMU that crashes
    /// ends the run with a message naming it, the signal and the time, and every row recorded
    /// before is kept. Costs 2–5 µs per FMU step (docs/FMU-BOUNDARY.md)
    #[arg(long)]
    pub isolate: bool,
    /// After the summary, print where the run's time went: each FMU's steps and recorded reads, the
    /// recorder, the master, and the CPU of the results writer's thread (two clock readings per FMU
    /// call timed: up to a fifth more wall time on the lightest scenes)
    #[arg(long)]
    pub profile: bool,
    /// With --isolate: an FMU whose single call takes longer than this many seconds (an endless
    /// loop) is killed and the run ends naming it [default: wait as in-process]
    #[arg(long, requires = "isolate", value_parser = parse_timeout)]
    pub call_timeout: Option<f64>,
}

fn parse_timeout(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 && x < 1e9 => Ok(x),
        _ => Err(format!("{s:?} is not a positive number of seconds")),
    }
}

fn parse_acceleration(s: &str) -> Result<Acceleration, String> {
    Acceleration::parse(s).ok_or_else(|| format!("unknown acceleration {s:?} (one of {})", Acceleration::NAMES))
}

fn parse_algorithm(s: &str) -> Result<Algorithm, String> {
    Algorithm::parse(s).ok_or_else(|| format!("unknown algorithm {s:?} (one of {})", Algorithm::NAMES))
}

#[derive(clap::Args)]
pub struct PackSceneArgs {
    /// Scene folder with SystemStructure.ssd
    pub scene: PathBuf,
    /// Output archive [default: target/ssp/<folder name>.ssp]
    #[arg(long, short)]
    pub out: Option<PathBuf>,
}

/// Our own FMUs a scene refers to are packed or refreshed in place ([`crate::pack::provide_own_fmus`]).
pub fn provide_own_fmus(scene: &Scene, refresh: bool) -> anyhow::Result<()> {
    Ok(crate::pack::provide_own_fmus(
        scene.components.iter().map(|c| c.path.as_path()),
        refresh,
    )?)
}

fn parse_growth(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(g) if g > 1.0 => Ok(g),
        _ => Err(format!(
            "{s}: a growth factor above 1 (e.g. 1000), or inf to turn the check off"
        )),
    }
}

fn parse_params(params: &[String]) -> anyhow::Result<Vec<(String, String, String)>> {
    params
        .iter()
        .map(|p| {
            let (name, value) = p
                .split_once('=')
                .ok_or_else(|| anyhow!("--param {p}: expected component.variable=value"))?;
            let (comp, var) = name
                .split_once('.')
                .ok_or_else(|| anyhow!("--param {p}: expected component.variable=value"))?;
            Ok((comp.to_string(), var.to_string(), value.to_string()))
        })
        .collect()
}

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let scene = Scene::open(&args.scene)?;
    if args.scene.is_dir() {
        provide_own_fmus(&scene, false)?;
    }
    let record = if args.record.is_empty() {
        Record::Outputs
    } else {
        Record::Only(args.record.clone())
    };
    let params = parse_params(&args.params)?;
    let mut system = if args.isolate {
        let host = std::env::current_exe().context("finding windrive's executable to host the FMUs")?;
        let mut how = crate::fmi2::host::isolate::Isolation::new(host);
        how.call_timeout = args.call_timeout.map(std::time::Duration::from_secs_f64);
        System::build_isolated(&scene, &params, &record, &how)?
    } else {
        System::build(&scene, &params, &record)?
    };
    for w in &system.warnings {
        eprintln!("warning: {w}");
    }
    let settings = Settings {
        algorithm: args.algorithm,
        step: args.step,
        stop_time: args.stop_time,
        order: args.order,
        rel_tol: args.tolerance,
        abs_tol: args.abs_tolerance,
        max_iterations: args.max_iterations,
        acceleration: args.acceleration,
        divergence_growth: args.divergence_growth,
        min_step: args.min_step,
        max_step: args.max_step,
        threads: args.threads,
    };
    let opts = settings.options(&scene, &system).map_err(|missing| match missing {
        Missing::Step => anyhow!("no step size: give --step (the scene and its FMUs declare none)"),
        Missing::StopTime => anyhow!("no stop time: give --stop-time (the scene and its FMUs declare none)"),
    })?;
    let stop = opts.stop_time;

    let analyse = args.analyse.as_deref().map(read_case_spec).transpose()?;
    let out = match (&args.out, &analyse) {
        (Some(o), _) => Some(o.clone()),
        (None, Some(_)) => None,
        (None, None) => Some(PathBuf::from("results").join(format!("{}.csv", scene.name))),
    };
    system.initialize(Some(stop))?;
    let mut recorder = Recorder::new(out.as_deref(), analyse.is_some(), &system, args.every)?;
    let shown = || out.as_ref().map_or("memory".to_string(), |o| o.display().to_string());
    let progress = (!args.quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(1000);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {percent:>3}%  t = {msg}  eta {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let t0 = system.start_time;
    if args.profile {
        crate::cosim::profile::start(&mut system);
    }
    let mut recording = std::time::Duration::ZERO;
    let wall = Instant::now();
    let cpu = crate::cosim::master::process_cpu_seconds();
    let loop_thread_cpu = crate::cosim::master::thread_cpu_seconds();
    let mut master = Master::new(&mut system, opts.clone())?;
    let mut last_tick = 0u64;
    let result = master.run(|t, sys| {
        let started = args.profile.then(Instant::now);
        recorder.observe(t, sys)?;
        if let Some(s) = started {
            recording += s.elapsed();
        }
        if let Some(bar) = &progress {
            let tick = ((t - t0) / (stop - t0) * 1000.0) as u64;
            if tick != last_tick {
                last_tick = tick;
                bar.set_position(tick);
                bar.set_message(format!("{t:.3} s"));
            }
        }
        Ok(())
    });
    let stats = master.stats.clone();
    let finishing = Instant::now();
    let flushed = match &result {
        Ok(()) => recorder
            .finish(stats.final_time, &mut system)
            .map_err(anyhow::Error::from),
        Err(_) => recorder.flush().map_err(anyhow::Error::from),
    };
    recording += finishing.elapsed();
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    let elapsed = wall.elapsed().as_secs_f64();
    let cpu_s = crate::cosim::master::process_cpu_seconds() - cpu;
    let profile = args.profile.then(|| {
        // Jacobi's workers are other threads too: their CPU is the FMUs' rows, not the writer's
        let others = cpu_s - (crate::cosim::master::thread_cpu_seconds() - loop_thread_cpu);
        let others = (opts.threads <= 1).then_some(others);
        crate::cosim::profile::Profile::of_system(&system, elapsed, recording, others, opts.threads)
    });
    system.terminate();
    if !args.quiet || result.is_err() {
        let summary = Summary {
            scene: &scene.name,
            components: system.units.len(),
            opts: &opts,
            stats: &stats,
            start_time: t0,
            wall_s: elapsed,
            cpu_s,
            results: shown(),
            rows: recorder.rows,
            columns: system.recorded.len() + 1,
        };
        eprint!("{summary}");
    }
    if let Some(p) = profile {
        eprint!("{p}");
    }
    flushed.with_context(|| format!("writing {}", shown()))?;
    if let Err(e) = result {
        match &out {
            Some(o) => bail!(
                "{e}\n(results up to t = {} s are in {})",
                recorder.last_time(),
                o.display()
            ),
            None => bail!("{e}"),
        }
    }
    if let Some(spec) = analyse {
        let series = recorder.take_series().expect("kept in memory with --analyse");
        let started = Instant::now();
        let statistics = crate::analysis::case::analyse(&series.time, &series.names, &series.columns, &spec)
            .map_err(|e| anyhow!("analysis: {e}"))?;
        let report = crate::analysis::case::Report {
            statistics: &statistics,
            simulation_s: elapsed,
            analysis_s: started.elapsed().as_secs_f64(),
        };
        println!("{}", serde_json::to_string(&report)?);
    }
    Ok(())
}

/// `--analyse SPEC`: inline JSON (starting with `{`) or a JSON file, checked before the run starts.
fn read_case_spec(text: &str) -> anyhow::Result<CaseSpec> {
    let (json, source) = if text.trim_start().starts_with('{') {
        (text.to_string(), "--analyse".to_string())
    } else {
        let json = std::fs::read_to_string(text).with_context(|| format!("--analyse {text}"))?;
        (json, format!("--analyse {text}"))
    };
    let spec: CaseSpec = serde_json::from_str(&json).map_err(|e| anyhow!("{source}: {e}"))?;
    spec.check().map_err(|e| anyhow!("{source}: {e}"))?;
    Ok(spec)
}

pub fn pack_scene(args: &PackSceneArgs) -> anyhow::Result<()> {
    let scene = Scene::open(&args.scene)?;
    if !args.scene.is_dir() {
        bail!("{}: pack-scene takes a scene folder", args.scene.display());
    }
    provide_own_fmus(&scene, true)?;
    let name = args
        .scene
        .canonicalize()?
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| scene.name.clone());
    let out = match &args.out {
        Some(o) => o.clone(),
        None => crate::pack::target_dir(&crate::pack::workspace_root()?)
            .join("ssp")
            .join(format!("{name}.ssp")),
    };
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    crate::pack::write_ssp(&args.scene, &out)?;
    println!("packed {}", out.display());
    Ok(())
}
