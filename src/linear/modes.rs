//! Natural frequencies and mode shapes: K x = ω² M x of any linearised model ([`modal_analysis`]),
//! solved by the Cholesky reduction M = L·Lᵀ, A = L⁻¹ K L⁻ᵀ symmetric, modes x = L⁻ᵀ y
//! (M-orthonormal; no QZ for a symmetric pencil), and the torsional drivetrain's boundaries.

use crate::physics::torsional::TorsionalModel;
use crate::solver::system::{Linearisation, SecondOrderSystem};

use nalgebra::DMatrix;
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

/// The stiffness matrix `k` under a generator boundary (K_gen to ground when connected) and the DOFs
/// that stay free (all but the generator when the HSS is locked).
pub fn with_boundary(
    model: &TorsionalModel,
    mut k: nalgebra::DMatrix<f64>,
    boundary: Boundary,
    k_generator: f64,
) -> (nalgebra::DMatrix<f64>, Vec<usize>) {
    let g = model.generator;
    if boundary == Boundary::Connected {
        k[(g, g)] += k_generator;
    }
    let keep = (0..model.dofs())
        .filter(|&d| !(boundary == Boundary::HssLocked && d == g))
        .collect();
    (k, keep)
}

/// M-orthonormal eigenpairs of K x = ω² M x restricted to the DOFs `keep`, for any symmetric
/// positive definite M (diagonal or with 6×6 body blocks): M = L·Lᵀ, A = L⁻¹·K·L⁻ᵀ is symmetric, its
/// eigenvectors y give x = L⁻ᵀ·y. Returns (ω² per pair, x as columns over the kept DOFs).
pub fn eigenpairs_of(mass: &DMatrix<f64>, stiffness: &DMatrix<f64>, keep: &[usize]) -> (Vec<f64>, DMatrix<f64>) {
    let n = keep.len();
    let m = DMatrix::from_fn(n, n, |i, j| mass[(keep[i], keep[j])]);
    let k = DMatrix::from_fn(n, n, |i, j| stiffness[(keep[i], keep[j])]);
    let l = m.cholesky().expect("the mass matrix is positive definite").l();
    let l_inv_k = l.solve_lower_triangular(&k).expect("L is invertible");
    let a = l.solve_lower_triangular(&l_inv_k.transpose()).expect("L is invertible");
    // symmetrise the rounding before the symmetric solver
    let a = (&a + a.transpose()) * 0.5;
    let eig = nalgebra::SymmetricEigen::new(a);
    let x = l
        .transpose()
        .solve_upper_triangular(&eig.eigenvectors)
        .expect("L is invertible");
    (eig.eigenvalues.iter().copied().collect(), x)
}

/// Natural frequencies and shapes of any linearised model over the DOFs `keep`, sorted by
/// frequency. Shapes are divided by `reference` per DOF (e.g. each DOF's speed ratio, so rigid
/// rotation is flat), cover every DOF (0 where not kept) and peak at 1; the dominant DOF holds the
/// largest share of the mode's kinetic energy (M_dd·x_d²).
pub fn modal_analysis(lin: &Linearisation, keep: &[usize], dof_names: &[String], reference: &[f64]) -> Modes {
    let (eigenvalues, x) = eigenpairs_of(&lin.mass, &lin.stiffness, keep);
    let n = keep.len();
    let dofs = lin.mass.nrows();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| eigenvalues[a].total_cmp(&eigenvalues[b]));
    let scale = eigenvalues.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut frequencies_hz = Vec::with_capacity(n);
    let mut shapes = Vec::with_capacity(n);
    let mut dominant_dof = Vec::with_capacity(n);
    for &m in &order {
        // the rigid-body eigenvalue comes out as round-off of either sign
        let lambda = if eigenvalues[m].abs() < 1e-12 * scale {
            0.0
        } else {
            eigenvalues[m].max(0.0)
        };
        frequencies_hz.push(lambda.sqrt() / std::f64::consts::TAU);
        let mut shape = vec![0.0; dofs];
        let mut energy = (0, 0.0);
        for (i, &d) in keep.iter().enumerate() {
            let xd = x[(i, m)];
            let e = lin.mass[(d, d)] * xd * xd;
            if e > energy.1 {
                energy = (d, e);
            }
            shape[d] = xd / reference[d];
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
        dof_names: dof_names.to_vec(),
        frequencies_hz,
        shapes,
        dominant_dof,
    }
}

/// The torsional model linearised (every mesh in contact at its mean stiffness) under `boundary`,
/// and the DOFs that stay free.
pub fn linearised(model: &TorsionalModel, boundary: Boundary, k_generator: f64) -> (Linearisation, Vec<usize>) {
    // nominal stiffness everywhere: a mesh with backlash is linearised in contact, a time-varying
    // one at its mean
    let (k, damping) = model.stiffness_and_damping();
    let (stiffness, keep) = with_boundary(model, k, boundary, k_generator);
    let mass = model.mass().to_matrix();
    (
        Linearisation {
            mass,
            damping,
            stiffness,
        },
        keep,
    )
}

fn eigenpairs(
    model: &TorsionalModel,
    boundary: Boundary,
    k_generator: f64,
) -> (Vec<usize>, Vec<f64>, nalgebra::DMatrix<f64>) {
    let (lin, keep) = linearised(model, boundary, k_generator);
    let (lambda, x) = eigenpairs_of(&lin.mass, &lin.stiffness, &keep);
    (keep, lambda, x)
}

/// Exact response of the undamped linear model, at rest in its reference state, to a torque
/// `torque` applied at DOF `dof` from t = 0: q(t) = Σ x_i (x_iᵀF / ω_i²)(1 − cos ω_i t) (modal
/// superposition). Returns q at each time (every DOF; a locked DOF stays 0). The boundary must hold
/// the model (Connected or HssLocked): a free–free model has a rigid mode that drifts.
pub fn undamped_step_response(
    model: &TorsionalModel,
    boundary: Boundary,
    k_generator: f64,
    dof: usize,
    torque: f64,
    times: &[f64],
) -> Vec<Vec<f64>> {
    assert!(
        boundary != Boundary::Disconnected,
        "a free-free model has no static response"
    );
    let (keep, lambda, x) = eigenpairs(model, boundary, k_generator);
    let at = keep.iter().position(|&d| d == dof).expect("the loaded DOF is not held");
    times
        .iter()
        .map(|&t| {
            let mut q = vec![0.0; model.dofs()];
            for m in 0..keep.len() {
                let amplitude = x[(at, m)] * torque / lambda[m];
                let c = 1.0 - (lambda[m].sqrt() * t).cos();
                for (i, &d) in keep.iter().enumerate() {
                    q[d] += x[(i, m)] * amplitude * c;
                }
            }
            q
        })
        .collect()
}

pub fn modes(model: &TorsionalModel, boundary: Boundary, k_generator: f64) -> Modes {
    let (lin, keep) = linearised(model, boundary, k_generator);
    modal_analysis(&lin, &keep, &model.dof_names, &model.speed_ratio)
}
