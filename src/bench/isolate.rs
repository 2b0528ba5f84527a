//! `windrive bench isolate`: what `--isolate` costs. The same scenes run in-process (the baseline)
//! and with every FMU in its own process, in the same invocation, alternating, best of 5 each;
//! every output recorded into memory at every step as `windrive run` does, and the two runs' results
//! checked identical.

use crate::cosim::master::read_every_row;
use crate::cosim::{Algorithm, Master, Options, Record, Scene, System};
use crate::fmi2::host::isolate::Isolation;
use anyhow::bail;
use std::path::Path;
use std::time::Instant;

/// The scenes and algorithms compared.
pub const CASES: [(&str, Algorithm); 3] = [
    ("c-shutdown-spring", Algorithm::GaussSeidel),
    ("c-shutdown-spring", Algorithm::Jacobi),
    ("d-shutdown-6dof", Algorithm::GaussSeidel),
];

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
        read_every_row(sys, t)?;
        for &(_, u, i) in &sys.recorded {
            checksum = checksum.rotate_left(5) ^ sys.units[u].values[i].to_bits();
        }
        Ok(())
    })?;
    Ok((start.elapsed().as_secs_f64(), checksum))
}

/// One scene both ways.
pub struct Compared {
    pub fmus: usize,
    /// Best wall time in-process and isolated, s.
    pub in_process_s: f64,
    pub isolated_s: f64,
    /// FMU steps of a run.
    pub fmu_steps: f64,
}

impl Compared {
    /// Wall time per FMU-step, µs.
    pub fn per_fmu_step_us(&self, seconds: f64) -> f64 {
        seconds / self.fmu_steps * 1e6
    }

    /// The row of the scene `name` run with `algorithm`, under [`head`].
    pub fn row(&self, name: &str, algorithm: Algorithm) -> String {
        format!(
            "{name:<18} {:<13} {:>5} {:>22.2} {:>20.2} {:>12.2} {:>7.2}×",
            algorithm.name(),
            self.fmus,
            self.per_fmu_step_us(self.in_process_s),
            self.per_fmu_step_us(self.isolated_s),
            self.per_fmu_step_us(self.isolated_s - self.in_process_s),
            self.isolated_s / self.in_process_s
        )
    }
}

/// The head of the table, a [`Compared::row`] per case.
pub fn head() -> String {
    format!(
        "{:<18} {:<13} {:>5} {:>22} {:>20} {:>12} {:>8}",
        "scene", "algorithm", "FMUs", "in-process µs/FMU-step", "isolated µs/FMU-step", "added µs", "ratio"
    )
}

/// `scene` (named `name`) with `algorithm` over `stop` s (at most the scene's own stop time), both
/// ways; `host` is the executable that hosts an isolated FMU (windrive itself).
pub fn compare(name: &str, scene: &Scene, algorithm: Algorithm, stop: f64, host: &Path) -> anyhow::Result<Compared> {
    let stop = stop.min(scene.experiment.stop_time.unwrap_or(stop));
    let (mut local, mut isolated) = ((f64::INFINITY, 0), (f64::INFINITY, 0));
    for _ in 0..5 {
        let l = timed(scene, algorithm, stop, None)?;
        let i = timed(scene, algorithm, stop, Some(host))?;
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
    Ok(Compared {
        fmus: scene.components.len(),
        in_process_s: local.0,
        isolated_s: isolated.0,
        fmu_steps: (stop / step).round() * scene.components.len() as f64,
    })
}
