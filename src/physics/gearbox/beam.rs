//! A flexible shaft between two bodies as Timoshenko beam elements (one, or several with nodes
//! between them, model.rs): bending in both transverse planes with shear deformation, and axial
//! stretch. The element's stiffness is split into springs
//! along its eigenvectors (K = Σ λ_i v_i v_iᵀ), so the model carries it as it carries every other
//! spring: a row over the DOFs and a stiffness. Torsion stays the shaft's own spring (the published
//! torsional stiffness, and the torque the FMU reports).

use crate::solver::norms::max_abs;
use nalgebra::{Matrix4, SymmetricEigen};

/// Stiffness of a Timoshenko beam element in one plane, DOFs (w₁, φ₁, w₂, φ₂) with φ = dw/dz: EI the
/// bending stiffness, κGA the shear stiffness, L the length. Exact for loads at its ends (Przemieniecki,
/// *Theory of Matrix Structural Analysis*, §5.6).
pub fn bending_stiffness(ei: f64, kga: f64, length: f64) -> Matrix4<f64> {
    let l = length;
    let phi = 12.0 * ei / (kga * l * l);
    let c = ei / ((1.0 + phi) * l * l * l);
    c * Matrix4::new(
        12.0,
        6.0 * l,
        -12.0,
        6.0 * l,
        6.0 * l,
        (4.0 + phi) * l * l,
        -6.0 * l,
        (2.0 - phi) * l * l,
        -12.0,
        -6.0 * l,
        12.0,
        -6.0 * l,
        6.0 * l,
        (2.0 - phi) * l * l,
        -6.0 * l,
        (4.0 + phi) * l * l,
    )
}

/// The element's stiffness as springs: (stiffness λ_i, direction v_i) for every eigenvalue above
/// 1e-9 of the largest (the two rigid-body motions of a free element carry none).
pub fn springs(k: &Matrix4<f64>) -> Vec<(f64, [f64; 4])> {
    let e = SymmetricEigen::new(*k);
    let largest = max_abs(e.eigenvalues.as_slice());
    (0..4)
        .filter(|&i| e.eigenvalues[i] > 1e-9 * largest)
        .map(|i| {
            let v = e.eigenvectors.column(i);
            (e.eigenvalues[i], [v[0], v[1], v[2], v[3]])
        })
        .collect()
}

/// Section properties of a hollow circular shaft (outer and inner diameter, m): area, second moment of
/// area, and Cowper's shear coefficient κ at Poisson's ratio ν.
pub fn hollow_section(outer: f64, inner: f64, nu: f64) -> (f64, f64, f64) {
    let area = std::f64::consts::PI / 4.0 * (outer * outer - inner * inner);
    let second_moment = std::f64::consts::PI / 64.0 * (outer.powi(4) - inner.powi(4));
    let m = inner / outer;
    let m2 = (1.0 + m * m).powi(2);
    let kappa = 6.0 * (1.0 + nu) * m2 / ((7.0 + 6.0 * nu) * m2 + (20.0 + 12.0 * nu) * m * m);
    (area, second_moment, kappa)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cantilever (end 1 held) under an end load P deflects P·L³/(3EI) + P·L/(κGA) and turns
    /// P·L²/(2EI): Timoshenko's beam, exact at the ends of one element.
    #[test]
    fn cantilever_deflects_as_timoshenko() {
        let (e, g) = (2.1e11, 8.1e10);
        let (a, i, kappa) = hollow_section(0.4, 0.1, e / (2.0 * g) - 1.0);
        let l = 1.5;
        let k = bending_stiffness(e * i, kappa * g * a, l);
        let free = k.fixed_view::<2, 2>(2, 2).into_owned();
        let p = 1e5;
        let d = free.try_inverse().unwrap() * nalgebra::Vector2::new(p, 0.0);
        let w = p * l.powi(3) / (3.0 * e * i) + p * l / (kappa * g * a);
        assert!((d[0] / w - 1.0).abs() < 1e-12, "{} vs {w}", d[0]);
        assert!((d[1] / (p * l * l / (2.0 * e * i)) - 1.0).abs() < 1e-12);
        // solid section: Cowper's κ = 6(1+ν)/(7+6ν)
        let nu = 0.3;
        assert!((hollow_section(0.3, 0.0, nu).2 - 6.0 * 1.3 / 8.8).abs() < 1e-15);
    }

    /// The springs add back up to the element, and a rigid motion strains none of them.
    #[test]
    fn springs_rebuild_the_element() {
        let k = bending_stiffness(3.0e8, 2.0e9, 1.2);
        let s = springs(&k);
        assert_eq!(s.len(), 2, "two rigid-body motions carry no stiffness");
        let mut rebuilt = Matrix4::zeros();
        for (lambda, v) in &s {
            let v = nalgebra::Vector4::from(*v);
            rebuilt += *lambda * v * v.transpose();
        }
        assert!((rebuilt - k).norm() < 1e-9 * k.norm());
        // translation (1, 0, 1, 0) and rotation about end 1 (0, 1, L, 1)
        for rigid in [[1.0, 0.0, 1.0, 0.0], [0.0, 1.0, 1.2, 1.0]] {
            for (_, v) in &s {
                let strain: f64 = v.iter().zip(rigid).map(|(a, b)| a * b).sum();
                assert!(strain.abs() < 1e-12, "{strain}");
            }
        }
    }
}
