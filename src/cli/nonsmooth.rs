//! `windrive chart non-smooth`: chatter or its absence at the drivetrain's two non-smooth places, as
//! the co-simulation's macro step and algorithm change, on a shutdown scene (drivetrain C's):
//!
//! - **the brake at standstill**: after the HSS first locks, how often `brake_locked` changes at the
//!   communication points (a held brake that releases and re-locks every few steps chatters), and the
//!   largest generator speed while locked;
//! - **backlash with torque reversal**: every mesh given a backlash, the sun–planet mesh's contact
//!   state (drive flank, separated, back flank) read at the communication points, and how often it
//!   changes, against the scene's reference (its coupled equations converged every 0.25 ms).

use crate::cosim::master::run_columns_with;
use crate::cosim::{Acceleration, Algorithm, Options, Override, Scene, param};
use crate::reference::scene::{DEFAULT_STEP, options as reference_options};
use anyhow::{Context, anyhow};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive chart non-smooth                                   c-shutdown, 100 µm backlash (about 1 min)\n  \
    windrive chart non-smooth --backlash 2e-4 --out /tmp/ns     a wider backlash")]
pub struct NonSmoothArgs {
    /// Shutdown scene with a `torsional` component whose brake locks
    #[arg(long, default_value = "scenes/c-shutdown")]
    pub scene: PathBuf,
    /// Total backlash of every mesh for the reversal study, m (an estimate: ISO 1328 flank play of
    /// modules 9-16 mm is 0.1-0.3 mm)
    #[arg(long, default_value_t = 1e-4)]
    pub backlash: f64,
    /// Output stem: STEM.png, STEM.svg (the backlash chart), STEM.csv
    #[arg(long, default_value = "results/non-smooth")]
    pub out: PathBuf,
}

const STEPS_MS: [f64; 7] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0];

/// The runs: label, algorithm, input order, acceleration, and the torsional FMU's integrator settings
/// (the scene's: Newmark with internal steps up to 1 ms).
/// label, algorithm, input order, acceleration, torsional parameters.
type Variant = (
    &'static str,
    Algorithm,
    usize,
    Acceleration,
    Vec<(&'static str, &'static str)>,
);

fn variants() -> Vec<Variant> {
    let gs = Algorithm::GaussSeidel;
    let none = Acceleration::None;
    vec![
        ("gauss-seidel p0", gs, 0, none, vec![]),
        ("jacobi p0", Algorithm::Jacobi, 0, none, vec![]),
        (
            "iterative iqn-ils",
            Algorithm::Iterative,
            1,
            Acceleration::IqnIls,
            vec![],
        ),
        (
            "gs p0, internal 0.25 ms",
            gs,
            0,
            none,
            vec![("max_internal_step", "0.00025")],
        ),
        (
            "gs p0, hht rho=0.6",
            gs,
            0,
            none,
            vec![("integrator", "hht"), ("spectral_radius", "0.6")],
        ),
    ]
}

/// Changes of a state sequence.
fn changes<T: PartialEq>(states: impl Iterator<Item = T>) -> usize {
    let mut last = None;
    let mut n = 0;
    for s in states {
        if last.as_ref().is_some_and(|l| *l != s) {
            n += 1;
        }
        last = Some(s);
    }
    n
}

/// Contact state of a mesh from its force: 1 drive flank, 0 separated, −1 back flank.
fn contact(force: f64) -> i8 {
    if force > 0.0 {
        1
    } else if force < 0.0 {
        -1
    } else {
        0
    }
}

struct Counts {
    brake_changes: usize,
    creep: f64,
    contact_changes: usize,
    /// Communication points of the backlash run.
    points: usize,
}

impl Counts {
    /// Contact changes per 1000 communication points: a rattle changes state at a steady share of the
    /// points whatever their spacing, a resolved reversal at a handful.
    fn contact_rate(&self) -> f64 {
        1000.0 * self.contact_changes as f64 / self.points.max(1) as f64
    }
}

fn measure(scene: &Scene, integrator: &[Override], backlash: &[Override], opts: &Options) -> anyhow::Result<Counts> {
    let run = run_columns_with(
        scene,
        integrator,
        &["torsional.brake_locked", "torsional.generator_speed"],
        opts.clone(),
    )
    .map_err(|e| anyhow!("{}: {e}", scene.name))?;
    let (locked, speed) = (&run.columns[1], &run.columns[2]);
    let first = locked.iter().position(|l| *l > 0.5).unwrap_or(locked.len());
    let brake_changes = changes(locked[first..].iter().map(|l| *l > 0.5));
    let creep = locked[first..]
        .iter()
        .zip(&speed[first..])
        .filter(|(l, _)| **l > 0.5)
        .map(|(_, w)| w.abs())
        .fold(0.0, f64::max);
    let with_backlash: Vec<Override> = integrator.iter().chain(backlash).cloned().collect();
    let run = run_columns_with(
        scene,
        &with_backlash,
        &["torsional.mesh_force_sun_planet_1"],
        opts.clone(),
    )
    .map_err(|e| anyhow!("{} with backlash: {e}", scene.name))?;
    let contact_changes = changes(run.columns[1].iter().map(|f| contact(*f)));
    Ok(Counts {
        brake_changes,
        creep,
        contact_changes,
        points: run.columns[1].len(),
    })
}

pub fn run(args: &NonSmoothArgs) -> anyhow::Result<()> {
    if !(args.backlash > 0.0 && args.backlash < 0.01) {
        anyhow::bail!("--backlash {}: a total backlash in metres, e.g. 1e-4", args.backlash);
    }
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the output folder", dir.display()))?;
    }
    let scene = Scene::open(&args.scene)?;
    super::run::provide_own_fmus(&scene, false)?;
    let stop = scene
        .experiment
        .stop_time
        .ok_or_else(|| anyhow!("scene {}: no stop time", scene.name))?;
    let backlash = vec![param("torsional", "mesh_backlash", args.backlash)];
    let reference = measure(&scene, &[], &backlash, &reference_options(DEFAULT_STEP, stop))?;
    println!(
        "{}: brake held after its first lock, and every mesh with {} µm backlash; reference (converged every {} ms):\n  \
         brake_locked changes {}, largest generator speed while locked {:.2e} rad/s, sun-planet contact changes {} ({:.2} per 1000 points)\n",
        scene.name,
        args.backlash * 1e6,
        DEFAULT_STEP * 1e3,
        reference.brake_changes,
        reference.creep,
        reference.contact_changes,
        reference.contact_rate()
    );
    println!(
        "{:<26} {:>8} {:>16} {:>22} {:>18} {:>14}",
        "algorithm", "H [ms]", "brake changes", "speed locked [rad/s]", "contact changes", "per 1000 pts"
    );
    let mut csv = String::from(
        "algorithm,step_s,brake_locked_changes,max_speed_locked,contact_changes,contact_changes_per_1000_points\n",
    );
    let mut contact_lines: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut brake_chatter = 0;
    for (label, algorithm, order, acceleration, settings) in variants() {
        let integrator: Vec<Override> = settings.iter().map(|(k, v)| param("torsional", k, v)).collect();
        let mut c = Vec::new();
        for h_ms in STEPS_MS {
            let mut opts = Options::new(algorithm, h_ms * 1e-3, stop);
            opts.order = order;
            opts.acceleration = acceleration;
            let m = measure(&scene, &integrator, &backlash, &opts)?;
            println!(
                "{label:<26} {h_ms:>8} {:>16} {:>22.2e} {:>18} {:>14.2}",
                m.brake_changes,
                m.creep,
                m.contact_changes,
                m.contact_rate()
            );
            writeln!(
                csv,
                "{label},{},{},{},{},{}",
                h_ms * 1e-3,
                m.brake_changes,
                m.creep,
                m.contact_changes,
                m.contact_rate()
            )?;
            brake_chatter += m.brake_changes;
            c.push((h_ms.log10(), m.contact_rate().max(0.01).log10()));
        }
        contact_lines.push((label.to_string(), c));
    }
    println!(
        "\nbrake at standstill: {}",
        if brake_chatter == 0 {
            "no chatter in any run (the implicit integrator holds the stick exactly, speed 0 while locked)".to_string()
        } else {
            format!("{brake_chatter} lock/release changes over all runs (see the table)")
        }
    );
    let reference_points = vec![
        (STEPS_MS[0].log10(), reference.contact_rate().max(0.01).log10()),
        (
            STEPS_MS[STEPS_MS.len() - 1].log10(),
            reference.contact_rate().max(0.01).log10(),
        ),
    ];
    let mut series: Vec<super::plot::Series> = contact_lines
        .iter()
        .map(|(label, points)| super::plot::Series {
            label: label.clone(),
            points,
        })
        .collect();
    series.push(super::plot::Series {
        label: "reference".into(),
        points: &reference_points,
    });
    let title = format!(
        "{}, {} µm backlash: sun-planet contact changes",
        scene.name,
        args.backlash * 1e6
    );
    super::plot::write_chart_and_table(&args.out, &csv, |path| {
        super::plot::lines(
            path,
            &title,
            "log10 macro step / ms",
            "log10 contact changes per 1000 communication points",
            &series,
            &[],
        )
    })
}
