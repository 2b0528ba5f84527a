//! `windrive bench states`: what an FMU state costs. Per FMU the serialised size and the time to take
//! and free a state (what the master's rollback pays at every macro step); then drivetrain C's
//! shutdown scene with `iterative` coupling against `gauss-seidel`, the baseline measured in the
//! same run (the iterative algorithm saves every FMU's state at every macro step).

use crate::cosim::{Algorithm, Master, Options, Record, Scene, System};
use crate::fmi2::host::import::Fmu;
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
        "{:<12} {:>16} {:>15} {:>26} {:>21}",
        "FMU", "serialised bytes", "get + free, µs", "update in place + set, µs", "serialise + load, µs"
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
        // what the iterative and adaptive algorithms pay per macro step: fmi2GetFMUstate into the
        // state they keep, fmi2SetFMUstate back from it
        let mut kept = inst.get_state()?;
        let roll_back = best_of(|| {
            for _ in 0..reps {
                inst.update_state(&mut kept)?;
                inst.set_state(&kept)?;
            }
            Ok(())
        })? / reps as f64;
        inst.free_state(kept)?;
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
            "{name:<12} {:>16} {:>15.3} {:>26.3} {:>21.1}",
            bytes.len(),
            take * 1e6,
            roll_back * 1e6,
            round_trip * 1e6
        );
    }
    Ok(())
}

/// One run of `scene` with `algorithm` (1 ms macro step, input order `order`, nothing recorded):
/// wall time of the stepping alone, steps and sweeps.
fn timed(scene: &Scene, algorithm: Algorithm, order: usize, stop: f64) -> anyhow::Result<(f64, u64, u64)> {
    let mut system = System::build(scene, &[], &Record::Only(Vec::new()))?;
    system.initialize(Some(stop))?;
    let mut opts = Options::new(algorithm, 1e-3, stop);
    opts.order = order;
    let start = Instant::now();
    let mut master = Master::new(&mut system, opts)?;
    master.run(|_, _| Ok(()))?;
    Ok((start.elapsed().as_secs_f64(), master.stats.steps, master.stats.sweeps))
}

pub fn run(stop: f64) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let dir = root.join("scenes").join("c-shutdown-spring");
    super::run::provide_own_fmus(&Scene::open(&dir)?, true)?;
    state_costs(&root)?;
    // The four runs alternate, best of seven each, so that a busy machine slows all of them alike.
    let scene = Scene::open(&dir)?;
    let none = (f64::INFINITY, 0, 0);
    let (mut gs, mut gs1, mut it, mut it0) = (none, none, none, none);
    let best = |b: &mut (f64, u64, u64), r: (f64, u64, u64)| {
        if r.0 < b.0 {
            *b = r;
        }
    };
    for _ in 0..7 {
        best(&mut gs, timed(&scene, Algorithm::GaussSeidel, 0, stop)?);
        best(&mut gs1, timed(&scene, Algorithm::GaussSeidel, 1, stop)?);
        best(&mut it, timed(&scene, Algorithm::Iterative, 1, stop)?);
        best(&mut it0, timed(&scene, Algorithm::Iterative, 0, stop)?);
    }
    let sweeps = it.2 as f64 / it.1 as f64;
    println!(
        "\nscenes/c-shutdown-spring, {stop} s at 1 ms, best of 7 each:\n  gauss-seidel (order 0, the default; the baseline) {:.4} s\n  \
         gauss-seidel with order-1 inputs                  {:.4} s\n  iterative (order 1, the default)                  {:.4} s, \
         {sweeps:.2} sweeps per step\niterative / gauss-seidel: {:.2}× ({:.2}× per sweep); against gauss-seidel with the same \
         order-1 inputs: {:.2}×\niterative with order-0 inputs: {:.4} s, {:.2} sweeps per step, {:.2}× gauss-seidel at the same order",
        gs.0,
        gs1.0,
        it.0,
        it.0 / gs.0,
        it.0 / gs.0 / sweeps,
        it.0 / gs1.0,
        it0.0,
        it0.2 as f64 / it0.1 as f64,
        it0.0 / gs.0,
    );
    Ok(())
}
