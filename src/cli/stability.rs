//! `windrive chart stability`: where each co-simulation algorithm holds on a stiff split, measured
//! and in theory. Two splits: d-grid-step (drivetrain D's undamped 2-mass model in `torsional`, its
//! generator's electrical spring in `generator`) and d-shaft-cut (the same drivetrain cut in its main
//! shaft across two `torsional` FMUs: the rotor's inertia | the rest, free-free). The sweep is macro
//! step × coupling stiffness, every run 20 s of the rotor-torque step. A run is unstable when the
//! master stops it (divergence or non-finite values) or the coupling torque's peak over its last
//! quarter is more than twice the peak over its first (the undamped exact solution keeps its
//! amplitude). The theory ([`crate::cosim::stability`]) draws the boundary where the macro-step map
//! grows the amplitude by the same factor over the same time.

use crate::cosim::master::run_columns_with;
use crate::cosim::stability::{Scheme, Split};
use crate::cosim::{Acceleration, Algorithm, Options, Scene, param};
use crate::reference::grid_step::torsional_params;
use crate::reference::shaft_cut;
use anyhow::{Context, anyhow, bail};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive chart stability                               the map (about 1 min), results/stability-map.{png,svg,csv}\n  \
    windrive chart stability --out docs/stability-map\n  \
    windrive chart stability --split shaft                 the main shaft cut across two FMUs instead\n\n\
    Reading it: a green dot is a run that kept its amplitude, a red cross one that grew or diverged; the black line\n\
    is the theory's boundary (stable to its left). Pick the largest macro step left of the line for your coupling\n\
    stiffness; where no step is stable, use --algorithm iterative --acceleration iqn-ils.")]
pub struct StabilityArgs {
    /// The split: generator (drivetrain | the generator's electrical spring, scene d-grid-step) or
    /// shaft (the rotor | the rest of the drivetrain, cut in the main shaft, scene d-shaft-cut)
    #[arg(long, default_value = "generator", value_parser = ["generator", "shaft"])]
    pub split: String,
    /// Simulated time per run, s
    #[arg(long, default_value_t = 20.0)]
    pub stop_time: f64,
    /// Amplitude growth over the run that counts as unstable (measured and in theory)
    #[arg(long, default_value_t = 2.0)]
    pub growth: f64,
    /// Output stem: STEM.png, STEM.svg, STEM.csv
    #[arg(long, default_value = "results/stability-map")]
    pub out: PathBuf,
}

/// Macro steps (s) and coupling stiffnesses (× drivetrain D's own) of the measured grid.
const STEPS: [f64; 9] = [5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 0.1, 0.2];
const STIFFNESS: [f64; 5] = [0.1, 0.3, 1.0, 3.0, 10.0];

/// One split charted: its scene, how a stiffness factor κ reaches the scene and the theory, and the
/// coupling torque watched.
struct Case {
    scene: &'static str,
    channel: &'static str,
    /// What the split is, with its stiffness at κ = 1.
    describe: String,
    y_label: &'static str,
    title: &'static str,
    override_at: Box<dyn Fn(f64) -> crate::cosim::Override>,
    split_at: Box<dyn Fn(f64) -> Split>,
}

impl Case {
    fn new(split: &str) -> anyhow::Result<Self> {
        Ok(if split == "shaft" {
            let (rotor, drivetrain) = shaft_cut::models(1.0);
            let stiffness = Split::shaft_cut(&rotor, &drivetrain).stiffness;
            Case {
                scene: "d-shaft-cut",
                channel: "drivetrain.lss_torque",
                describe: format!(
                    "d-shaft-cut split: drivetrain D's rotor | the rest (2-mass, undamped, free-free), cut in the main shaft, \
                     K = κ·{stiffness:.3e} N·m/rad (LSS-referred)"
                ),
                y_label: "K / K_shaft",
                title: "drivetrain D cut in its main shaft: rotor | rest",
                override_at: Box::new(|kappa| param("drivetrain", "shaft_stiffness_scale", kappa)),
                split_at: Box::new(|kappa| {
                    let (rotor, drivetrain) = shaft_cut::models(kappa);
                    Split::shaft_cut(&rotor, &drivetrain)
                }),
            }
        } else {
            let built = torsional_params().build().map_err(|e| anyhow!("drivetrain D: {e}"))?;
            let k_d = built.drivetrain.k_generator;
            Case {
                scene: "d-grid-step",
                channel: "generator.generator_torque",
                describe: format!(
                    "d-grid-step split: drivetrain D 2-mass undamped | generator spring K = κ·{k_d:.3e} N·m/rad"
                ),
                y_label: "K / K_gen",
                title: "drivetrain D | generator spring",
                override_at: Box::new(move |kappa| param("generator", "stiffness", kappa * k_d)),
                split_at: Box::new(move |kappa| Split::new(&built.model, kappa * k_d)),
            }
        })
    }
}

/// The algorithms charted: label, master options, and the scheme the theory analyses (None: the
/// plain iteration's convergence factor; the IQN-ILS panel has no boundary: it converges the coupling).
fn panels() -> Vec<(&'static str, Algorithm, usize, Acceleration, Option<Scheme>)> {
    let none = Acceleration::None;
    vec![
        ("jacobi p0", Algorithm::Jacobi, 0, none, Some(Scheme::Jacobi(0))),
        ("jacobi p1", Algorithm::Jacobi, 1, none, Some(Scheme::Jacobi(1))),
        ("jacobi p2", Algorithm::Jacobi, 2, none, Some(Scheme::Jacobi(2))),
        (
            "gauss-seidel p0",
            Algorithm::GaussSeidel,
            0,
            none,
            Some(Scheme::GaussSeidel(0)),
        ),
        (
            "gauss-seidel p1",
            Algorithm::GaussSeidel,
            1,
            none,
            Some(Scheme::GaussSeidel(1)),
        ),
        (
            "gauss-seidel p2",
            Algorithm::GaussSeidel,
            2,
            none,
            Some(Scheme::GaussSeidel(2)),
        ),
        ("iterative p1", Algorithm::Iterative, 1, none, None),
        (
            "iterative iqn-ils",
            Algorithm::Iterative,
            1,
            Acceleration::IqnIls,
            Some(Scheme::Converged),
        ),
    ]
}

/// Whether a run kept its amplitude: its master finished and the last quarter's peak is within
/// `growth` of the first quarter's.
fn measured_stable(scene: &Scene, case: &Case, kappa: f64, opts: Options, growth: f64) -> anyhow::Result<bool> {
    let overrides = vec![(case.override_at)(kappa)];
    let stop = opts.stop_time;
    let run = match run_columns_with(scene, &overrides, &[case.channel], opts) {
        Ok(r) => r,
        // the master stopped a diverging coupling, or values (or an FMU's state) overflowed
        Err(e)
            if ["diverges", "not finite", "non-finite"]
                .iter()
                .any(|w| e.to_string().contains(w)) =>
        {
            return Ok(false);
        }
        Err(e) => return Err(anyhow!("{}: {e}", case.scene)),
    };
    let (t, y) = (&run.columns[0], &run.columns[1]);
    let peak = |from: f64, to: f64| {
        t.iter()
            .zip(y)
            .filter(|(t, _)| **t >= from && **t <= to)
            .map(|(_, y)| y.abs())
            .fold(0.0, f64::max)
    };
    Ok(peak(0.75 * stop, stop) <= growth * peak(0.0, 0.25 * stop))
}

pub fn run(args: &StabilityArgs) -> anyhow::Result<()> {
    if !(args.stop_time > 0.0 && args.stop_time.is_finite() && args.growth > 1.0) {
        bail!(
            "--stop-time {} --growth {}: the stop time must be a positive number of seconds, the growth a factor above 1",
            args.stop_time,
            args.growth
        );
    }
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the output folder", dir.display()))?;
    }
    let root = crate::pack::workspace_root()?;
    let case = Case::new(&args.split)?;
    let scene = Scene::open(&root.join("scenes").join(case.scene))?;
    super::run::provide_own_fmus(&scene, false)?;
    let split_at = &case.split_at;
    let fine_steps: Vec<f64> = (0..=160).map(|i| 1e-4 * 10f64.powf(i as f64 / 40.0)).collect();
    // the splits the theory reads, built once: the runs' stiffnesses (with their top mode) and a fine
    // sweep for the boundary line
    let grid: Vec<(f64, Split, f64)> = STIFFNESS
        .iter()
        .map(|&kappa| {
            let s = split_at(kappa);
            let omega = s.top_mode();
            (kappa, s, omega)
        })
        .collect();
    let fine: Vec<(f64, Split)> = (0..=40)
        .map(|i| 0.05 * 10f64.powf(i as f64 / 16.0))
        .map(|kappa| (kappa, split_at(kappa)))
        .collect();
    let (_, rated, omega_1) = grid
        .iter()
        .find(|(kappa, _, _)| *kappa == 1.0)
        .context("K_gen is on the grid")?;
    let duration = 0.75 * args.stop_time;
    println!(
        "{}; {} s per run;\n\
         unstable = diverged, or the amplitude grew more than {}× (theory: spectral radius of the macro-step map)\n",
        case.describe, args.stop_time, args.growth
    );
    println!(
        "{:<20} {:>26} {:>26} {:>10}",
        "algorithm", "largest stable H, theory", "largest stable H, runs", "agree"
    );
    let mut csv = String::from("algorithm,step_s,stiffness_factor,h_omega,stable_measured,stable_theory\n");
    let mut drawn = Vec::new();
    for (label, algorithm, order, acceleration, scheme) in panels() {
        let theory_stable = |s: &Split, h: f64| match scheme {
            Some(sc) => !s.grows(sc, h, duration, args.growth),
            None => s.iteration_factor(h) < 1.0,
        };
        let mut stable_pts = Vec::new();
        let mut unstable_pts = Vec::new();
        let (mut agree, mut total) = (0, 0);
        let mut at_rated: Vec<(f64, bool)> = Vec::new();
        for (kappa, split, omega) in &grid {
            let (kappa, omega) = (*kappa, *omega);
            for &h in &STEPS {
                let mut opts = Options::new(algorithm, h, args.stop_time);
                opts.order = order;
                opts.acceleration = acceleration;
                opts.max_iterations = 20;
                let ok = measured_stable(&scene, &case, kappa, opts, args.growth)?;
                let theory = theory_stable(split, h);
                total += 1;
                agree += usize::from(ok == theory);
                if ok {
                    stable_pts.push((h, kappa))
                } else {
                    unstable_pts.push((h, kappa))
                }
                if kappa == 1.0 {
                    at_rated.push((h, ok));
                }
                writeln!(csv, "{label},{h},{kappa},{},{ok},{theory}", h * omega)?;
            }
        }
        // the theory's boundary: per stiffness, the largest step stable at every smaller step
        let boundary: Vec<(f64, f64)> = fine
            .iter()
            .filter_map(|(kappa, s)| Split::limit(&fine_steps, |h| theory_stable(s, h)).map(|h| (h, *kappa)))
            // stable at every step charted: no boundary inside the chart
            .filter(|(h, _)| *h < fine_steps[fine_steps.len() - 1])
            .collect();
        let steps: Vec<f64> = at_rated.iter().map(|(h, _)| *h).collect();
        let limit_runs = Split::limit(&steps, |h| at_rated.iter().any(|(x, ok)| *x == h && *ok));
        let limit_theory = Split::limit(&fine_steps, |h| theory_stable(rated, h));
        let show = |h: Option<f64>, last: f64| match h {
            Some(h) if h >= last => format!("all (to {last} s)"),
            Some(h) => format!("{:.4} s (H·ω {:.2})", h, h * omega_1),
            None => "none".to_string(),
        };
        println!(
            "{label:<20} {:>26} {:>26} {:>6}/{total}",
            show(limit_theory, fine_steps[fine_steps.len() - 1]),
            show(limit_runs, STEPS[STEPS.len() - 1]),
            agree
        );
        drawn.push(super::plot::StabilityPanel {
            title: label.to_string(),
            stable: stable_pts,
            unstable: unstable_pts,
            boundary,
        });
    }
    println!(
        "(at κ = 1, ω of the top coupled mode = {:.1} rad/s; runs on the grid {:?} s)",
        omega_1, STEPS
    );
    let title = format!(
        "Co-simulation stability on a stiff split ({}): dots = runs ({} s), line = theory",
        case.title, args.stop_time
    );
    write_map(&args.out, &csv, &title, ("macro step H [s]", case.y_label), &drawn)
}

/// Writes a stability map's table (STEM.csv) and chart (STEM.png, STEM.svg) and says where.
pub fn write_map(
    stem: &std::path::Path,
    csv: &str,
    title: &str,
    (x_label, y_label): (&str, &str),
    panels: &[super::plot::StabilityPanel],
) -> anyhow::Result<()> {
    super::plot::write_chart_and_table(stem, csv, |path| {
        super::plot::stability_panels(path, title, x_label, y_label, panels)
    })
}
