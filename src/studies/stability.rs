//! Where each co-simulation algorithm holds on a stiff split, measured and in theory (`windrive chart
//! stability` prints and draws it). Two splits: d-grid-step (drivetrain D's undamped 2-mass model in
//! `torsional`, its generator's electrical spring in `generator`) and d-shaft-cut (the same drivetrain
//! cut in its main shaft across two `torsional` FMUs: the rotor's inertia | the rest, free-free). The
//! sweep is macro step × coupling stiffness, every run the rotor-torque step. A run is unstable when
//! the master stops it (divergence or non-finite values) or the coupling torque's peak over its last
//! quarter is more than `growth` times the peak over its first (the undamped exact solution keeps its
//! amplitude). The theory ([`crate::cosim::stability`]) draws the boundary where the macro-step map
//! grows the amplitude by the same factor over the same time.

use crate::cosim::master::run_columns_with;
use crate::cosim::stability::{Scheme, Split};
use crate::cosim::{Acceleration, Algorithm, Options, Scene, param};
use crate::reference::grid_step::torsional_params;
use crate::reference::shaft_cut;
use anyhow::{Context, anyhow};

/// Macro steps (s) and coupling stiffnesses (× drivetrain D's own) of the measured grid.
pub const STEPS: [f64; 9] = [5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 0.1, 0.2];
pub const STIFFNESS: [f64; 5] = [0.1, 0.3, 1.0, 3.0, 10.0];

/// One split charted: its scene, how a stiffness factor κ reaches the scene and the theory, and the
/// coupling torque watched.
pub struct Case {
    pub scene: &'static str,
    pub channel: &'static str,
    /// What the split is, with its stiffness at κ = 1.
    pub describe: String,
    pub y_label: &'static str,
    pub title: &'static str,
    override_at: Box<dyn Fn(f64) -> crate::cosim::Override>,
    split_at: Box<dyn Fn(f64) -> Split>,
}

impl Case {
    /// `split`: "shaft" (d-shaft-cut) or anything else (d-grid-step, the generator's spring).
    pub fn new(split: &str) -> anyhow::Result<Self> {
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

/// One run of the map beside the theory.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Macro step, s.
    pub step: f64,
    /// Coupling stiffness over the split's own.
    pub stiffness: f64,
    /// The step times the top coupled mode's angular frequency at this stiffness.
    pub h_omega: f64,
    pub measured: bool,
    pub theory: bool,
}

/// One algorithm's map: every run, the theory's boundary and the largest stable step at κ = 1.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub label: &'static str,
    /// By stiffness, then step (the order of [`STIFFNESS`] and [`STEPS`]).
    pub points: Vec<Point>,
    /// The theory's boundary: per stiffness, the largest step stable at every smaller step.
    pub boundary: Vec<(f64, f64)>,
    /// Largest stable step at κ = 1 in theory (on [`Map::fine_steps`]) and in the runs (on [`STEPS`]).
    pub limit_theory: Option<f64>,
    pub limit_runs: Option<f64>,
    /// Runs whose outcome the theory predicted.
    pub agree: usize,
}

/// What every panel shares.
#[derive(Debug, Clone, PartialEq)]
pub struct Map {
    /// ω of the top coupled mode at κ = 1, rad/s.
    pub omega_1: f64,
    /// The steps the theory's boundary is searched on, s.
    pub fine_steps: Vec<f64>,
}

/// Runs the map of `case` on `scene` (its FMUs packed), `stop_time` s a run, calling `on_panel` as
/// each algorithm's panel is done (a panel is about 45 runs).
pub fn map(
    scene: &Scene,
    case: &Case,
    stop_time: f64,
    growth: f64,
    mut on_panel: impl FnMut(&Map, &Panel),
) -> anyhow::Result<(Map, Vec<Panel>)> {
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
    let shared = Map {
        omega_1: *omega_1,
        fine_steps,
    };
    let fine_steps = &shared.fine_steps;
    let duration = 0.75 * stop_time;
    let mut done = Vec::new();
    for (label, algorithm, order, acceleration, scheme) in panels() {
        let theory_stable = |s: &Split, h: f64| match scheme {
            Some(sc) => !s.grows(sc, h, duration, growth),
            None => s.iteration_factor(h) < 1.0,
        };
        let mut points = Vec::new();
        let mut at_rated: Vec<(f64, bool)> = Vec::new();
        for (kappa, split, omega) in &grid {
            let (kappa, omega) = (*kappa, *omega);
            for &h in &STEPS {
                let mut opts = Options::new(algorithm, h, stop_time);
                opts.order = order;
                opts.acceleration = acceleration;
                opts.max_iterations = 20;
                let measured = measured_stable(scene, case, kappa, opts, growth)?;
                if kappa == 1.0 {
                    at_rated.push((h, measured));
                }
                points.push(Point {
                    step: h,
                    stiffness: kappa,
                    h_omega: h * omega,
                    measured,
                    theory: theory_stable(split, h),
                });
            }
        }
        let boundary: Vec<(f64, f64)> = fine
            .iter()
            .filter_map(|(kappa, s)| Split::limit(fine_steps, |h| theory_stable(s, h)).map(|h| (h, *kappa)))
            // stable at every step charted: no boundary inside the chart
            .filter(|(h, _)| *h < fine_steps[fine_steps.len() - 1])
            .collect();
        let steps: Vec<f64> = at_rated.iter().map(|(h, _)| *h).collect();
        let panel = Panel {
            label,
            agree: points.iter().filter(|p| p.measured == p.theory).count(),
            points,
            boundary,
            limit_theory: Split::limit(fine_steps, |h| theory_stable(rated, h)),
            limit_runs: Split::limit(&steps, |h| at_rated.iter().any(|(x, ok)| *x == h && *ok)),
        };
        on_panel(&shared, &panel);
        done.push(panel);
    }
    Ok((shared, done))
}
