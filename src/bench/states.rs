//! `windrive bench states`: what an FMU state costs. Per FMU the serialised size and the time to take
//! and free a state (what the master's rollback pays at every macro step); then drivetrain C's
//! shutdown scene with `iterative` coupling against `gauss-seidel`, the baseline measured in the
//! same run (the iterative algorithm saves every FMU's state at every macro step).

use super::best_of;
use crate::cosim::{Algorithm, Master, Options, Record, Scene, System};
use crate::fmi2::host::import::Fmu;
use std::path::Path;
use std::time::Instant;

/// The FMUs measured, in order.
pub const FMUS: [&str; 4] = ["rotor", "torsional", "generator", "gearbox6dof"];

/// One FMU's state: its serialised size and the cost of each way of keeping it, µs.
pub struct StateCost {
    pub bytes: usize,
    /// fmi2GetFMUstate + fmi2FreeFMUstate.
    pub take_us: f64,
    /// Updating a kept state in place and setting it back: what the iterative and adaptive
    /// algorithms pay per macro step.
    pub roll_back_us: f64,
    /// Serialise, deserialise and set.
    pub round_trip_us: f64,
}

/// The state costs of the packed FMU at `path`, one step into a run.
/// The head of the state-cost table; each [`StateCost`] renders as a row of it ([`StateCost::row`]).
pub fn head() -> String {
    format!(
        "{:<12} {:>16} {:>15} {:>26} {:>21}",
        "FMU", "serialised bytes", "get + free, µs", "update in place + set, µs", "serialise + load, µs"
    )
}

impl StateCost {
    /// The row of the FMU `name`.
    pub fn row(&self, name: &str) -> String {
        format!(
            "{name:<12} {:>16} {:>15.3} {:>26.3} {:>21.1}",
            self.bytes, self.take_us, self.roll_back_us, self.round_trip_us
        )
    }
}

pub fn state_cost(path: &Path) -> anyhow::Result<StateCost> {
    let fmu = Fmu::open(path)?;
    let mut inst = fmu.instantiate("bench", false)?;
    inst.setup_experiment(0.0, None)?;
    inst.enter_initialization_mode()?;
    inst.exit_initialization_mode()?;
    inst.do_step(0.0, 1e-3)?;
    let st = inst.get_state()?;
    let bytes = inst.serialize_state(&st)?;
    inst.free_state(st)?;
    let reps = 200;
    let take = best_of(5, || {
        for _ in 0..reps {
            let st = inst.get_state()?;
            inst.free_state(st)?;
        }
        Ok(())
    })? / reps as f64;
    // what the iterative and adaptive algorithms pay per macro step: fmi2GetFMUstate into the
    // state they keep, fmi2SetFMUstate back from it
    let mut kept = inst.get_state()?;
    let roll_back = best_of(5, || {
        for _ in 0..reps {
            inst.update_state(&mut kept)?;
            inst.set_state(&kept)?;
        }
        Ok(())
    })? / reps as f64;
    inst.free_state(kept)?;
    let round_trip = best_of(5, || {
        let st = inst.get_state()?;
        let b = inst.serialize_state(&st)?;
        inst.free_state(st)?;
        let back = inst.deserialize_state(&b)?;
        inst.set_state(&back)?;
        inst.free_state(back)?;
        Ok(())
    })?;
    Ok(StateCost {
        bytes: bytes.len(),
        take_us: take * 1e6,
        roll_back_us: roll_back * 1e6,
        round_trip_us: round_trip * 1e6,
    })
}

/// One coupled run: wall time of the stepping alone, s, steps and sweeps.
#[derive(Debug, Clone, Copy)]
pub struct Timed {
    pub wall_s: f64,
    pub steps: u64,
    pub sweeps: u64,
}

impl Timed {
    pub fn sweeps_per_step(&self) -> f64 {
        self.sweeps as f64 / self.steps as f64
    }
}

/// One run of `scene` with `algorithm` (1 ms macro step, input order `order`, nothing recorded).
fn timed(scene: &Scene, algorithm: Algorithm, order: usize, stop: f64) -> anyhow::Result<Timed> {
    let mut system = System::build(scene, &[], &Record::Only(Vec::new()))?;
    system.initialize(Some(stop))?;
    let mut opts = Options::new(algorithm, 1e-3, stop);
    opts.order = order;
    let start = Instant::now();
    let mut master = Master::new(&mut system, opts)?;
    master.run(|_, _| Ok(()))?;
    Ok(Timed {
        wall_s: start.elapsed().as_secs_f64(),
        steps: master.stats.steps,
        sweeps: master.stats.sweeps,
    })
}

/// The coupled runs, best of seven each.
pub struct Coupled {
    /// Gauss–Seidel at input order 0 (the default; the baseline) and 1.
    pub gauss_seidel: Timed,
    pub gauss_seidel_order_1: Timed,
    /// Iterative at input order 1 (the default) and 0.
    pub iterative: Timed,
    pub iterative_order_0: Timed,
}

impl Coupled {
    /// What the runs of `scene` over `stop` s say, the paragraph `windrive bench states` ends with.
    pub fn report(&self, scene: &str, stop: f64) -> String {
        let (gs, gs1, it, it0) = (
            self.gauss_seidel,
            self.gauss_seidel_order_1,
            self.iterative,
            self.iterative_order_0,
        );
        let sweeps = it.sweeps_per_step();
        format!(
            "{scene}, {stop} s at 1 ms, best of 7 each:\n  gauss-seidel (order 0, the default; the baseline) {:.4} s\n  \
             gauss-seidel with order-1 inputs                  {:.4} s\n  iterative (order 1, the default)                  {:.4} s, \
             {sweeps:.2} sweeps per step\niterative / gauss-seidel: {:.2}× ({:.2}× per sweep); against gauss-seidel with the same \
             order-1 inputs: {:.2}×\niterative with order-0 inputs: {:.4} s, {:.2} sweeps per step, {:.2}× gauss-seidel at the same order",
            gs.wall_s,
            gs1.wall_s,
            it.wall_s,
            it.wall_s / gs.wall_s,
            it.wall_s / gs.wall_s / sweeps,
            it.wall_s / gs1.wall_s,
            it0.wall_s,
            it0.sweeps_per_step(),
            it0.wall_s / gs.wall_s,
        )
    }
}

/// The four runs of `scene` over `stop` s, alternating so that a busy machine slows all of them
/// alike.
pub fn coupled(scene: &Scene, stop: f64) -> anyhow::Result<Coupled> {
    let none = Timed {
        wall_s: f64::INFINITY,
        steps: 0,
        sweeps: 0,
    };
    let (mut gs, mut gs1, mut it, mut it0) = (none, none, none, none);
    let best = |b: &mut Timed, r: Timed| {
        if r.wall_s < b.wall_s {
            *b = r;
        }
    };
    for _ in 0..7 {
        best(&mut gs, timed(scene, Algorithm::GaussSeidel, 0, stop)?);
        best(&mut gs1, timed(scene, Algorithm::GaussSeidel, 1, stop)?);
        best(&mut it, timed(scene, Algorithm::Iterative, 1, stop)?);
        best(&mut it0, timed(scene, Algorithm::Iterative, 0, stop)?);
    }
    Ok(Coupled {
        gauss_seidel: gs,
        gauss_seidel_order_1: gs1,
        iterative: it,
        iterative_order_0: it0,
    })
}
