//! `windrive bench states`: what an FMU state costs. Per FMU the serialised size and the time to take
//! and free a state (what the master's rollback pays at every macro step); then drivetrain C's
//! shutdown scene with `iterative` coupling against `gauss-seidel`, the baseline measured in the
//! same run (the iterative algorithm saves every FMU's state at every macro step).

use crate::cosim::{Algorithm, Master, Options, Record, Scene, System};
use crate::fmi2::import::Fmu;
use std::path::Path;
use std::time::Instant;

/// Best-of-five wall time of `f`, s.
fn best_of(mut f: impl FnMut() -> anyhow::Result<()>) -> anyhow::Result<f64> {
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let start = Instant::now();
        f()?;
        best = best.min(start.elapsed().as_secs_f64());
    }
    Ok(best)
}

fn state_costs(root: &Path) -> anyhow::Result<()> {
    println!(
        "{:<12} {:>16} {:>18} {:>20}",
        "FMU", "serialised bytes", "get + free, µs", "serialise + load, µs"
    );
    for name in ["rotor", "torsional", "generator", "gearbox6dof"] {
        let path = root.join("target").join("fmu").join(format!("{name}.fmu"));
        let fmu = Fmu::open(&path)?;
        let mut inst = fmu.instantiate("bench", false)?;
        inst.setup_experiment(0.0, None)?;
        inst.enter_initialization_mode()?;
        inst.exit_initialization_mode()?;
        inst.do_step(0.0, 1e-3)?;
        let st = inst.get_state()?;
        let bytes = inst.serialize_state(&st)?;
        inst.free_state(st)?;
        let reps = 200;
        let take = best_of(|| {
            for _ in 0..reps {
                let st = inst.get_state()?;
                inst.free_state(st)?;
            }
            Ok(())
        })? / reps as f64;
        let round_trip = best_of(|| {
            let st = inst.get_state()?;
            let b = inst.serialize_state(&st)?;
            inst.free_state(st)?;
            let back = inst.deserialize_state(&b)?;
            inst.set_state(&back)?;
            inst.free_state(back)?;
            Ok(())
        })?;
        println!(
            "{name:<12} {:>16} {:>18.2} {:>20.1}",
            bytes.len(),
            take * 1e6,
            round_trip * 1e6
        );
    }
    Ok(())
}

/// Best-of-three wall time and the sweeps of scenes/c-shutdown with one algorithm (1 ms macro step,
/// nothing recorded).
fn scene(dir: &Path, algorithm: Algorithm, stop: f64) -> anyhow::Result<(f64, u64, u64)> {
    let scene = Scene::open(dir)?;
    let mut best = (f64::INFINITY, 0, 0);
    for _ in 0..3 {
        let mut system = System::build(&scene, &[], &Record::Only(Vec::new()))?;
        system.initialize(Some(stop))?;
        let start = Instant::now();
        let mut master = Master::new(&mut system, Options::new(algorithm, 1e-3, stop))?;
        master.run(|_, _| Ok(()))?;
        let wall = start.elapsed().as_secs_f64();
        if wall < best.0 {
            best = (wall, master.stats.steps, master.stats.sweeps);
        }
    }
    Ok(best)
}

pub fn run(stop: f64) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let dir = root.join("scenes").join("c-shutdown");
    super::run::provide_own_fmus(&Scene::open(&dir)?, true)?;
    state_costs(&root)?;
    let (t_gs, _, _) = scene(&dir, Algorithm::GaussSeidel, stop)?;
    let (t_it, steps, sweeps) = scene(&dir, Algorithm::Iterative, stop)?;
    println!(
        "\nscenes/c-shutdown, {stop} s at 1 ms: gauss-seidel {:.3} s (the baseline), iterative {:.3} s with {:.2} \
         sweeps per step: {:.2}× the baseline's cost ({:.2}× per sweep)",
        t_gs,
        t_it,
        sweeps as f64 / steps as f64,
        t_it / t_gs,
        t_it / t_gs / (sweeps as f64 / steps as f64)
    );
    Ok(())
}
