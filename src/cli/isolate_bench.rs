//! `windrive bench isolate`: what `--isolate` costs. The same scenes run in-process (the baseline)
//! and with every FMU in its own process, in the same invocation, alternating, best of 5 each;
//! every output recorded into memory at every step as `windrive run` does. Prints the wall time per
//! FMU-step both ways, the difference and the ratio, and checks the two runs' results are identical.

use crate::cosim::master::read_recorded;
use crate::cosim::{Algorithm, Master, Options, Record, Scene, System};
use crate::fmi2::host::isolate::Isolation;
use anyhow::bail;
use std::path::Path;
use std::time::Instant;

/// One run: wall time of the stepping (instantiation and initialisation excluded) and a checksum
/// of every recorded value.
fn timed(scene: &Scene, algorithm: Algorithm, stop: f64, host: Option<&Path>) -> anyhow::Result<(f64, u64)> {
    let mut system = match host {
        Some(host) => System::build_isolated(scene, &[], &Record::Outputs, &Isolation::new(host))?,
        None => System::build(scene, &[], &Record::Outputs)?,
    };
    system.initialize(Some(stop))?;
    let step = scene.experiment.step_size.unwrap_or(1e-3);
    let mut checksum = 0u64;
    let start = Instant::now();
    let mut master = Master::new(&mut system, Options::new(algorithm, step, stop))?;
    master.run(|t, sys| {
        read_recorded(sys, t)?;
        for &(_, u, i) in &sys.recorded {
            checksum = checksum.rotate_left(5) ^ sys.units[u].values[i].to_bits();
        }
        Ok(())
    })?;
    Ok((start.elapsed().as_secs_f64(), checksum))
}

pub fn run(stop: f64) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let host = std::env::current_exe()?;
    println!(
        "{:<18} {:<13} {:>5} {:>22} {:>20} {:>12} {:>8}",
        "scene", "algorithm", "FMUs", "in-process µs/FMU-step", "isolated µs/FMU-step", "added µs", "ratio"
    );
    for (name, algorithm) in [
        ("c-shutdown-spring", Algorithm::GaussSeidel),
        ("c-shutdown-spring", Algorithm::Jacobi),
        ("d-shutdown-6dof", Algorithm::GaussSeidel),
    ] {
        let dir = root.join("scenes").join(name);
        let scene = Scene::open(&dir)?;
        super::run::provide_own_fmus(&scene, false)?;
        let stop = stop.min(scene.experiment.stop_time.unwrap_or(stop));
        let (mut local, mut isolated) = ((f64::INFINITY, 0), (f64::INFINITY, 0));
        for _ in 0..5 {
            let l = timed(&scene, algorithm, stop, None)?;
            let i = timed(&scene, algorithm, stop, Some(&host))?;
            local = (local.0.min(l.0), l.1);
            isolated = (isolated.0.min(i.0), i.1);
        }
        if local.1 != isolated.1 {
            bail!(
                "{name}, {}: the isolated run's results differ from the in-process run's",
                algorithm.name()
            );
        }
        let step = scene.experiment.step_size.unwrap_or(1e-3);
        let fmu_steps = (stop / step).round() * scene.components.len() as f64;
        let per = |s: f64| s / fmu_steps * 1e6;
        println!(
            "{name:<18} {:<13} {:>5} {:>22.2} {:>20.2} {:>12.2} {:>7.2}×",
            algorithm.name(),
            scene.components.len(),
            per(local.0),
            per(isolated.0),
            per(isolated.0 - local.0),
            isolated.0 / local.0
        );
    }
    println!("({stop} s of each scene, best of 5, runs alternating; results identical both ways)");
    Ok(())
}
