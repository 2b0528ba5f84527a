//! Where a run's time went, as `windrive run --profile` prints it: each FMU's steps (doStep and the
//! coupled outputs' getters) and the reads of the variables only the recorder wants, the recorder's
//! own work (gathering rows, handing them to the writer, CSV text, completing the file), the
//! master's (inputs, extrapolation, bookkeeping: the loop's wall time less all of the above), and the
//! CPU time of the threads beside the loop (the Parquet writer's encoding and compression), which
//! adds to the cost, not to the wall. `windrive bench gearbox` starts the same clocks.

use super::system::System;
use super::unit::Clock;
use std::fmt;
use std::time::Duration;

/// The split of one run; `loop_s` is the run loop's wall time, the whole of which the rows share.
pub struct Profile {
    /// (FMU, steps, recorded reads), s.
    pub units: Vec<(String, f64, f64)>,
    /// The recorder's wall time less the recorded reads, s.
    pub recorder_s: f64,
    pub loop_s: f64,
    /// CPU time of the process's other threads during the loop, s (None with Jacobi's worker
    /// threads, whose CPU is the FMUs' and cannot be told apart from a writer's).
    pub other_threads_cpu_s: Option<f64>,
    /// Jacobi's worker threads step FMUs side by side: their rows add up to more than the wall.
    pub threads: usize,
}

/// Starts timing every unit of `system` (its steps and its recorded reads apart).
pub fn start(system: &mut System) {
    for unit in &mut system.units {
        unit.clock = Some(Clock::default());
    }
}

impl Profile {
    /// The split after a run of `loop_s` seconds of wall, given each FMU's clock, the recorder's wall
    /// time (its reads included) and the CPU time of the process's other threads.
    pub fn of<'a>(
        clocks: impl IntoIterator<Item = (&'a str, Option<Clock>)>,
        loop_s: f64,
        recorder: Duration,
        other_threads_cpu_s: Option<f64>,
        threads: usize,
    ) -> Self {
        // the recorder's wall holds the reads it called, not those joined to a step's
        let mut recorded = 0.0;
        let units: Vec<(String, f64, f64)> = clocks
            .into_iter()
            .map(|(name, c)| {
                let c = c.unwrap_or_default();
                recorded += c.recorded.as_secs_f64();
                let (steps, reads) = c.steps_and_reads();
                (name.to_string(), steps.as_secs_f64(), reads.as_secs_f64())
            })
            .collect();
        Self {
            units,
            recorder_s: (recorder.as_secs_f64() - recorded).max(0.0),
            loop_s,
            other_threads_cpu_s: other_threads_cpu_s.map(|s| s.max(0.0)),
            threads,
        }
    }

    /// The split of `system`'s run (see [`Profile::of`]).
    pub fn of_system(
        system: &System,
        loop_s: f64,
        recorder: Duration,
        other_threads_cpu_s: Option<f64>,
        threads: usize,
    ) -> Self {
        let clocks = system.units.iter().map(|u| (u.name.as_str(), u.clock));
        Self::of(clocks, loop_s, recorder, other_threads_cpu_s, threads)
    }

    /// The loop's wall less every timed part: the master's own work.
    pub fn master_s(&self) -> f64 {
        let timed: f64 = self.units.iter().map(|u| u.1 + u.2).sum::<f64>() + self.recorder_s;
        (self.loop_s - timed).max(0.0)
    }
}

impl fmt::Display for Profile {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let share = |s: f64| 100.0 * s / self.loop_s.max(1e-12);
        writeln!(f, "profile     wall s of the run loop's {:.3} s (share)", self.loop_s)?;
        for (name, step, recorded) in &self.units {
            writeln!(
                f,
                "  {name:<20} steps {step:>8.3} ({:>4.1} %)   recorded reads {recorded:>8.3} ({:>4.1} %)",
                share(*step),
                share(*recorded)
            )?;
        }
        writeln!(
            f,
            "  {:<20} {:>14.3} ({:>4.1} %)   rows gathered and handed to the file, the file completed",
            "recorder",
            self.recorder_s,
            share(self.recorder_s)
        )?;
        let master = self.master_s();
        writeln!(
            f,
            "  {:<20} {:>14.3} ({:>4.1} %)   inputs, extrapolation, bookkeeping (the rest)",
            "master",
            master,
            share(master)
        )?;
        if self.threads > 1 {
            writeln!(
                f,
                "  ({} Jacobi threads step FMUs side by side: the FMUs' rows overlap)",
                self.threads
            )?;
        }
        match self.other_threads_cpu_s {
            Some(cpu) => writeln!(
                f,
                "  other threads        CPU {cpu:>8.3} s besides the loop (the Parquet writer's encoding and compression)"
            ),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Clock, Profile};
    use std::time::Duration;

    fn ms(x: u64) -> Duration {
        Duration::from_millis(x)
    }

    /// The recorder's row is its wall time less the FMUs' recorded reads, the master's the loop less
    /// every timed part; an FMU never timed counts nothing; nothing goes negative.
    #[test]
    fn the_rows_split_the_loop_and_the_master_takes_the_rest() {
        let clocks = [
            (
                "rotor",
                Some(Clock {
                    step: ms(20),
                    recorded: ms(5),
                    ..Clock::default()
                }),
            ),
            (
                "torsional",
                Some(Clock {
                    step: ms(30),
                    recorded: ms(25),
                    ..Clock::default()
                }),
            ),
            ("generator", None),
        ];
        let p = Profile::of(clocks, 0.150, ms(45), Some(0.04), 1);
        assert_eq!(p.units.len(), 3);
        assert!((p.recorder_s - 0.015).abs() < 1e-12, "{}", p.recorder_s);
        assert!((p.master_s() - (0.150 - 0.020 - 0.005 - 0.030 - 0.025 - 0.015)).abs() < 1e-12);
        assert_eq!(p.units[2], ("generator".to_string(), 0.0, 0.0));
        let text = p.to_string();
        for row in ["rotor", "torsional", "generator", "recorder", "master", "other threads"] {
            assert!(text.contains(row), "{text}");
        }
        assert!(!text.contains("side by side"), "{text}");
        // a recorder clock below its reads (clock granularity), a loop shorter than its parts
        let p = Profile::of(
            [(
                "x",
                Some(Clock {
                    step: ms(9),
                    recorded: ms(3),
                    ..Clock::default()
                }),
            )],
            0.005,
            ms(2),
            Some(-1.0),
            1,
        );
        assert_eq!(
            (p.recorder_s, p.master_s(), p.other_threads_cpu_s),
            (0.0, 0.0, Some(0.0))
        );
        // reads joined to a step count as the FMU's reads, outside both its steps and the recorder
        let p = Profile::of(
            [(
                "x",
                Some(Clock {
                    step: ms(30),
                    recorded: ms(2),
                    recorded_with_step: ms(10),
                    ..Clock::default()
                }),
            )],
            0.100,
            ms(7),
            None,
            1,
        );
        assert_eq!(p.units[0], ("x".to_string(), 0.020, 0.012));
        assert!((p.recorder_s - 0.005).abs() < 1e-12, "{}", p.recorder_s);
        assert!((p.master_s() - (0.100 - 0.020 - 0.012 - 0.005)).abs() < 1e-12);
        // Jacobi's workers: no writer's CPU to tell apart, and the FMUs' rows overlap
        let p = Profile::of([("x", None)], 0.005, ms(2), None, 4);
        let text = p.to_string();
        assert!(
            text.contains("4 Jacobi threads") && !text.contains("other threads"),
            "{text}"
        );
    }
}
