//! Chatter or its absence at the drivetrain's two non-smooth places, as the co-simulation's macro
//! step and algorithm change, on a shutdown scene (`windrive chart non-smooth` prints and draws it):
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
use anyhow::anyhow;

/// Macro steps of the runs, ms.
pub const STEPS_MS: [f64; 7] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0];

/// The runs: label, algorithm, input order, acceleration, and the torsional FMU's integrator settings
/// (the scene's: Newmark with internal steps up to 1 ms).
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

/// What one run (a pair: the scene as it is, and with backlash) shows at the communication points.
#[derive(Debug, Clone, PartialEq)]
pub struct Counts {
    /// `brake_locked` changes after the HSS first locks.
    pub brake_changes: usize,
    /// Largest |generator speed| while locked, rad/s.
    pub creep: f64,
    /// Sun–planet contact-state changes with backlash.
    pub contact_changes: usize,
    /// Communication points of the backlash run.
    pub points: usize,
}

impl Counts {
    /// Contact changes per 1000 communication points: a rattle changes state at a steady share of the
    /// points whatever their spacing, a resolved reversal at a handful.
    pub fn contact_rate(&self) -> f64 {
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

/// One algorithm's runs over [`STEPS_MS`].
#[derive(Debug, Clone, PartialEq)]
pub struct Variation {
    pub label: &'static str,
    /// (macro step in ms, what the run showed), in the order of [`STEPS_MS`].
    pub runs: Vec<(f64, Counts)>,
}

/// The reference of `scene` (its FMUs packed, `stop` s) with every mesh's backlash `backlash` m, then
/// every algorithm at every macro step; `on_reference` and `on_run` are told as they are measured.
pub fn chart(
    scene: &Scene,
    stop: f64,
    backlash: f64,
    on_reference: impl FnOnce(&Counts),
    mut on_run: impl FnMut(&str, f64, &Counts),
) -> anyhow::Result<(Counts, Vec<Variation>)> {
    let backlash = vec![param("torsional", "mesh_backlash", backlash)];
    let reference = measure(scene, &[], &backlash, &reference_options(DEFAULT_STEP, stop))?;
    on_reference(&reference);
    let mut all = Vec::new();
    for (label, algorithm, order, acceleration, settings) in variants() {
        let integrator: Vec<Override> = settings.iter().map(|(k, v)| param("torsional", k, v)).collect();
        let mut runs = Vec::new();
        for h_ms in STEPS_MS {
            let mut opts = Options::new(algorithm, h_ms * 1e-3, stop);
            opts.order = order;
            opts.acceleration = acceleration;
            let m = measure(scene, &integrator, &backlash, &opts)?;
            on_run(label, h_ms, &m);
            runs.push((h_ms, m));
        }
        all.push(Variation { label, runs });
    }
    Ok((reference, all))
}
