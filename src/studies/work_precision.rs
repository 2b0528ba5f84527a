//! Error against CPU time over a grid of runs of any scene (`windrive chart work-precision` prints and
//! draws it): the grid for what varies (co-simulation algorithms, macro steps, extrapolation orders,
//! integrators, internal steps, fidelities, slices), every run measured against the scene's reference
//! ([`crate::reference::scene`]: the error of a run is the largest relative error of its quantities of
//! interest), the lines to draw and the Pareto front.

use super::scene_study::{ERROR_FLOOR, Measured, Study};
use crate::cosim::{Acceleration, Algorithm, Options, Override, param};
use anyhow::{anyhow, bail};

/// What can vary, as `--vary` names it.
pub const VARY: &str = "algorithm, macro-step, order, integrator, step, fidelity, slices";

const MACRO_STEPS_MS: [f64; 8] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0];
// down to below RK4's limit on the full models (57 µs for C, 2.785/ω_max of its stiffest mesh mode)
const INTERNAL_STEPS_MS: [f64; 6] = [1.0, 0.5, 0.25, 0.1, 0.05, 0.025];

/// One run of the grid: the line it belongs to, its setting, what it changes.
pub struct Variant {
    pub line: String,
    pub setting: String,
    overrides: Vec<Override>,
    opts: Options,
}

/// The grid of runs varying `vary` (one of [`VARY`]), at `steps_ms` (macro or internal steps, ms;
/// default: the grid's own), the runs that do not vary the algorithm with `algorithm`.
pub fn variants(study: &Study, vary: &str, steps_ms: Option<&[f64]>, algorithm: &str) -> anyhow::Result<Vec<Variant>> {
    let name = algorithm;
    let algorithm =
        Algorithm::parse(name).ok_or_else(|| anyhow!("--algorithm {name}: use one of {}", Algorithm::NAMES))?;
    let stop = study.stop_time;
    let steps = |default: &[f64]| -> anyhow::Result<Vec<f64>> {
        let s = steps_ms.map(<[f64]>::to_vec).unwrap_or_else(|| default.to_vec());
        if s.is_empty() || s.iter().any(|h| !(*h > 0.0 && h.is_finite())) {
            bail!("--steps {s:?}: every step must be a positive number of milliseconds");
        }
        Ok(s.iter().map(|h| h * 1e-3).collect())
    };
    let at = |algorithm, h| Options::new(algorithm, h, stop);
    let mut out = Vec::new();
    let mut over_macro =
        |line: String, overrides: Vec<Override>, make: &dyn Fn(f64) -> Options| -> anyhow::Result<()> {
            for h in steps(&MACRO_STEPS_MS)? {
                out.push(Variant {
                    line: line.clone(),
                    setting: format!("H = {} ms", h * 1e3),
                    overrides: overrides.clone(),
                    opts: make(h),
                });
            }
            Ok(())
        };
    match vary {
        "macro-step" => over_macro(name.to_string(), vec![], &|h| at(algorithm, h))?,
        "algorithm" => {
            for a in [Algorithm::Jacobi, Algorithm::GaussSeidel, Algorithm::Iterative] {
                over_macro(a.name().into(), vec![], &|h| at(a, h))?;
            }
            over_macro("iterative iqn-ils".into(), vec![], &|h| {
                let mut o = at(Algorithm::Iterative, h);
                o.acceleration = Acceleration::IqnIls;
                o
            })?;
        }
        "order" => {
            for order in 0..=2 {
                over_macro(format!("{} order {order}", algorithm.name()), vec![], &|h| {
                    let mut o = at(algorithm, h);
                    o.order = order;
                    o
                })?;
            }
        }
        "fidelity" => {
            let c = study.component_of("torsional")?;
            for f in ["2", "5", "full"] {
                over_macro(
                    format!("{f}-mass").replace("full-mass", "full"),
                    vec![param(&c, "fidelity", f)],
                    &|h| at(algorithm, h),
                )?;
            }
        }
        "integrator" | "step" => {
            let c = study.component_of("torsional")?;
            let integrators: Vec<(&str, Vec<Override>)> = if vary == "step" {
                vec![("scene's integrator", vec![])]
            } else {
                vec![
                    ("implicit (Newmark)", vec![param(&c, "integrator", "implicit")]),
                    (
                        "hht rho=0.6",
                        vec![param(&c, "integrator", "hht"), param(&c, "spectral_radius", 0.6)],
                    ),
                    (
                        "generalized-alpha rho=0.3",
                        vec![
                            param(&c, "integrator", "generalized-alpha"),
                            param(&c, "spectral_radius", 0.3),
                        ],
                    ),
                    ("rk4", vec![param(&c, "integrator", "rk4")]),
                ]
            };
            for (line, base) in integrators {
                for h in steps(&INTERNAL_STEPS_MS)? {
                    let mut overrides = base.clone();
                    overrides.push(param(&c, "max_internal_step", h));
                    out.push(Variant {
                        line: line.into(),
                        setting: format!("h = {} ms", h * 1e3),
                        overrides,
                        opts: at(algorithm, study.scene_step),
                    });
                }
            }
        }
        "slices" => {
            let c = study.component_of("gearbox6dof")?;
            for n in [3, 5, 11, 21, 35] {
                out.push(Variant {
                    line: "gearbox6dof slices".into(),
                    setting: format!("{n} slices"),
                    overrides: vec![param(&c, "slices", n)],
                    opts: at(algorithm, study.scene_step),
                });
            }
        }
        other => bail!("--vary {other}: use one of {VARY}"),
    }
    Ok(out)
}

/// Whether a run is drawn on the chart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shown {
    Drawn,
    /// Its error is within the reference's own: the reference cannot resolve it.
    Unresolved,
    /// It failed or blew up (error ≥ 100 %): listed, not drawn.
    Unstable,
}

/// One measured run of the grid.
pub struct Point {
    pub measured: Measured,
    /// The largest relative error over the quantities.
    pub worst: f64,
    pub shown: Shown,
}

/// The chart: per line its drawn (CPU s, error) points, in grid order, and the Pareto front as
/// (variant, point), cheapest first.
pub struct Chart {
    pub lines: Vec<(String, Vec<(f64, f64)>)>,
    pub front: Vec<(usize, (f64, f64))>,
}

/// Runs every variant `repeat` times against the study's reference; `starting(k, variant)` before
/// run k, `measured(variant, point)` after it.
pub fn run(
    study: &Study,
    variants: &[Variant],
    repeat: usize,
    mut starting: impl FnMut(usize, &Variant),
    mut measured: impl FnMut(&Variant, &Point),
) -> Chart {
    let reference_error = study.reference_error();
    let mut lines: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut drawn = Vec::new();
    for (k, v) in variants.iter().enumerate() {
        starting(k, v);
        let m = study.measure(&v.overrides, &v.opts, repeat);
        let worst = m.worst();
        let shown = if m.failure.is_none() && worst <= reference_error {
            Shown::Unresolved
        } else if m.failure.is_none() && worst < 1.0 {
            Shown::Drawn
        } else {
            Shown::Unstable
        };
        let point = (m.cpu_s, worst.max(ERROR_FLOOR));
        measured(
            v,
            &Point {
                measured: m,
                worst,
                shown,
            },
        );
        let entry = match lines.iter_mut().position(|(l, _)| *l == v.line) {
            Some(i) => &mut lines[i].1,
            None => {
                lines.push((v.line.clone(), Vec::new()));
                &mut lines.last_mut().expect("just pushed").1
            }
        };
        if shown == Shown::Drawn {
            entry.push(point);
            drawn.push((point, k));
        }
    }
    let points: Vec<(f64, f64)> = drawn.iter().map(|(p, _)| *p).collect();
    let front = pareto_front(&points)
        .into_iter()
        .map(|i| (drawn[i].1, drawn[i].0))
        .collect();
    Chart { lines, front }
}

/// Indices of the points (CPU time, error) no other point beats on both, cheapest first.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut front: Vec<usize> = Vec::new();
    for i in order {
        if front.last().is_none_or(|&last| points[i].1 < points[last].1) {
            front.push(i);
        }
    }
    front
}
