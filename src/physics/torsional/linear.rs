//! The linear view of the model: its matrices, highest angular frequency and static deflection.

use super::{Element, Section, TorsionalModel};

impl TorsionalModel {
    pub fn dofs(&self) -> usize {
        self.mass.len()
    }

    /// True when some element is nonlinear (backlash) so a step needs Newton iterations.
    pub fn has_backlash(&self) -> bool {
        self.backlash
    }

    pub fn has_stiffness_variation(&self) -> bool {
        self.stiffness_variation
    }

    /// Adds Σ_e w_e · g_e g_eᵀ to `matrix`, with the weight w_e = `weight(index, element)`: the one
    /// assembly loop behind the stiffness, damping and iteration matrices.
    pub fn assemble_into(&self, matrix: &mut nalgebra::DMatrix<f64>, weight: impl Fn(usize, &Element) -> f64) {
        for (index, e) in self.elements.iter().enumerate() {
            let w = weight(index, e);
            if w == 0.0 {
                continue;
            }
            for &(i, gi) in &e.coeffs {
                for &(j, gj) in &e.coeffs {
                    matrix[(i, j)] += w * gi * gj;
                }
            }
        }
    }

    fn assemble(&self, weight: impl Fn(usize, &Element) -> f64) -> nalgebra::DMatrix<f64> {
        let mut m = nalgebra::DMatrix::zeros(self.dofs(), self.dofs());
        self.assemble_into(&mut m, weight);
        m
    }

    /// Stiffness matrix with every element in contact at its nominal (mean) stiffness.
    pub fn stiffness_matrix(&self) -> nalgebra::DMatrix<f64> {
        self.assemble(|_, e| e.stiffness)
    }

    /// Stiffness and damping matrices with every element in contact at nominal stiffness.
    pub fn stiffness_and_damping(&self) -> (nalgebra::DMatrix<f64>, nalgebra::DMatrix<f64>) {
        (self.stiffness_matrix(), self.assemble(|_, e| e.damping))
    }

    /// Largest undamped natural angular frequency with every mesh at its stiffest, rad/s.
    pub fn max_angular_frequency(&self) -> f64 {
        let n = self.dofs();
        let k = self.assemble(|_, e| e.variation.map_or(e.stiffness, |v| v.k_double.max(v.k_single)));
        let inv_sqrt: Vec<f64> = self.mass.iter().map(|m| 1.0 / m.sqrt()).collect();
        let a = nalgebra::DMatrix::from_fn(n, n, |i, j| k[(i, j)] * inv_sqrt[i] * inv_sqrt[j]);
        let eig = nalgebra::SymmetricEigen::new(a);
        eig.eigenvalues.iter().cloned().fold(0.0, f64::max).sqrt()
    }

    /// Angles of a static equilibrium carrying `rotor_torque` at the LSS (balanced at the generator),
    /// rotor angle 0. Backlash gaps are closed on the loaded flank.
    /// Cut away from the rotor ([`Section::Drivetrain`]), the boundary's angle is the 0 the rotor's
    /// would be, and the grounded shaft carries the torque.
    pub fn static_deflection(&self, rotor_torque: f64) -> Result<Vec<f64>, String> {
        let n = self.dofs();
        if self.section == Section::Rotor || (n < 2 && self.section == Section::Whole) {
            return Ok(vec![0.0; n]);
        }
        let mut f = vec![0.0; n];
        if self.section == Section::Whole {
            f[self.rotor] += rotor_torque;
        }
        f[self.generator] -= rotor_torque / self.gear_ratio;
        // A loaded mesh with backlash carries k·(δ − b/2·sign): move that offset to the right-hand side.
        let mut rhs = f.clone();
        let probe = self.solve_pinned(&f)?;
        for e in &self.elements {
            if e.half_backlash > 0.0 {
                let sign = e.deflection(&probe).signum();
                for &(d, g) in &e.coeffs {
                    rhs[d] += e.stiffness * g * e.half_backlash * sign;
                }
            }
        }
        self.solve_pinned(&rhs)
    }

    /// Solves K θ = f with the rotor pinned (the free-free K is singular; cut from the rotor, the
    /// LSS's boundary holds the model).
    fn solve_pinned(&self, f: &[f64]) -> Result<Vec<f64>, String> {
        let n = self.dofs();
        let k = self.stiffness_matrix();
        let pinned = (self.section == Section::Whole).then_some(self.rotor);
        let keep: Vec<usize> = (0..n).filter(|&d| Some(d) != pinned).collect();
        let kr = nalgebra::DMatrix::from_fn(keep.len(), keep.len(), |i, j| k[(keep[i], keep[j])]);
        let fr = nalgebra::DVector::from_iterator(keep.len(), keep.iter().map(|&d| f[d]));
        let x = kr
            .lu()
            .solve(&fr)
            .ok_or("stiffness matrix is singular with the rotor held")?;
        let mut q = vec![0.0; n];
        for (i, &d) in keep.iter().enumerate() {
            q[d] = x[i];
        }
        Ok(q)
    }
}
