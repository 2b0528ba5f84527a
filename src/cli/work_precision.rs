//! `windrive chart work-precision SCENE --vary WHAT`: error against CPU time over a grid of runs of
//! any scene, one line per method, the Pareto front marked; chart as PNG and SVG, the table as CSV.
//! The study is [`crate::studies::work_precision`].

use crate::cosim::Scene;
use crate::studies::work_precision::{self, Shown, VARY, variants};
use anyhow::{Context, bail};
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive chart work-precision scenes/c-shutdown --vary algorithm       every algorithm over macro steps 0.25-32 ms (about 2 min)\n  \
    windrive chart work-precision scenes/c-normal --vary fidelity          2-mass, 5-mass and full torsional model\n  \
    windrive chart work-precision scenes/c-shutdown --vary integrator --algorithm iterative\n  \
    windrive chart work-precision scenes/c-shutdown-spring --vary order --steps 0.5,1,2 --repeat 1\n\n\
    The chart, its SVG and the table go to --out (default results/work-precision/SCENE-WHAT.{png,svg,csv}).\n\
    The scene's quantities of interest come from quantities.toml beside it (format: scenes/c-shutdown/quantities.toml).")]
pub struct WorkPrecisionArgs {
    /// Scene: a folder with SystemStructure.ssd, a .ssd file or a .ssp archive
    pub scene: PathBuf,
    /// What varies: algorithm (one line per co-simulation algorithm over macro steps), macro-step (the
    /// --algorithm over macro steps), order (input extrapolation 0/1/2 over macro steps), integrator (the
    /// torsional FMU's integrators over internal steps), step (the scene's integrator over internal
    /// steps), fidelity (2-mass, 5-mass, full over macro steps) or slices (gearbox6dof's slices per mesh)
    #[arg(long)]
    pub vary: String,
    /// Macro steps (--vary algorithm, macro-step, order, fidelity) or internal steps (integrator, step), ms
    #[arg(long, value_delimiter = ',')]
    pub steps: Option<Vec<f64>>,
    /// Algorithm of the runs that do not vary it
    #[arg(long, default_value = "gauss-seidel")]
    pub algorithm: String,
    #[command(flatten)]
    pub study: super::study::StudyArgs,
    /// Output stem: writes STEM.png, STEM.svg and STEM.csv [default: results/work-precision/SCENE-WHAT]
    #[arg(long)]
    pub out: Option<PathBuf>,
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub fn run(args: &WorkPrecisionArgs) -> anyhow::Result<()> {
    if args.study.repeat == 0 {
        bail!("--repeat 0: at least one run per grid point");
    }
    let scene = Scene::open(&args.scene)?;
    let stem = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("results/work-precision").join(format!("{}-{}", scene.name, args.vary)));
    if let Some(dir) = stem.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the output folder", dir.display()))?;
    }
    if !VARY.split(", ").any(|v| v == args.vary) {
        bail!("--vary {}: use one of {VARY}", args.vary);
    }
    let study = args.study.open(scene, Vec::new())?;
    let variants = variants(&study, &args.vary, args.steps.as_deref(), &args.algorithm)?;
    print!("{}", study.describe_reference());
    println!(
        "\n{:<28} {:>14} {:>11} {:>12} {:>9}  worst quantity",
        "method", "setting", "CPU [s]", "max rel err", "in tol"
    );
    let mut csv = String::from("method,setting,cpu_s,max_relative_error,within_tolerance");
    for q in &study.quantities {
        write!(csv, ",{}", csv_field(&format!("error {}", q.name)))?;
    }
    csv += ",failure\n";
    let n = variants.len();
    let progress = std::io::stderr().is_terminal();
    let qs = &study.quantities;
    let chart = work_precision::run(
        &study,
        &variants,
        args.study.repeat,
        |k, v| {
            if progress {
                eprint!("\r[{}/{n}] {} {}          ", k + 1, v.line, v.setting);
            }
        },
        |v, p| {
            if progress {
                eprint!("\r{:60}\r", "");
            }
            let m = &p.measured;
            match &m.failure {
                None => println!(
                    "{:<28} {:>14} {:>11.3} {:>12.3e} {:>9}  {}{}",
                    v.line,
                    v.setting,
                    m.cpu_s,
                    p.worst,
                    if m.within(qs) { "yes" } else { "no" },
                    m.worst_quantity(qs),
                    match p.shown {
                        Shown::Unresolved => " (within the reference's own error: not drawn)",
                        Shown::Drawn => "",
                        Shown::Unstable => " (unstable: not drawn)",
                    }
                ),
                Some(f) => println!(
                    "{:<28} {:>14}  failed: {}",
                    v.line,
                    v.setting,
                    f.lines().next().unwrap_or("")
                ),
            }
            let worst = if m.failure.is_some() { f64::NAN } else { p.worst };
            let _ = write!(
                csv,
                "{},{},{},{},{}",
                csv_field(&v.line),
                csv_field(&v.setting),
                m.cpu_s,
                worst,
                m.within(qs)
            );
            for i in 0..qs.len() {
                let _ = write!(csv, ",{}", m.errors.get(i).copied().unwrap_or(f64::NAN));
            }
            let _ = writeln!(csv, ",{}", csv_field(m.failure.as_deref().unwrap_or("")));
        },
    );
    println!("\nPareto front (no other run is both cheaper and more accurate):");
    for &(k, p) in &chart.front {
        println!(
            "  {:<28} {:>14}  CPU {:>8.3} s  max rel err {:.3e}",
            variants[k].line, variants[k].setting, p.0, p.1
        );
    }
    let front: Vec<(f64, f64)> = chart.front.iter().map(|(_, p)| *p).collect();
    let lines: Vec<(String, Vec<(f64, f64)>)> = chart.lines.into_iter().filter(|(_, p)| !p.is_empty()).collect();
    let tightest = qs.iter().map(|q| q.tolerance).fold(f64::INFINITY, f64::min);
    let title = format!("{}: work-precision, varying {}", study.scene.name, args.vary);
    crate::plot::write_chart_and_table(&stem, &csv, |path| {
        crate::plot::work_precision(path, &title, &lines, &front, Some(tightest))
    })
}
