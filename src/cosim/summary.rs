//! What a run reports when it ends (`windrive run` prints it on stderr): the scene, the algorithm and
//! its settings, simulated against wall time, the steps taken and where the results went.

use super::master::{Algorithm, Options, Stats};
use std::fmt;

/// A finished or failed run, as its summary tells it.
pub struct Summary<'a> {
    pub scene: &'a str,
    pub components: usize,
    pub opts: &'a Options,
    pub stats: &'a Stats,
    /// The run's start time, s, its wall time, s, and the CPU time of every thread of the process
    /// meanwhile (the results' writer thread included), s.
    pub start_time: f64,
    pub wall_s: f64,
    pub cpu_s: f64,
    /// Where the rows went (a file, or "memory"), how many, and their columns (time included).
    pub results: String,
    pub rows: u64,
    pub columns: usize,
}

impl fmt::Display for Summary<'_> {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let (opts, stats) = (self.opts, self.stats);
        let simulated = stats.final_time - self.start_time;
        writeln!(f, "scene       {} ({} components)", self.scene, self.components)?;
        let threads = if opts.threads > 1 {
            format!(", {} threads", opts.threads)
        } else {
            String::new()
        };
        writeln!(
            f,
            "algorithm   {}, extrapolation order {}, step {} s{threads}",
            opts.algorithm.name(),
            opts.order,
            opts.step,
        )?;
        writeln!(
            f,
            "simulated   {simulated} s of {} s in {:.3} s wall, {:.3} s CPU ({:.1}× real time)",
            opts.stop_time - self.start_time,
            self.wall_s,
            self.cpu_s,
            simulated / self.wall_s.max(1e-12)
        )?;
        let unconverged = if stats.unconverged > 0 {
            format!(
                ", {} not converged in {} iterations",
                stats.unconverged, opts.max_iterations
            )
        } else {
            String::new()
        };
        let steps = if opts.algorithm == Algorithm::Adaptive && stats.steps > 0 {
            format!(", step {:.3e}–{:.3e} s", stats.min_step_taken, stats.max_step_taken)
        } else {
            String::new()
        };
        writeln!(
            f,
            "steps       {} accepted, {} rejected, {} sweeps{unconverged}{steps}",
            stats.steps, stats.rejected, stats.sweeps
        )?;
        writeln!(
            f,
            "results     {} ({} rows × {} columns)",
            self.results, self.rows, self.columns
        )?;
        if stats.stopped_early {
            writeln!(
                f,
                "warning: stopped at t = {} s: the stop time is not a whole number of steps and an FMU cannot shorten its last step",
                stats.final_time
            )?;
        }
        Ok(())
    }
}
