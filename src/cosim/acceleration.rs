//! Acceleration of the `iterative` algorithm's fixed-point iteration x ← G(x) over the coupled
//! outputs at the end of a macro step (G: restore the states, one Gauss–Seidel sweep with x as the
//! sources' end values). Plain iteration diverges when the split is stiff for the step
//! (scenes/d-grid-step at H·ω = 3.7); the two methods of partitioned coupling practice (preCICE)
//! make it converge:
//!
//! - **Aitken**: x ← x + ω·r, r = G(x) − x, with ω from the last two residuals (Küttler & Wall 2008),
//!   starting each macro step at [`INITIAL_RELAXATION`].
//! - **IQN-ILS**, interface quasi-Newton with an inverse Jacobian from least squares (Degroote et al.
//!   2009): x ← G(x) + W·c with c = argmin ‖V·c + r‖, V and W the differences of the residuals and of
//!   G(x) against the earlier iterates of the same macro step. On a linear coupling of n variables it
//!   converges in at most n + 1 sweeps.
//!
//! Variables are scaled by their convergence tolerance (abs + rel·max(|y|, peak)), so a torque in
//! N·m and a speed in rad/s weigh alike.

/// How the iterative algorithm picks its next iterate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Acceleration {
    /// x ← G(x).
    None,
    Aitken,
    IqnIls,
}

impl Acceleration {
    pub const NAMES: &'static str = "none, aitken, iqn-ils";

    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "none" => Some(Self::None),
            "aitken" => Some(Self::Aitken),
            "iqn-ils" => Some(Self::IqnIls),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Aitken => "aitken",
            Self::IqnIls => "iqn-ils",
        }
    }
}

/// Under-relaxation of the first iterate of each macro step (Aitken's start, IQN-ILS's step before
/// it has a difference to learn from).
pub const INITIAL_RELAXATION: f64 = 1.0;

/// The iteration's memory within one macro step.
#[derive(Debug, Default)]
pub struct Accelerator {
    /// Tolerance scale of each variable.
    scale: Vec<f64>,
    omega: f64,
    /// Scaled residuals and scaled G(x) of the iterates so far (oldest first).
    residuals: Vec<Vec<f64>>,
    images: Vec<Vec<f64>>,
}

impl Accelerator {
    /// Forgets the previous macro step; `scale` is each variable's tolerance scale.
    pub fn start(&mut self, scale: impl Iterator<Item = f64>) {
        self.scale.clear();
        self.scale.extend(scale);
        self.omega = INITIAL_RELAXATION;
        self.residuals.clear();
        self.images.clear();
    }

    /// Replaces `x` (the iterate the last sweep used) by the next one, given `g` = G(x).
    pub fn next(&mut self, kind: Acceleration, x: &mut [f64], g: &[f64]) {
        let n = x.len();
        let r: Vec<f64> = (0..n).map(|i| (g[i] - x[i]) / self.scale[i]).collect();
        let gs: Vec<f64> = (0..n).map(|i| g[i] / self.scale[i]).collect();
        match kind {
            Acceleration::None => x.copy_from_slice(g),
            Acceleration::Aitken => {
                if let Some(prev) = self.residuals.last() {
                    let d: Vec<f64> = r.iter().zip(prev).map(|(a, b)| a - b).collect();
                    let dd: f64 = d.iter().map(|v| v * v).sum();
                    if dd > 0.0 {
                        let rd: f64 = prev.iter().zip(&d).map(|(a, b)| a * b).sum();
                        self.omega = -self.omega * rd / dd;
                    }
                }
                for i in 0..n {
                    x[i] += self.omega * r[i] * self.scale[i];
                }
            }
            Acceleration::IqnIls => match self.least_squares(&r, &gs) {
                Some(step) => {
                    for i in 0..n {
                        x[i] = g[i] + step[i] * self.scale[i];
                    }
                }
                None => {
                    for i in 0..n {
                        x[i] += INITIAL_RELAXATION * r[i] * self.scale[i];
                    }
                }
            },
        }
        // at most n differences carry information about n variables: keep the newest
        if self.residuals.len() > n {
            self.residuals.remove(0);
            self.images.remove(0);
        }
        self.residuals.push(r);
        self.images.push(gs);
    }

    /// W·c with c = argmin ‖V·c + r‖ (scaled), V and W the differences of the newest residual and
    /// image against the earlier ones; None before there is a difference. Solved by SVD, singular
    /// values below 1e-12 of the largest dropped (nearly repeated iterates).
    fn least_squares(&self, r: &[f64], g: &[f64]) -> Option<Vec<f64>> {
        let q = self.residuals.len();
        if q == 0 {
            return None;
        }
        let n = r.len();
        let v = nalgebra::DMatrix::from_fn(n, q, |i, j| r[i] - self.residuals[j][i]);
        let w = nalgebra::DMatrix::from_fn(n, q, |i, j| g[i] - self.images[j][i]);
        let svd = v.svd(true, true);
        let largest = svd.singular_values.max();
        if largest.is_nan() || largest <= 0.0 {
            return None;
        }
        let minus_r = nalgebra::DVector::from_fn(n, |i, _| -r[i]);
        let c = svd.solve(&minus_r, 1e-12 * largest).ok()?;
        let step = w * c;
        step.iter()
            .all(|s| s.is_finite())
            .then(|| step.iter().copied().collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x ← G(x) = A·x + b with a spectral radius of 1.8: plain iteration diverges, IQN-ILS reaches
    /// the fixed point (I − A)⁻¹·b in n + 1 evaluations, Aitken converges too.
    #[test]
    fn a_diverging_linear_iteration_converges_when_accelerated() {
        let a = [[-1.2, 0.5, 0.1], [0.3, -0.9, 0.2], [0.0, 0.4, -1.1]];
        let b = [1.0, -2.0, 0.5];
        let g = |x: &[f64]| -> Vec<f64> {
            (0..3)
                .map(|i| (0..3).map(|j| a[i][j] * x[j]).sum::<f64>() + b[i])
                .collect()
        };
        let m = nalgebra::Matrix3::from_fn(|i, j| f64::from(u8::from(i == j)) - a[i][j]);
        let exact = m.lu().solve(&nalgebra::Vector3::from(b)).unwrap();
        let run = |kind: Acceleration, sweeps: usize| -> f64 {
            let mut acc = Accelerator::default();
            acc.start([1.0, 1.0, 1.0].into_iter());
            let mut x = vec![0.0; 3];
            for _ in 0..sweeps {
                let gx = g(&x);
                acc.next(kind, &mut x, &gx);
            }
            (0..3).map(|i| (x[i] - exact[i]).abs()).fold(0.0, f64::max)
        };
        assert!(run(Acceleration::None, 20) > 1e3);
        assert!(run(Acceleration::IqnIls, 5) < 1e-10, "{}", run(Acceleration::IqnIls, 5));
        assert!(
            run(Acceleration::Aitken, 60) < 1e-8,
            "{}",
            run(Acceleration::Aitken, 60)
        );
    }
}
