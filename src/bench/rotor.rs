//! The rotor's aerodynamics per step: the rotationally sampled rotor (three blades reading a full
//! field, field lookup included) against the rotor-averaged BEM it replaces, in the same run. Drivetrain
//! C's rotor (the WindPACT blade scaled to 40 m) at rated speed in an IEC class A field at 11.4 m/s with
//! α = 0.2 shear (11 × 11 points, 60 s), 10 ms steps with the blades turning.
//!
//! Three loops, each its own function so that `valgrind --tool=callgrind --toggle-collect=…` can count
//! their instructions alone on a loaded machine: [`averaged_steps`] (one BEM solve a step at the hub
//! wind), [`blades_steps`] (3 × stations table reads and field lookups a step: what the FMU runs) and
//! [`solved_steps`] (the same with every station solved: what the table saves).

use super::best_of;
use crate::physics::aero::AIR_DENSITY;
use crate::physics::bem::BemRotor;
use crate::physics::blade::Blade;
use crate::physics::blades::{BladeSampling, DiscMotion};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::turbulence::Variance;
use crate::physics::wind_field::{FieldSpec, Grid, generate};

/// Steps per timed loop (the solved loop takes a tenth of them: it is the slow one).
pub const STEPS: usize = 2000;
const DT: f64 = 0.01;
const PITCH: f64 = 0.02;

pub struct Setup {
    bem: BemRotor,
    sampling: BladeSampling,
    omega: f64,
}

/// The rotor with the blade in `blade_dir` (the rotor FMU's windpact-1.5mw) and its field; building them
/// is not timed.
pub fn setup(blade_dir: &std::path::Path) -> anyhow::Result<Setup> {
    let blade = Blade::load(blade_dir)?;
    let bem = BemRotor::new(blade.scaled(40.0), AIR_DENSITY);
    let spec = FieldSpec {
        mean_wind: 11.4,
        sigma: 0.16 * (0.75 * 11.4 + 5.6),
        hub_height: 80.0,
        shear_exponent: 0.2,
        grid: Grid {
            ny: 11,
            nz: 11,
            width: 88.0,
            height: 88.0,
        },
        period: 60.0,
        max_dt: 0.05,
        variance: Variance::TenMinute,
        seed: 1,
    };
    let field = generate(&spec)?;
    let sampling = BladeSampling::new(&bem, field, 80.0, 0.0, std::f64::consts::FRAC_PI_2)?;
    let omega = Drivetrain::preset("C").expect("preset C").rated_rotor_speed;
    // the load table's columns at the loops' pitch are solved on first read (in the FMU as well): here,
    // so the loops time the reads a step costs, not that one-off
    sampling.loads(&bem, 0.0, 0.0, omega, PITCH, DiscMotion::default());
    Ok(Setup { bem, sampling, omega })
}

/// Sum of the torques of `n` steps of the rotor-averaged BEM at the field's hub wind.
#[inline(never)]
pub fn averaged_steps(s: &Setup, n: usize) -> f64 {
    (0..n)
        .map(|k| {
            let t = k as f64 * DT;
            let v = s.sampling.field.velocity_at(t, 0.0, s.sampling.hub_height)[0];
            s.bem.torque_thrust(v, s.omega, PITCH).0
        })
        .sum()
}

/// Sum of the torques of `n` steps of the sampled rotor, stations read from the table.
#[inline(never)]
pub fn blades_steps(s: &Setup, n: usize) -> f64 {
    (0..n)
        .map(|k| {
            let t = k as f64 * DT;
            s.sampling
                .loads(&s.bem, t, s.omega * t, s.omega, PITCH, DiscMotion::default())
                .torque
        })
        .sum()
}

/// Sum of the torques of `n` steps of the sampled rotor, every station solved.
#[inline(never)]
pub fn solved_steps(s: &Setup, n: usize) -> f64 {
    (0..n)
        .map(|k| {
            let t = k as f64 * DT;
            s.sampling
                .loads_solved(&s.bem, t, s.omega * t, s.omega, PITCH, DiscMotion::default())
                .torque
        })
        .sum()
}

/// µs per step (best of 3) of the three loops and their mean torques (deterministic).
pub struct Timing {
    pub averaged_us: f64,
    pub blades_us: f64,
    pub solved_us: f64,
    pub torques: [f64; 3],
}

pub fn run(s: &Setup) -> anyhow::Result<Timing> {
    let mut torques = [0.0; 3];
    let per_step = |seconds: f64, n: usize| seconds / n as f64 * 1e6;
    let averaged = best_of(3, || {
        torques[0] = averaged_steps(s, STEPS) / STEPS as f64;
        Ok(())
    })?;
    let blades = best_of(3, || {
        torques[1] = blades_steps(s, STEPS) / STEPS as f64;
        Ok(())
    })?;
    let solved = best_of(3, || {
        torques[2] = solved_steps(s, STEPS / 10) / (STEPS / 10) as f64;
        Ok(())
    })?;
    Ok(Timing {
        averaged_us: per_step(averaged, STEPS),
        blades_us: per_step(blades, STEPS),
        solved_us: per_step(solved, STEPS / 10),
        torques,
    })
}

impl std::fmt::Display for Timing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "rotor aerodynamics per step: drivetrain C's BEM rotor (40 m, 3 blades) at rated speed, IEC A field at 11.4 m/s, α = 0.2"
        )?;
        writeln!(
            f,
            "{:<44} {:>10} {:>12} {:>16}",
            "", "µs/step", "vs averaged", "mean torque N·m"
        )?;
        let rows = [
            (
                "rotor-averaged BEM (one solve a step)",
                self.averaged_us,
                self.torques[0],
            ),
            ("blades sampled, table (the FMU's)", self.blades_us, self.torques[1]),
            ("blades sampled, every station solved", self.solved_us, self.torques[2]),
        ];
        for (name, us, q) in rows {
            writeln!(f, "{name:<44} {us:>10.2} {:>11.3}× {q:>16.1}", us / self.averaged_us)?;
        }
        writeln!(
            f,
            "({STEPS} steps of {DT} s, the solved loop {}; best of 3; target: sampled ≤ 10 µs a step)",
            STEPS / 10
        )
    }
}
