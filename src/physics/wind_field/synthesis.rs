//! Veers' method (Veers 1988, SAND88-0152; TurbSim user's guide NREL/TP-500-46198 §"spectral
//! representation"): at each frequency f_k = k/T, the points' Fourier coefficients are
//! X(f_k) = (a_k/2)·L(f_k)·e^{iφ_k}, a_k = √(2·S(f_k)·Δf·scale) the cosine amplitude of the point
//! spectrum, L the Cholesky factor of the coherence matrix and φ_k independent uniform phases, one per
//! point. Then E[X_i X_j*] = (a_k/2)²·Coh_ij: each point has the spectrum S and each pair the coherence.
//! v and w are uncorrelated between points (L = I). The mean and Nyquist bins stay zero, so every
//! point's fluctuation has zero mean over the period.

use faer::Side;
use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use super::coherence::GridOffsets;
use super::spectra::{coherence_length, iec_kaimal};
use super::{FieldSpec, WindField, WindFieldError};
use crate::physics::turbulence::{SplitMix, Variance, iec_coherence, sampling, variance_scale};

/// Points above which the coherence matrix (8·(ny·nz)² bytes, factored at every frequency) stops
/// being a rotor grid and becomes a memory and time sink: 40 × 40.
const MAX_POINTS: usize = 1600;

impl FieldSpec {
    fn check(&self) -> Result<(), WindFieldError> {
        let invalid = |variable, value: f64, why| Err(WindFieldError::Invalid { variable, value, why });
        let positive = |x: f64| x.is_finite() && x > 0.0;
        let g = &self.grid;
        if !positive(self.mean_wind) {
            return invalid("mean_wind", self.mean_wind, "must be finite and positive");
        }
        if !(self.sigma.is_finite() && self.sigma >= 0.0) {
            return invalid("sigma", self.sigma, "must be finite and not negative");
        }
        if !positive(self.hub_height) {
            return invalid("hub_height", self.hub_height, "must be finite and positive");
        }
        if !self.shear_exponent.is_finite() {
            return invalid("shear_exponent", self.shear_exponent, "must be finite");
        }
        if g.ny < 2 || g.nz < 2 {
            return invalid(
                "grid.ny × grid.nz",
                (g.ny * g.nz) as f64,
                "need at least 2 points each way",
            );
        }
        if g.ny * g.nz > MAX_POINTS {
            return invalid("grid.ny × grid.nz", (g.ny * g.nz) as f64, "more than 1600 points");
        }
        if !positive(g.width) {
            return invalid("grid.width", g.width, "must be finite and positive");
        }
        if !positive(g.height) {
            return invalid("grid.height", g.height, "must be finite and positive");
        }
        if self.hub_height - 0.5 * g.height <= 0.0 {
            return invalid(
                "grid.height",
                g.height,
                "the grid reaches the ground: keep it under twice the hub height",
            );
        }
        if !positive(self.period) {
            return invalid("period", self.period, "must be finite and positive");
        }
        if !(positive(self.max_dt) && self.max_dt <= 0.5 * self.period) {
            return invalid("max_dt", self.max_dt, "must be positive and at most half the period");
        }
        Ok(())
    }
}

/// The field of `spec` (module documentation).
pub fn generate(spec: &FieldSpec) -> Result<WindField, WindFieldError> {
    spec.check()?;
    let (dt, n) = sampling(spec.period, spec.max_dt);
    let df = 1.0 / (n as f64 * dt);
    let g = spec.grid;
    let (ny, nz) = (g.ny, g.nz);
    let points = ny * nz;
    let (dy, dz) = (g.width / (ny - 1) as f64, g.height / (nz - 1) as f64);
    let v_hub = spec.mean_wind;
    let spectra = iec_kaimal(spec.sigma, spec.hub_height);
    let length_c = coherence_length(spec.hub_height);
    let offsets = GridOffsets::new(ny, nz, dy, dz);

    // half the cosine amplitude of each component at each bin: the coefficient the inverse FFT takes
    let bins = n / 2 + 1;
    let half_amplitude: Vec<Vec<f64>> = spectra
        .iter()
        .map(|s| {
            let density = |f: f64| s.density(f, v_hub);
            let scale = variance_scale(density, s.sigma, dt, n, spec.variance);
            (0..bins)
                .map(|k| match k {
                    0 => 0.0,
                    k if k == n / 2 => 0.0,
                    k => 0.5 * (2.0 * scale * density(k as f64 * df) * df).sqrt(),
                })
                .collect()
        })
        .collect();

    // coefficients point-major: [component][p·bins + k], p = k_z·ny + j
    let zero = Complex::new(0.0, 0.0);
    let mut coefficients: [Vec<Complex<f64>>; 3] = std::array::from_fn(|_| vec![zero; points * bins]);
    let mut streams: [SplitMix; 3] = std::array::from_fn(|c| SplitMix::stream(spec.seed, c as u64));
    let mut phases = faer::Mat::<f64>::zeros(points, 2);
    // beyond the frequency where even the closest points' coherence is below f64's epsilon, C is the
    // identity to working precision and so is its Cholesky factor: the factorisation is skipped there
    // (most bins of a 0.05 s series: above 3·V/d for the smallest spacing d)
    let nearest = dy.min(dz);
    for k in 1..n / 2 {
        let f = k as f64 * df;
        for p in 0..points {
            let (s, c) = (std::f64::consts::TAU * streams[0].next_f64()).sin_cos();
            phases[(p, 0)] = c;
            phases[(p, 1)] = s;
        }
        let a = half_amplitude[0][k];
        if iec_coherence(f, nearest, v_hub, length_c) >= f64::EPSILON {
            let llt = offsets
                .matrix(f, v_hub, length_c)
                .llt(Side::Lower)
                .map_err(|_| WindFieldError::NotPositiveDefinite { frequency_hz: f })?;
            let mixed = llt.L() * phases.as_ref();
            for p in 0..points {
                coefficients[0][p * bins + k] = Complex::new(a * mixed[(p, 0)], a * mixed[(p, 1)]);
            }
        } else {
            for p in 0..points {
                coefficients[0][p * bins + k] = Complex::new(a * phases[(p, 0)], a * phases[(p, 1)]);
            }
        }
        for c in 1..3 {
            let a = half_amplitude[c][k];
            for p in 0..points {
                let phase = std::f64::consts::TAU * streams[c].next_f64();
                coefficients[c][p * bins + k] = Complex::from_polar(a, phase);
            }
        }
    }
    if matches!(spec.variance, Variance::TenMinute | Variance::Period) {
        // u's points draw L·e^{iφ}, whose squared modulus is 1 only on average: one factor over the grid
        // brings the points' mean variance to the spectrum's (Parseval: var = Σ_k 2|X_k|²)
        let held: f64 = half_amplitude[0].iter().map(|a| 2.0 * a * a).sum::<f64>() * points as f64;
        let drawn: f64 = coefficients[0].iter().map(|x| 2.0 * x.norm_sqr()).sum();
        if drawn > 0.0 {
            let factor = (held / drawn).sqrt();
            coefficients[0].iter_mut().for_each(|x| *x *= factor);
        }
    }

    let plan = RealFftPlanner::<f64>::new().plan_fft_inverse(n);
    let mut scratch = plan.make_input_vec();
    let mut series = plan.make_output_vec();
    let z_bottom = spec.hub_height - 0.5 * g.height;
    let mut velocity: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; n * points]);
    for c in 0..3 {
        for p in 0..points {
            scratch.copy_from_slice(&coefficients[c][p * bins..(p + 1) * bins]);
            plan.process(&mut scratch, &mut series).expect("sizes from the plan");
            let height = z_bottom + (p / ny) as f64 * dz;
            let mean = if c == 0 {
                v_hub * (height / spec.hub_height).powf(spec.shear_exponent)
            } else {
                0.0
            };
            for (t, x) in series.iter().enumerate() {
                velocity[c][t * points + p] = mean + x;
            }
        }
    }
    Ok(WindField {
        ny,
        nz,
        nt: n,
        dy,
        dz,
        dt,
        z_bottom,
        hub_height: spec.hub_height,
        mean_hub: v_hub,
        periodic: true,
        velocity,
        tower: Default::default(),
    })
}

/// The mean profile of `spec` alone, no turbulence whatever its σ: one plane, periodic, so every time
/// reads the same power-law shear (what a rotor in steady sheared wind samples).
pub fn steady(spec: &FieldSpec) -> Result<WindField, WindFieldError> {
    spec.check()?;
    let g = spec.grid;
    let (dy, dz) = (g.width / (g.ny - 1) as f64, g.height / (g.nz - 1) as f64);
    let z_bottom = spec.hub_height - 0.5 * g.height;
    let u = (0..g.nz)
        .flat_map(|k| {
            let height = z_bottom + k as f64 * dz;
            let u = spec.mean_wind * (height / spec.hub_height).powf(spec.shear_exponent);
            std::iter::repeat_n(u, g.ny)
        })
        .collect();
    let points = g.ny * g.nz;
    Ok(WindField {
        ny: g.ny,
        nz: g.nz,
        nt: 1,
        dy,
        dz,
        dt: spec.period,
        z_bottom,
        hub_height: spec.hub_height,
        mean_hub: spec.mean_wind,
        periodic: true,
        velocity: [u, vec![0.0; points], vec![0.0; points]],
        tower: Default::default(),
    })
}
