//! Natural frequencies and mode shapes of a torsional model: K x = ω² M x, solved by the Cholesky
//! reduction (M is diagonal, so L = √M): A = M^{-1/2} K M^{-1/2} is symmetric, its eigenvectors y give
//! M-orthonormal modes x = M^{-1/2} y (STYLE.md habit 11: no QZ for a symmetric pencil).

use super::torsional::TorsionalModel;
use serde::Serialize;

/// How the generator end is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Boundary {
    /// Variable speed or disconnected: free–free, one zero (rigid-body) mode.
    Disconnected,
    /// Fixed-speed generator on the grid: electrical spring K_gen from the generator to ground (free–fixed).
    Connected,
    /// The HSS brake holds the generator side at standstill.
    HssLocked,
}

impl Boundary {
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "disconnected" | "free" | "free-free" => Some(Self::Disconnected),
            "connected" | "free-fixed" => Some(Self::Connected),
            "locked" | "hss-locked" | "braked" => Some(Self::HssLocked),
            _ => None,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Modes {
    pub dof_names: Vec<String>,
    pub frequencies_hz: Vec<f64>,
    /// One shape per mode, an entry per DOF, referred to the LSS (each angle divided by the DOF's
    /// speed ratio, so rigid rotation is a flat line) and scaled to a largest magnitude of 1. A locked
    /// generator DOF appears with amplitude 0.
    pub shapes: Vec<Vec<f64>>,
    /// Index of the DOF holding the largest share of each mode's kinetic energy (m·x²).
    pub dominant_dof: Vec<usize>,
}

pub fn modes(model: &TorsionalModel, boundary: Boundary, k_generator: f64) -> Modes {
    let mut k = model.stiffness_matrix();
    let g = model.generator;
    if boundary == Boundary::Connected {
        k[(g, g)] += k_generator;
    }
    let keep: Vec<usize> = (0..model.dofs())
        .filter(|&d| !(boundary == Boundary::HssLocked && d == g))
        .collect();
    let n = keep.len();
    let inv_sqrt: Vec<f64> = keep.iter().map(|&d| 1.0 / model.mass[d].sqrt()).collect();
    let a = nalgebra::DMatrix::from_fn(n, n, |i, j| k[(keep[i], keep[j])] * inv_sqrt[i] * inv_sqrt[j]);
    let eig = nalgebra::SymmetricEigen::new(a);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&x, &y| eig.eigenvalues[x].total_cmp(&eig.eigenvalues[y]));
    let scale = eig.eigenvalues.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut frequencies_hz = Vec::with_capacity(n);
    let mut shapes = Vec::with_capacity(n);
    let mut dominant_dof = Vec::with_capacity(n);
    for &m in &order {
        // the rigid-body eigenvalue comes out as round-off of either sign
        let lambda = if eig.eigenvalues[m].abs() < 1e-12 * scale {
            0.0
        } else {
            eig.eigenvalues[m].max(0.0)
        };
        frequencies_hz.push(lambda.sqrt() / std::f64::consts::TAU);
        let mut shape = vec![0.0; model.dofs()];
        let mut energy = (0, 0.0);
        for (i, &d) in keep.iter().enumerate() {
            let x = eig.eigenvectors[(i, m)] * inv_sqrt[i];
            if model.mass[d] * x * x > energy.1 {
                energy = (d, model.mass[d] * x * x);
            }
            shape[d] = x / model.speed_ratio[d];
        }
        dominant_dof.push(energy.0);
        let peak = shape
            .iter()
            .cloned()
            .fold(0.0f64, |p, v| if v.abs() > p.abs() { v } else { p });
        if peak != 0.0 {
            shape.iter_mut().for_each(|v| *v /= peak);
        }
        shapes.push(shape);
    }
    Modes {
        dof_names: model.dof_names.clone(),
        frequencies_hz,
        shapes,
        dominant_dof,
    }
}
