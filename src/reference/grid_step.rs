//! The d-grid-step scene's exact solution (scenes/d-grid-step: the undamped 2-mass drivetrain D with
//! its generator spring to ground, rotor torque stepped at t = 0), and a run of the scene through the
//! master measured against it.

use crate::linear::modes::{Boundary, undamped_step_response};
use crate::slaves::torsional::Params;

/// Rotor torque the scene applies at t = 0, N·m (scenes/d-grid-step/torsional.ssv).
pub const ROTOR_TORQUE: f64 = 385_000.0;

/// The scene's torsional FMU parameters (scenes/d-grid-step/torsional.ssv): drivetrain D, 2-mass,
/// undamped.
pub fn torsional_params() -> Params {
    Params {
        preset: "D".into(),
        fidelity: "2".into(),
        integrator: "implicit".into(),
        damping_scale: 0.0,
        contact_ratio: 1.6,
        ..Params::default()
    }
}

/// Generator torque of the scene from the exact modal solution: K_gen · q_generator(t).
pub fn exact_generator_torque(times: &[f64]) -> Vec<f64> {
    let built = torsional_params().build().expect("preset D builds");
    let (m, k_gen) = (&built.model, built.drivetrain.k_generator);
    undamped_step_response(m, Boundary::Connected, k_gen, m.rotor, ROTOR_TORQUE, times)
        .iter()
        .map(|q| k_gen * q[m.generator])
        .collect()
}

/// One run of the scene: the largest deviation of the generator torque from the exact solution
/// relative to its peak (None when the run failed), the wall time and the master's statistics.
#[cfg(feature = "cli")]
pub struct Outcome {
    pub error: Option<f64>,
    pub failure: Option<String>,
    pub wall_s: f64,
    pub stats: crate::cosim::Stats,
}

/// Runs the scene folder through the master with `opts` and measures it against
/// [`exact_generator_torque`]. A run the master stops is an outcome (its failure named), not an error.
#[cfg(feature = "cli")]
pub fn compare(scene_dir: &std::path::Path, opts: crate::cosim::Options) -> Result<Outcome, super::ReferenceError> {
    use crate::cosim::{Master, Record, Scene, System};
    let scene = Scene::open(scene_dir)?;
    let record = Record::Only(vec!["generator.generator_torque".into()]);
    let mut system = System::build(&scene, &[], &record)?;
    system.initialize(Some(opts.stop_time))?;
    let (u, i) = (system.recorded[0].1, system.recorded[0].2);
    let (mut t, mut y) = (Vec::new(), Vec::new());
    let wall = std::time::Instant::now();
    let mut master = Master::new(&mut system, opts)?;
    let result = master.run(|time, sys| {
        t.push(time);
        y.push(sys.units[u].values[i]);
        Ok(())
    });
    let wall_s = wall.elapsed().as_secs_f64();
    let stats = master.stats.clone();
    let error = crate::analysis::signal::metrics::trajectory_error(&y, &exact_generator_torque(&t));
    Ok(Outcome {
        error: result.is_ok().then_some(error),
        failure: result.err().map(|e| e.to_string()),
        wall_s,
        stats,
    })
}
