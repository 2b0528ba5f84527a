//! Benchmarks (`windrive bench TARGET` prints them): how fast our code runs and, where a bench has a
//! reference, how accurately, each measured in the same run as the baselines it is compared with (the
//! machine is shared: a number from another run would compare clocks, not code). Times are the best of
//! several runs; the deterministic columns (errors, step and sweep counts, checksums) are what a change
//! of code may not move.
//!
//! - [`torsional`]: the torsional FMU through FMI against the bare model and RK4, and a
//!   work–precision sweep of both integrators;
//! - [`gearbox`]: the 6-DOF gearbox in drivetrain D's shutdown at several fidelities, at part load, and
//!   the explicit step against the implicit one;
//! - [`coupling`]: every co-simulation algorithm on d-grid-step against its exact solution;
//! - [`states`], [`master`], [`isolate`]: what an FMU state, our master and `--isolate` cost;
//! - [`rotor`]: the rotationally sampled rotor against the rotor-averaged BEM, per step;
//! - [`rainflow`], [`solvers`]: cycle counting with DELs, and the linear solvers on gearbox-shaped
//!   matrices;
//! - [`profile`]: a model wrapper that times the model's own calls, for a model/solver split.

pub mod coupling;
pub mod gearbox;
pub mod isolate;
pub mod master;
pub mod profile;
pub mod rainflow;
pub mod rotor;
pub mod solvers;
pub mod states;
pub mod torsional;

/// Named lines of (x, y) points, a work–precision chart's.
pub type Curves = Vec<(String, Vec<(f64, f64)>)>;

/// Best-of-`runs` wall time of `f`, s.
fn best_of(runs: usize, mut f: impl FnMut() -> anyhow::Result<()>) -> anyhow::Result<f64> {
    let mut best = f64::INFINITY;
    for _ in 0..runs {
        let start = std::time::Instant::now();
        f()?;
        best = best.min(start.elapsed().as_secs_f64());
    }
    Ok(best)
}
