//! What the thesis measured on drivetrain C's field turbine (its ch. 3) and, where it measured nothing,
//! what its own drivetrain C model gave (the sun–planet force ranges, §6.2.1; the peak torque ratio,
//! §6.2.2, Fig. 6.17: 1.32–1.38 over A–C's shafts, a model output), as statistics of a
//! normal-operation and a shutdown run, and each one's misfit: the objective the scene inputs that no
//! source gives (turbulence intensity, brake torque and ramp, pitch rate, trip delay) are fitted to by
//! `windrive calibrate`.
//!
//! Misfits are logarithmic, ln(achieved / target), so a factor of two weighs the same whichever the
//! statistic's size: zero inside a bound the thesis states as "more than" or "between", the distance
//! to the bound outside it. The objective is their sum of squares.

#[cfg(feature = "cli")]
pub mod fit;

use crate::analysis::fatigue::damage::damage_equivalent_load;
use crate::analysis::fatigue::rainflow::cycles;
use crate::analysis::signal::metrics::{peak, range};

/// What the thesis states about a statistic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    About(f64),
    AtLeast(f64),
    Between(f64, f64),
}

impl Target {
    pub fn misfit(&self, achieved: f64) -> f64 {
        if !(achieved.is_finite() && achieved > 0.0) {
            return f64::INFINITY;
        }
        match *self {
            Target::About(t) => (achieved / t).ln(),
            Target::AtLeast(t) => (achieved / t).ln().min(0.0),
            Target::Between(lo, hi) => (achieved / lo).ln().min(0.0) + (achieved / hi).ln().max(0.0),
        }
    }

    pub fn describe(&self) -> String {
        match *self {
            Target::About(t) => format!("≈ {}", short(t)),
            Target::AtLeast(t) => format!("> {}", short(t)),
            Target::Between(lo, hi) => format!("{}–{}", short(lo), short(hi)),
        }
    }
}

fn short(x: f64) -> String {
    if x.abs() >= 1e3 {
        format!("{:.4}", x)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        format!("{x}")
    }
}

/// The series a statistic is computed from: both runs' shaft torques and sun–planet force, N·m / N,
/// on a common time grid per run.
#[derive(Debug, Clone, Default)]
pub struct Runs {
    pub normal_time: Vec<f64>,
    pub normal_lss: Vec<f64>,
    pub normal_hss: Vec<f64>,
    pub normal_sun_planet: Vec<f64>,
    pub shutdown_time: Vec<f64>,
    pub shutdown_lss: Vec<f64>,
    pub shutdown_hss: Vec<f64>,
    pub shutdown_sun_planet: Vec<f64>,
}

/// The run's context a statistic needs: rated LSS torque, N·m, and when the brake is fully applied
/// in the shutdown, s.
#[derive(Debug, Clone, Copy)]
pub struct Context {
    pub rated_lss: f64,
    pub brake_applied_s: f64,
    pub shutdown_s: f64,
}

pub struct Statistic {
    pub name: &'static str,
    pub source: &'static str,
    pub unit: &'static str,
    pub target: Target,
    pub compute: fn(&Runs, &Context) -> f64,
}

/// DEL of a torque series at Wöhler slope 6, one equivalent cycle per second (the thesis's choice).
fn del6(x: &[f64], duration: f64) -> f64 {
    damage_equivalent_load(&cycles(x), 6.0, duration)
}

fn after(time: &[f64], x: &[f64], from: f64) -> Vec<f64> {
    time.iter()
        .zip(x)
        .filter(|(t, _)| **t >= from)
        .map(|(_, v)| *v)
        .collect()
}

fn window_mean(time: &[f64], x: &[f64], from: f64, to: f64) -> f64 {
    let v: Vec<f64> = time
        .iter()
        .zip(x)
        .filter(|(t, _)| **t >= from && **t <= to)
        .map(|(_, v)| *v)
        .collect();
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// The thesis's measured statistics of drivetrain C (ch. 3), in the order they are reported.
pub fn statistics() -> Vec<Statistic> {
    vec![
        Statistic {
            name: "HSS torque range, normal operation",
            source: "ch. 3: up to ≈ 3.8 kN·m",
            unit: "N·m",
            target: Target::About(3.8e3),
            compute: |r, _| range(&r.normal_hss),
        },
        Statistic {
            name: "LSS torque range, normal operation",
            source: "ch. 3: ≈ 250 kN·m",
            unit: "N·m",
            target: Target::About(250e3),
            compute: |r, _| range(&r.normal_lss),
        },
        Statistic {
            name: "sun–planet force range, normal operation",
            source: "thesis, drivetrain C: ≈ 88 kN",
            unit: "N",
            target: Target::About(88e3),
            compute: |r, _| range(&r.normal_sun_planet),
        },
        Statistic {
            name: "HSS torque range, shutdown",
            source: "ch. 3: > 19 kN·m",
            unit: "N·m",
            target: Target::AtLeast(19e3),
            compute: |r, c| range(&after(&r.shutdown_time, &r.shutdown_hss, c.shutdown_s)),
        },
        Statistic {
            name: "LSS torque range, shutdown",
            source: "ch. 3: > 2 MN·m",
            unit: "N·m",
            target: Target::AtLeast(2e6),
            compute: |r, c| range(&after(&r.shutdown_time, &r.shutdown_lss, c.shutdown_s)),
        },
        Statistic {
            name: "sun–planet force range, shutdown",
            source: "thesis, drivetrain C: > 440 kN",
            unit: "N",
            target: Target::AtLeast(440e3),
            compute: |r, c| range(&after(&r.shutdown_time, &r.shutdown_sun_planet, c.shutdown_s)),
        },
        Statistic {
            name: "LSS DEL (m = 6, 1 Hz) shutdown / normal",
            source: "ch. 3: 3.65",
            unit: "",
            target: Target::About(3.65),
            compute: |r, _| {
                let d = |t: &[f64], x: &[f64]| del6(x, t.last().copied().unwrap_or(0.0) - t[0]);
                d(&r.shutdown_time, &r.shutdown_lss) / d(&r.normal_time, &r.normal_lss)
            },
        },
        Statistic {
            name: "peak LSS torque / rated, shutdown",
            source: "§6.2.2 (A–C simulated): 1.32–1.38",
            unit: "",
            target: Target::Between(1.32, 1.38),
            compute: |r, c| peak(&r.shutdown_lss) / c.rated_lss,
        },
        Statistic {
            name: "mean LSS torque / rated, 1 s after the brake is applied",
            source: "ch. 3: up to 1.3",
            unit: "",
            target: Target::About(1.3),
            compute: |r, c| {
                window_mean(
                    &r.shutdown_time,
                    &r.shutdown_lss,
                    c.brake_applied_s,
                    c.brake_applied_s + 1.0,
                ) / c.rated_lss
            },
        },
    ]
}

/// Each statistic's achieved value and misfit.
pub fn evaluate(runs: &Runs, context: &Context) -> Vec<(f64, f64)> {
    statistics()
        .iter()
        .map(|s| {
            let a = (s.compute)(runs, context);
            (a, s.target.misfit(a))
        })
        .collect()
}

/// Sum of squared misfits.
pub fn objective(misfits: &[(f64, f64)]) -> f64 {
    misfits.iter().map(|(_, m)| m * m).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn misfits_are_logarithmic_and_zero_inside_bounds() {
        assert!((Target::About(2.0).misfit(4.0) - 2f64.ln()).abs() < 1e-15);
        assert!((Target::About(2.0).misfit(1.0) + 2f64.ln()).abs() < 1e-15);
        assert_eq!(Target::AtLeast(2.0).misfit(5.0), 0.0);
        assert!((Target::AtLeast(2.0).misfit(1.0) + 2f64.ln()).abs() < 1e-15);
        assert_eq!(Target::Between(1.32, 1.38).misfit(1.35), 0.0);
        assert!((Target::Between(1.32, 1.38).misfit(1.38 * 1.1) - 1.1f64.ln()).abs() < 1e-12);
        assert!(Target::About(1.0).misfit(f64::NAN).is_infinite());
    }

    /// The statistics of a constructed pair of runs whose answers are known: a sine of amplitude A
    /// has range 2A, its DEL at any slope over whole periods is 2A times (cycles per second)^(1/m).
    #[test]
    fn statistics_of_known_series() {
        let t: Vec<f64> = (0..=20_000).map(|k| k as f64 * 1e-3).collect();
        let sine = |a: f64, f: f64, mean: f64| -> Vec<f64> {
            t.iter()
                .map(|x| mean + a * (std::f64::consts::TAU * f * x).sin())
                .collect()
        };
        let runs = Runs {
            normal_time: t.clone(),
            normal_lss: sine(1e5, 1.0, 1e6),
            normal_hss: sine(2e3, 1.0, 1e4),
            normal_sun_planet: sine(4e4, 1.0, 2e5),
            shutdown_time: t.clone(),
            shutdown_lss: sine(3.65e5, 1.0, 1e6),
            shutdown_hss: sine(1e4, 1.0, 1e4),
            shutdown_sun_planet: sine(3e5, 1.0, 2e5),
        };
        let context = Context {
            rated_lss: 1e6,
            brake_applied_s: 6.0,
            shutdown_s: 5.0,
        };
        let v = evaluate(&runs, &context);
        assert!((v[0].0 - 4e3).abs() < 1.0);
        assert!((v[1].0 - 2e5).abs() < 10.0);
        assert!((v[6].0 - 3.65).abs() < 1e-3, "DEL ratio {}", v[6].0);
        assert!((v[7].0 - 1.365).abs() < 1e-6);
        assert!((v[8].0 - 1.0).abs() < 1e-3);
        assert_eq!(v[7].1, 0.0);
    }
}
