//! Nelder–Mead simplex minimisation (Nelder & Mead 1965; the standard coefficients: reflection 1,
//! expansion 2, contraction ½, shrink ½), for objectives that are cheap to state and expensive to
//! evaluate, without derivatives: a simulation's misfit to measured statistics. Points are clamped to
//! the unit box, where the caller maps its parameters.

/// The best point found, its value, and how many evaluations it took.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    pub x: Vec<f64>,
    pub value: f64,
    pub evaluations: usize,
}

fn clamp(x: Vec<f64>) -> Vec<f64> {
    x.into_iter().map(|v| v.clamp(0.0, 1.0)).collect()
}

/// Minimises `f` over [0, 1]ⁿ from `start` with an initial simplex of edge `step`, stopping after
/// `max_evaluations` or when the simplex's values agree to `tolerance` (absolute).
pub fn minimise(
    mut f: impl FnMut(&[f64]) -> f64,
    start: &[f64],
    step: f64,
    max_evaluations: usize,
    tolerance: f64,
) -> Minimum {
    let n = start.len();
    let mut evaluations = 0;
    let mut eval = |x: &[f64], evaluations: &mut usize| {
        *evaluations += 1;
        let v = f(x);
        if v.is_finite() { v } else { f64::INFINITY }
    };
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    let x0 = clamp(start.to_vec());
    simplex.push((x0.clone(), eval(&x0, &mut evaluations)));
    for i in 0..n {
        let mut x = x0.clone();
        // step inward from a face of the box so every vertex differs from the start
        x[i] = if x[i] + step <= 1.0 { x[i] + step } else { x[i] - step };
        let v = eval(&x, &mut evaluations);
        simplex.push((x, v));
    }
    while evaluations < max_evaluations {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (simplex[0].1, simplex[n].1);
        if (worst - best).abs() <= tolerance {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|j| simplex[..n].iter().map(|(x, _)| x[j]).sum::<f64>() / n as f64)
            .collect();
        let toward = |t: f64| -> Vec<f64> {
            clamp(
                centroid
                    .iter()
                    .zip(&simplex[n].0)
                    .map(|(c, w)| c + t * (w - c))
                    .collect(),
            )
        };
        let reflected = toward(-1.0);
        let fr = eval(&reflected, &mut evaluations);
        if fr < simplex[0].1 {
            let expanded = toward(-2.0);
            let fe = eval(&expanded, &mut evaluations);
            simplex[n] = if fe < fr { (expanded, fe) } else { (reflected, fr) };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (reflected, fr);
        } else {
            let (t, bound) = if fr < simplex[n].1 {
                (-0.5, fr)
            } else {
                (0.5, simplex[n].1)
            };
            let contracted = toward(t);
            let fc = eval(&contracted, &mut evaluations);
            if fc < bound {
                simplex[n] = (contracted, fc);
            } else {
                let best = simplex[0].0.clone();
                for vertex in simplex.iter_mut().skip(1) {
                    let x: Vec<f64> = best.iter().zip(&vertex.0).map(|(b, v)| b + 0.5 * (v - b)).collect();
                    let v = eval(&x, &mut evaluations);
                    *vertex = (x, v);
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (x, value) = simplex.swap_remove(0);
    Minimum { x, value, evaluations }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock's valley, shifted into the unit box (minimum 0 at (0.6, 0.6)): the classic test a
    /// simplex method must walk along a curved floor to pass.
    #[test]
    fn finds_the_bottom_of_rosenbrocks_valley() {
        let f = |x: &[f64]| {
            let (a, b) = (5.0 * x[0] - 2.0, 5.0 * x[1] - 2.0);
            (1.0 - a).powi(2) + 100.0 * (b - a * a).powi(2)
        };
        let m = minimise(f, &[0.2, 0.9], 0.1, 2000, 1e-14);
        assert!((m.x[0] - 0.6).abs() < 1e-4 && (m.x[1] - 0.6).abs() < 1e-4, "{m:?}");
        assert!(m.evaluations < 2000);
    }

    /// A minimum outside the box ends on its face, and a non-finite objective counts as worst.
    #[test]
    fn stays_in_the_box_and_survives_nan() {
        let f = |x: &[f64]| {
            if x[1] > 0.9 {
                f64::NAN
            } else {
                (x[0] - 2.0).powi(2) + (x[1] - 0.3).powi(2)
            }
        };
        let m = minimise(f, &[0.5, 0.5], 0.2, 500, 1e-14);
        assert!((m.x[0] - 1.0).abs() < 1e-6 && (m.x[1] - 0.3).abs() < 1e-4, "{m:?}");
    }
}
