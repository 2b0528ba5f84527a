//! Statistics of generated fields against IEC 61400-1 ed. 3 Annex B, each tolerance from the sampling
//! of the quantity it bounds; the .bts round trip to within the format's quantisation.

use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use super::*;
use crate::physics::turbulence::{kaimal, scale_parameter};

/// A 90 m hub, IEC class B at 11.4 m/s (σ1 = 1.981 m/s), a 9 × 9 grid over 120 m, 10 minutes at 0.1 s.
fn spec(variance: Variance, seed: u64) -> FieldSpec {
    FieldSpec {
        mean_wind: 11.4,
        sigma: 1.981,
        hub_height: 90.0,
        shear_exponent: 0.2,
        grid: Grid {
            ny: 9,
            nz: 9,
            width: 120.0,
            height: 120.0,
        },
        period: 600.0,
        max_dt: 0.1,
        variance,
        seed,
    }
}

/// Forward real FFT of every point's series of every component: [component][point][bin].
fn spectra_of(field: &WindField) -> [Vec<Vec<Complex<f64>>>; 3] {
    let plan = RealFftPlanner::<f64>::new().plan_fft_forward(field.nt);
    std::array::from_fn(|c| {
        (0..field.nz)
            .flat_map(|k| (0..field.ny).map(move |j| (j, k)))
            .map(|(j, k)| {
                let mut x: Vec<f64> = field.series(c, j, k).collect();
                let mut out = plan.make_output_vec();
                plan.process(&mut x, &mut out).expect("sizes from the plan");
                out
            })
            .collect()
    })
}

fn moments(x: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = x.clone().count() as f64;
    let mean = x.clone().sum::<f64>() / n;
    (mean, x.map(|v| (v - mean).powi(2)).sum::<f64>() / n)
}

/// The points' coordinates in generation order p = k·ny + j.
fn coordinates(field: &WindField) -> Vec<(f64, f64)> {
    (0..field.nz)
        .flat_map(|k| (0..field.ny).map(move |j| (j, k)))
        .map(|(j, k)| (field.y(j), field.z(k)))
        .collect()
}

/// The IEC coherence matrix of u at `f` over `points`, written out from Eq. B.16 here, and its Cholesky
/// factor by nalgebra (not the generator's faer).
fn coherence_and_factor(
    points: &[(f64, f64)],
    f: f64,
    s: &FieldSpec,
) -> (nalgebra::DMatrix<f64>, nalgebra::DMatrix<f64>) {
    let length_c = 8.1 * scale_parameter(s.hub_height);
    let c = nalgebra::DMatrix::from_fn(points.len(), points.len(), |a, b| {
        let r = ((points[a].0 - points[b].0).powi(2) + (points[a].1 - points[b].1).powi(2)).sqrt();
        (-12.0 * ((f * r / s.mean_wind).powi(2) + (0.12 * r / length_c).powi(2)).sqrt()).exp()
    });
    let l = c
        .clone()
        .cholesky()
        .expect("the exponential kernel is positive definite")
        .l();
    (c, l)
}

/// Each component's point spectrum, averaged over the 81 points and over octave-wide bands of bins,
/// against the Kaimal density of Annex B (the spectrum's own variance: no scaling). v and w draw one
/// phase per bin and point, so their periodogram is the spectrum to rounding (1e-9). u's points mix
/// independent uniform phases φ through the Cholesky factor L of the coherence matrix C: over the
/// spectrum, the points' mean periodogram is φᴴ(LᵀL)φ/P, mean 1 and variance Σ_{i≠j}(LᵀL)²_ij/P² =
/// (‖C‖²_F − Σ_i ‖L_{:,i}‖⁴)/P² (phase differences of distinct pairs are uncorrelated), computed here from
/// the IEC formula; a band's tolerance is 4.5 standard deviations of its Kaimal-weighted sum (and 1e-9
/// where the points are independent and the draw exact). A wrong length scale (L_u, L_v, L_w permuted,
/// or Λ1 for a hub under 60 m) misses by tens of percent in the first bands.
#[test]
fn point_spectra_are_kaimal() {
    let s = spec(Variance::Spectrum, 5);
    let field = generate(&s).unwrap();
    let spectra = spectra_of(&field);
    let (n, points) = (field.nt, field.ny * field.nz);
    let df = 1.0 / field.duration();
    let lambda = scale_parameter(s.hub_height);
    let expected = [(1.0, 8.1), (0.8, 2.7), (0.5, 0.66)];
    let coordinates = coordinates(&field);
    // the variance of u's points' mean periodogram over its expectation, per bin
    let mixing_variance = |f: f64| {
        let (c, l) = coherence_and_factor(&coordinates, f, &s);
        let columns: f64 = l.column_iter().map(|col| col.norm_squared().powi(2)).sum();
        (c.norm_squared() - columns).max(0.0) / (points * points) as f64
    };
    let mut lo = 1;
    while lo < n / 2 {
        let hi = (2 * lo).min(n / 2);
        for (c, (ratio, scale)) in expected.iter().enumerate() {
            let (sigma, length) = (ratio * s.sigma, scale * lambda);
            let (mut drawn, mut kaimal_sum, mut variance) = (0.0, 0.0, 0.0);
            for k in lo..hi {
                let f = k as f64 * df;
                // one-sided density from the DFT of a real series: 2|X|²/(n²·Δf)
                let periodogram: f64 = spectra[c]
                    .iter()
                    .map(|x| 2.0 * x[k].norm_sqr() / (n * n) as f64 / df)
                    .sum::<f64>()
                    / points as f64;
                let density = kaimal(f, sigma, length, s.mean_wind);
                drawn += periodogram;
                kaimal_sum += density;
                if c == 0 && k < 512 {
                    variance += mixing_variance(f) * density * density;
                }
            }
            let tolerance = (4.5 * variance.sqrt() / kaimal_sum).max(1e-9);
            let misfit = drawn / kaimal_sum - 1.0;
            eprintln!(
                "{} bins {lo}..{hi}: drawn/Kaimal − 1 = {misfit:+.4} (tolerance {tolerance:.4})",
                COMPONENTS[c]
            );
            assert!(
                misfit.abs() <= tolerance,
                "{}: bins {lo}..{hi} off by {misfit}",
                COMPONENTS[c]
            );
        }
        lo = hi;
    }
}

/// Read as IEC's 10-minute σ1 over a 600 s period (TenMinute): at every point v and w hold exactly
/// 0.8σ1 and 0.5σ1 (one phase per bin and point), u's points together σ1 (one factor over the grid),
/// all to rounding; every point's u has over the period the power-law mean V·(z/z_hub)^α and v, w none.
/// (Each point's u variance scatters about σ1² with the phase mixing, as TurbSim's do under
/// `ScaleIEC = 1`.) Another α moves the profile with it.
#[test]
fn ten_minute_sigmas_and_mean_shear() {
    for (seed, alpha) in [(1, 0.2), (2, 0.14)] {
        let s = FieldSpec {
            shear_exponent: alpha,
            ..spec(Variance::TenMinute, seed)
        };
        let field = generate(&s).unwrap();
        let mut u_variance_sum = 0.0;
        for k in 0..field.nz {
            for j in 0..field.ny {
                let [(u_mean, u_var), (v_mean, v_var), (w_mean, w_var)] =
                    std::array::from_fn(|c| moments(field.series(c, j, k)));
                let profile = s.mean_wind * (field.z(k) / s.hub_height).powf(alpha);
                assert!(
                    (u_mean - profile).abs() < 1e-9,
                    "u mean {u_mean} at z = {}: {profile}",
                    field.z(k)
                );
                assert!(
                    v_mean.abs() < 1e-12 && w_mean.abs() < 1e-12,
                    "v, w means {v_mean} {w_mean}"
                );
                let sigma2 = s.sigma * s.sigma;
                assert!((v_var / (0.64 * sigma2) - 1.0).abs() < 1e-9, "σ_v² {v_var}");
                assert!((w_var / (0.25 * sigma2) - 1.0).abs() < 1e-9, "σ_w² {w_var}");
                u_variance_sum += u_var;
            }
        }
        let mean_u_variance = u_variance_sum / (field.ny * field.nz) as f64;
        assert!(
            (mean_u_variance / (s.sigma * s.sigma) - 1.0).abs() < 1e-9,
            "grid's σ_u² {mean_u_variance}"
        );
    }
}

/// u's coherence between points at several offsets, estimated from the generated series as the
/// co-coherence Σ Re(X_a·X_b*) / √(Σ|X_a|²·Σ|X_b|²), the sums over every pair of grid points at that
/// offset and over a band of bins, against the IEC Eq. B.16 coherence averaged over the band with the
/// Kaimal density's weights. Sampling: per bin the sums are quadratic forms in the independent uniform
/// phases φ, the pairs' cross sum φᴴ·Lᵀ·E·L·φ (E picks the pairs, ½ each way) and the powers
/// φᴴ·Lᵀ·F·L·φ (F the diagonal of how often each point appears), L the Cholesky factor of the coherence
/// matrix C (by nalgebra here, not the generator's faer). To first order (delta method) the ratio's
/// variance is that of the quadratic form with G = Lᵀ·(E − γ·F)·L over its expected denominator, and for
/// uniform phases var(φᴴGφ) = Σ_{i≠j} G²_ij = tr(((E − γF)·C)²) − Σ_i G²_ii. The tolerance is 4 of those
/// standard deviations. A field without coherence (L = I: the estimate near 0) or with ed. 2's
/// L_c = 3.5Λ1 fails at close offsets and low frequencies.
#[test]
fn u_coherence_follows_iec() {
    let s = spec(Variance::Spectrum, 9);
    let field = generate(&s).unwrap();
    let spectra = spectra_of(&field);
    let df = 1.0 / field.duration();
    let length_c = 8.1 * scale_parameter(s.hub_height);
    let (ny, nz, points) = (field.ny, field.nz, field.ny * field.nz);
    let coordinates = coordinates(&field);
    let density = |bin: usize| {
        kaimal(
            bin as f64 * df,
            s.sigma,
            8.1 * scale_parameter(s.hub_height),
            s.mean_wind,
        )
    };
    let bands = [(1, 4), (4, 10), (10, 25), (25, 60), (60, 150)];
    let factors: Vec<_> = (1..150)
        .map(|k| coherence_and_factor(&coordinates, k as f64 * df, &s))
        .collect();
    for (oj, ok) in [(1, 0), (0, 1), (2, 0), (1, 1), (0, 3), (4, 0)] {
        let r = ((oj as f64 * field.dy).powi(2) + (ok as f64 * field.dz).powi(2)).sqrt();
        let pairs: Vec<(usize, usize)> = (0..nz - ok)
            .flat_map(|k| (0..ny - oj).map(move |j| (k * ny + j, (k + ok) * ny + j + oj)))
            .collect();
        let mut appearances = vec![0.0; points];
        for &(a, b) in &pairs {
            appearances[a] += 0.5;
            appearances[b] += 0.5;
        }
        for (lo, hi) in bands {
            let weight: f64 = (lo..hi).map(density).sum();
            let expected = (lo..hi)
                .map(|bin| {
                    density(bin) * crate::physics::turbulence::iec_coherence(bin as f64 * df, r, s.mean_wind, length_c)
                })
                .sum::<f64>()
                / weight;
            let (mut cross, mut power_a, mut power_b, mut variance) = (0.0, 0.0, 0.0, 0.0);
            for bin in lo..hi {
                for &(a, b) in &pairs {
                    let (xa, xb) = (spectra[0][a][bin], spectra[0][b][bin]);
                    cross += (xa * xb.conj()).re;
                    power_a += xa.norm_sqr();
                    power_b += xb.norm_sqr();
                }
                let (c, l) = &factors[bin - 1];
                // (E − γF)·C, row by row
                let mut m = nalgebra::DMatrix::<f64>::zeros(points, points);
                for &(a, b) in &pairs {
                    for col in 0..points {
                        m[(a, col)] += 0.5 * c[(b, col)];
                        m[(b, col)] += 0.5 * c[(a, col)];
                    }
                }
                for (p, count) in appearances.iter().enumerate() {
                    for col in 0..points {
                        m[(p, col)] -= expected * count * c[(p, col)];
                    }
                }
                let trace_square = m.component_mul(&m.transpose()).sum();
                let diagonal: f64 = (0..points)
                    .map(|i| {
                        let cross: f64 = pairs.iter().map(|&(a, b)| l[(a, i)] * l[(b, i)]).sum();
                        let own: f64 = appearances.iter().enumerate().map(|(p, n)| n * l[(p, i)].powi(2)).sum();
                        (cross - expected * own).powi(2)
                    })
                    .sum();
                variance += (trace_square - diagonal).max(0.0) * density(bin).powi(2);
            }
            let estimate = cross / (power_a * power_b).sqrt();
            let tolerance = 4.0 * variance.sqrt() / (pairs.len() as f64 * weight);
            eprintln!(
                "offset ({oj}, {ok}) r = {r:.1} m, {:.4}-{:.4} Hz: coherence {estimate:.3}, IEC {expected:.3} (± {tolerance:.3})",
                lo as f64 * df,
                hi as f64 * df
            );
            assert!(
                (estimate - expected).abs() <= tolerance,
                "offset ({oj}, {ok}), bins {lo}..{hi}: {estimate} against {expected}"
            );
        }
    }
}

/// v and w are uncorrelated between points and with each other: the zero-lag correlation of two series
/// of independent phases, Σ_k (a_k a'_k/2)·cos(φ_k − φ'_k) / (σ σ'), has mean zero and standard deviation
/// sd = √(Σ a_k² a'_k² / 2) / √(Σ a_k² · Σ a'_k²), a_k the cosine amplitudes (the Kaimal spectrum's, few
/// effective bins: sd is about 0.1). Over the 3240 pairs of distinct points (pairwise independent: two
/// pairs sharing a point see its phase only through differences with independent uniform phases) the
/// mean of ρ² is sd² within a relative standard error √2/√3240 ≈ 2.5 %; tolerance 15 %. u's
/// neighbours, which should be correlated, sit far outside that band.
#[test]
fn v_and_w_are_uncorrelated_between_points() {
    let s = spec(Variance::TenMinute, 4);
    let field = generate(&s).unwrap();
    let spectra = spectra_of(&field);
    let points = field.ny * field.nz;
    let (n, nyquist) = (field.nt as f64, field.nt / 2);
    // cosine amplitudes from the DFT: a_k = 2|X_k|/n (the same at every point for v and w)
    let amplitude2 = |c: usize| -> Vec<f64> {
        (1..nyquist)
            .map(|k| 4.0 * spectra[c][0][k].norm_sqr() / (n * n))
            .collect()
    };
    let series: [Vec<Vec<f64>>; 3] = std::array::from_fn(|c| {
        (0..points)
            .map(|p| field.series(c, p % field.ny, p / field.ny).collect())
            .collect()
    });
    let correlation = |x: &[f64], y: &[f64]| {
        let (mx, vx) = moments(x.iter().copied());
        let (my, vy) = moments(y.iter().copied());
        x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum::<f64>() / n / (vx * vy).sqrt()
    };
    for (c1, c2) in [(1, 1), (2, 2), (1, 2)] {
        let (a1, a2) = (amplitude2(c1), amplitude2(c2));
        let sd2 = a1.iter().zip(&a2).map(|(x, y)| x * y / 2.0).sum::<f64>()
            / (a1.iter().sum::<f64>() * a2.iter().sum::<f64>());
        let (mut sum, mut pairs) = (0.0, 0);
        for p in 0..points {
            // v with w includes the same point: independent streams, independent phases
            let first = if c1 == c2 { p + 1 } else { 0 };
            for q in first..points {
                sum += correlation(&series[c1][p], &series[c2][q]).powi(2);
                pairs += 1;
            }
        }
        let ratio = sum / pairs as f64 / sd2;
        eprintln!(
            "{}-{}: mean ρ² / sd² = {ratio:.3} over {pairs} pairs (sd = {:.3})",
            COMPONENTS[c1],
            COMPONENTS[c2],
            sd2.sqrt()
        );
        assert!(
            (ratio - 1.0).abs() < 0.15,
            "{}-{}: {ratio}",
            COMPONENTS[c1],
            COMPONENTS[c2]
        );
        if c1 == 1 && c2 == 1 {
            let neighbours = correlation(&series[0][0], &series[0][1]);
            assert!(neighbours > 5.0 * sd2.sqrt(), "u neighbours' correlation {neighbours}");
        }
    }
}

/// A seed reproduces its field bit for bit; another seed draws another; the three components draw
/// from streams of their own (v's and w's series differ beyond their σ ratio).
#[test]
fn seeds_reproduce_and_differ() {
    let small = |seed| FieldSpec {
        grid: Grid {
            ny: 3,
            nz: 3,
            width: 60.0,
            height: 60.0,
        },
        period: 60.0,
        ..spec(Variance::TenMinute, seed)
    };
    let a = generate(&small(7)).unwrap();
    assert_eq!(a, generate(&small(7)).unwrap());
    assert_ne!(a.velocity[0], generate(&small(8)).unwrap().velocity[0]);
    let (v, w) = (&a.velocity[1], &a.velocity[2]);
    let rho = v.iter().zip(w).map(|(x, y)| x * y).sum::<f64>()
        / (v.iter().map(|x| x * x).sum::<f64>() * w.iter().map(|x| x * x).sum::<f64>()).sqrt();
    assert!(rho.abs() < 0.9, "v and w alike: {rho}");
}

/// A spec that cannot make a field names the variable at fault.
#[test]
fn invalid_specs_are_named() {
    let base = spec(Variance::TenMinute, 1);
    let ground = FieldSpec {
        grid: Grid {
            height: 190.0,
            ..base.grid
        },
        ..base
    };
    assert!(matches!(
        generate(&ground),
        Err(WindFieldError::Invalid {
            variable: "grid.height",
            ..
        })
    ));
    let line = FieldSpec {
        grid: Grid { ny: 1, ..base.grid },
        ..base
    };
    assert!(matches!(
        generate(&line),
        Err(WindFieldError::Invalid {
            variable: "grid.ny × grid.nz",
            ..
        })
    ));
    let calm = FieldSpec { mean_wind: 0.0, ..base };
    assert!(matches!(
        generate(&calm),
        Err(WindFieldError::Invalid {
            variable: "mean_wind",
            ..
        })
    ));
}

/// Written and read back, a field keeps its header (in f32) and every value to within half an i16
/// count of its component's range, (max − min)/131070, plus the f32 rounding of slope and offset;
/// a periodic field keeps ID 8. Truncated bytes and a foreign ID are refused with what is wrong.
#[test]
fn bts_round_trip_within_quantisation() {
    let s = FieldSpec {
        grid: Grid {
            ny: 5,
            nz: 4,
            width: 80.0,
            height: 60.0,
        },
        period: 120.0,
        ..spec(Variance::TenMinute, 3)
    };
    let field = generate(&s).unwrap();
    let mut bytes = Vec::new();
    bts::encode(&field, "windrive test field", &mut bytes).unwrap();
    let back = bts::parse(&bytes).unwrap();
    assert_eq!((back.ny, back.nz, back.nt, back.periodic), (5, 4, field.nt, true));
    for (ours, theirs) in [
        (field.dy, back.dy),
        (field.dz, back.dz),
        (field.dt, back.dt),
        (field.z_bottom, back.z_bottom),
        (field.hub_height, back.hub_height),
        (field.mean_hub, back.mean_hub),
    ] {
        assert!(
            (ours - theirs).abs() <= 1e-6 * ours.abs(),
            "{ours} read back as {theirs}"
        );
    }
    for c in 0..3 {
        let values = &field.velocity[c];
        let range = values.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - values.iter().cloned().fold(f64::INFINITY, f64::min);
        let half_count = 0.5 * range / 65_535.0;
        let worst = values
            .iter()
            .zip(&back.velocity[c])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            worst <= 1.02 * half_count,
            "{}: {worst} beyond half a count {half_count}",
            COMPONENTS[c]
        );
        assert!(worst >= 0.5 * half_count, "{}: {worst} — not quantised?", COMPONENTS[c]);
    }
    let truncated = bts::parse(&bytes[..bytes.len() - 2]).unwrap_err();
    assert!(truncated.contains("nt = "), "{truncated}");
    let mut foreign = bytes.clone();
    foreign[0] = 9;
    assert!(bts::parse(&foreign).unwrap_err().contains("format ID 9"));
}

/// A file's tower points survive a read and a write (TurbSim writes them below the grid and OpenFAST's
/// tower aerodynamics reads them): their count is kept, their values come back within half a count of a
/// range that covers grid and tower together, and a second round trip gives the same bytes.
#[test]
fn bts_tower_points_are_kept() {
    let s = FieldSpec {
        grid: Grid {
            ny: 3,
            nz: 3,
            width: 40.0,
            height: 40.0,
        },
        period: 20.0,
        ..spec(Variance::TenMinute, 5)
    };
    let mut field = generate(&s).unwrap();
    let n_tower = 2;
    // slower than anything in the grid, so the scaling must cover the tower's values too
    field.tower = std::array::from_fn(|c| {
        (0..field.nt * n_tower)
            .map(|i| [-3.0, 1.5, -0.5][c] * (1.0 + (i % 7) as f64))
            .collect()
    });
    let mut bytes = Vec::new();
    bts::encode(&field, "tower", &mut bytes).unwrap();
    let back = bts::parse(&bytes).unwrap();
    assert_eq!(back.n_tower(), n_tower);
    for c in 0..3 {
        let all = field.velocity[c].iter().chain(&field.tower[c]);
        let range = all.clone().cloned().fold(f64::NEG_INFINITY, f64::max) - all.cloned().fold(f64::INFINITY, f64::min);
        let worst = field.tower[c]
            .iter()
            .zip(&back.tower[c])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            worst <= 1.02 * 0.5 * range / 65_535.0,
            "{}: tower off by {worst}",
            COMPONENTS[c]
        );
    }
    let mut again = Vec::new();
    bts::encode(&back, "tower", &mut again).unwrap();
    assert_eq!(again, bytes);
}
