//! `windrive chart work-precision SCENE --vary WHAT`: error against CPU time over a grid of runs of
//! any scene, one line per method, the Pareto front marked; chart as PNG and SVG, the table as CSV.
//! The error of a run is the largest relative error of the scene's quantities of interest against
//! its reference ([`crate::reference::scene`]).

use super::study::{ERROR_FLOOR, Measured, Study};
use crate::cosim::{Acceleration, Algorithm, Options, Override, Scene, param};
use anyhow::{Context, anyhow, bail};
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

/// One run of the grid: the line it belongs to, its setting, what it changes.
struct Variant {
    line: String,
    setting: String,
    overrides: Vec<Override>,
    opts: Options,
}

const MACRO_STEPS_MS: [f64; 8] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0];
// down to below RK4's limit on the full models (57 µs for C, 2.785/ω_max of its stiffest mesh mode)
const INTERNAL_STEPS_MS: [f64; 6] = [1.0, 0.5, 0.25, 0.1, 0.05, 0.025];
pub const VARY: &str = "algorithm, macro-step, order, integrator, step, fidelity, slices";

fn variants(study: &Study, args: &WorkPrecisionArgs) -> anyhow::Result<Vec<Variant>> {
    let algorithm = Algorithm::parse(&args.algorithm)
        .ok_or_else(|| anyhow!("--algorithm {}: use one of {}", args.algorithm, Algorithm::NAMES))?;
    let stop = study.stop_time;
    let steps = |default: &[f64]| -> anyhow::Result<Vec<f64>> {
        let s = args.steps.clone().unwrap_or_else(|| default.to_vec());
        if s.is_empty() || s.iter().any(|h| !(*h > 0.0 && h.is_finite())) {
            bail!("--steps {s:?}: every step must be a positive number of milliseconds");
        }
        Ok(s.iter().map(|h| h * 1e-3).collect())
    };
    let at = |algorithm, h| Options::new(algorithm, h, stop);
    let mut out = Vec::new();
    let mut over_macro =
        |line: String, overrides: Vec<Override>, make: &dyn Fn(f64) -> Options| -> anyhow::Result<()> {
            for h in steps(&MACRO_STEPS_MS)? {
                out.push(Variant {
                    line: line.clone(),
                    setting: format!("H = {} ms", h * 1e3),
                    overrides: overrides.clone(),
                    opts: make(h),
                });
            }
            Ok(())
        };
    match args.vary.as_str() {
        "macro-step" => over_macro(args.algorithm.clone(), vec![], &|h| at(algorithm, h))?,
        "algorithm" => {
            for a in [Algorithm::Jacobi, Algorithm::GaussSeidel, Algorithm::Iterative] {
                over_macro(a.name().into(), vec![], &|h| at(a, h))?;
            }
            over_macro("iterative iqn-ils".into(), vec![], &|h| {
                let mut o = at(Algorithm::Iterative, h);
                o.acceleration = Acceleration::IqnIls;
                o
            })?;
        }
        "order" => {
            for order in 0..=2 {
                over_macro(format!("{} order {order}", algorithm.name()), vec![], &|h| {
                    let mut o = at(algorithm, h);
                    o.order = order;
                    o
                })?;
            }
        }
        "fidelity" => {
            let c = study.component_of("torsional")?;
            for f in ["2", "5", "full"] {
                over_macro(
                    format!("{f}-mass").replace("full-mass", "full"),
                    vec![param(&c, "fidelity", f)],
                    &|h| at(algorithm, h),
                )?;
            }
        }
        "integrator" | "step" => {
            let c = study.component_of("torsional")?;
            let integrators: Vec<(&str, Vec<Override>)> = if args.vary == "step" {
                vec![("scene's integrator", vec![])]
            } else {
                vec![
                    ("implicit (Newmark)", vec![param(&c, "integrator", "implicit")]),
                    (
                        "hht rho=0.6",
                        vec![param(&c, "integrator", "hht"), param(&c, "spectral_radius", 0.6)],
                    ),
                    (
                        "generalized-alpha rho=0.3",
                        vec![
                            param(&c, "integrator", "generalized-alpha"),
                            param(&c, "spectral_radius", 0.3),
                        ],
                    ),
                    ("rk4", vec![param(&c, "integrator", "rk4")]),
                ]
            };
            for (line, base) in integrators {
                for h in steps(&INTERNAL_STEPS_MS)? {
                    let mut overrides = base.clone();
                    overrides.push(param(&c, "max_internal_step", h));
                    out.push(Variant {
                        line: line.into(),
                        setting: format!("h = {} ms", h * 1e3),
                        overrides,
                        opts: at(algorithm, study.scene_step),
                    });
                }
            }
        }
        "slices" => {
            let c = study.component_of("gearbox6dof")?;
            for n in [3, 5, 11, 21, 35] {
                out.push(Variant {
                    line: "gearbox6dof slices".into(),
                    setting: format!("{n} slices"),
                    overrides: vec![param(&c, "slices", n)],
                    opts: at(algorithm, study.scene_step),
                });
            }
        }
        other => bail!("--vary {other}: use one of {VARY}"),
    }
    Ok(out)
}

/// Indices of the points (CPU time, error) no other point beats on both, cheapest first.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut front: Vec<usize> = Vec::new();
    for i in order {
        if front.last().is_none_or(|&last| points[i].1 < points[last].1) {
            front.push(i);
        }
    }
    front
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
    let study = Study::open(scene, &args.study, |_| Ok(Vec::new()))?;
    let variants = variants(&study, args)?;
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
    let reference_error = (0..study.quantities.len())
        .map(|i| study.reference.own_error(i))
        .fold(0.0, f64::max);
    let mut lines: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut all = Vec::new();
    let n = variants.len();
    let progress = std::io::stderr().is_terminal();
    for (k, v) in variants.iter().enumerate() {
        if progress {
            eprint!("\r[{}/{n}] {} {}          ", k + 1, v.line, v.setting);
        }
        let m: Measured = study.measure(&v.overrides, &v.opts, args.study.repeat);
        let worst = m.worst();
        // a run that failed or blew up (error ≥ 100 %) is listed, not drawn; nor one the reference
        // cannot resolve (error below the reference's own)
        let unresolved = m.failure.is_none() && worst <= reference_error;
        let drawn = m.failure.is_none() && worst < 1.0 && !unresolved;
        let worst_name = m
            .errors
            .iter()
            .zip(&study.quantities)
            .max_by(|a, b| a.0.total_cmp(b.0))
            .map(|(_, q)| q.name.as_str())
            .unwrap_or("");
        if progress {
            eprint!("\r{:60}\r", "");
        }
        match &m.failure {
            None => println!(
                "{:<28} {:>14} {:>11.3} {:>12.3e} {:>9}  {}{}",
                v.line,
                v.setting,
                m.cpu_s,
                worst,
                if m.within(&study.quantities) { "yes" } else { "no" },
                worst_name,
                if unresolved {
                    " (within the reference's own error: not drawn)"
                } else if drawn {
                    ""
                } else {
                    " (unstable: not drawn)"
                }
            ),
            Some(f) => println!(
                "{:<28} {:>14}  failed: {}",
                v.line,
                v.setting,
                f.lines().next().unwrap_or("")
            ),
        }
        write!(
            csv,
            "{},{},{},{},{}",
            csv_field(&v.line),
            csv_field(&v.setting),
            m.cpu_s,
            if m.failure.is_some() { f64::NAN } else { worst },
            m.within(&study.quantities)
        )?;
        for i in 0..study.quantities.len() {
            write!(csv, ",{}", m.errors.get(i).copied().unwrap_or(f64::NAN))?;
        }
        writeln!(csv, ",{}", csv_field(m.failure.as_deref().unwrap_or("")))?;
        let point = (m.cpu_s, worst.max(ERROR_FLOOR));
        let entry = match lines.iter_mut().position(|(l, _)| *l == v.line) {
            Some(i) => &mut lines[i].1,
            None => {
                lines.push((v.line.clone(), Vec::new()));
                &mut lines.last_mut().expect("just pushed").1
            }
        };
        if drawn {
            entry.push(point);
            all.push((point, k));
        }
    }
    let points: Vec<(f64, f64)> = all.iter().map(|(p, _)| *p).collect();
    let on_front = pareto_front(&points);
    let front: Vec<(f64, f64)> = on_front.iter().map(|&i| points[i]).collect();
    println!("\nPareto front (no other run is both cheaper and more accurate):");
    for &i in &on_front {
        let (p, k) = all[i];
        println!(
            "  {:<28} {:>14}  CPU {:>8.3} s  max rel err {:.3e}",
            variants[k].line, variants[k].setting, p.0, p.1
        );
    }
    let series: Vec<crate::plot::Series> = lines
        .iter()
        .filter(|(_, p)| !p.is_empty())
        .map(|(label, points)| crate::plot::Series {
            label: label.clone(),
            points,
        })
        .collect();
    let tightest = study
        .quantities
        .iter()
        .map(|q| q.tolerance)
        .fold(f64::INFINITY, f64::min);
    let title = format!("{}: work-precision, varying {}", study.scene.name, args.vary);
    crate::plot::write_chart_and_table(&stem, &csv, |path| {
        crate::plot::work_precision(path, &title, &series, &front, Some(tightest))
    })
}
