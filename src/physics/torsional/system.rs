//! The model as a [`SecondOrderSystem`] for the solver.

use super::{INPUT_BRAKE_COMMAND, Section, TorsionalModel};
use crate::solver::system::{Friction, InputLoad, Linearity, Mass, SecondOrderSystem};
use nalgebra::DMatrix;

/// Two pattern bits per element (flanks touching, double tooth contact), packed into u64 words.
fn set_bit(key: &mut Vec<u64>, bit: usize) {
    let word = bit / 64;
    if key.len() <= word {
        key.resize(word + 1, 0);
    }
    key[word] |= 1 << (bit % 64);
}

impl SecondOrderSystem for TorsionalModel {
    fn dofs(&self) -> usize {
        self.mass.len()
    }

    fn linearity(&self) -> Linearity {
        if self.backlash || self.stiffness_variation {
            Linearity::PiecewiseLinear
        } else {
            Linearity::Linear
        }
    }

    fn mass(&self) -> Mass<'_> {
        Mass::Diagonal(&self.mass)
    }

    fn input_loads(&self) -> &[InputLoad] {
        &self.input_loads
    }

    fn internal_forces(&self, _t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|x| *x = 0.0);
        for e in &self.elements {
            let f = e.force(e.stiffness_at(q), e.deflection(q), e.deflection(v));
            for &(d, g) in &e.coeffs {
                out[d] += g * f;
            }
        }
    }

    fn add_tangent(&self, _t: f64, q: &[f64], _v: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>) {
        self.assemble_into(j, |_, e| {
            if e.contact(e.deflection(q)).1 {
                c_k * e.stiffness_at(q) + c_c * e.damping
            } else {
                0.0
            }
        });
    }

    fn factor_key(&self, _t: f64, q: &[f64], key: &mut Vec<u64>) {
        key.clear();
        if !self.backlash && !self.stiffness_variation {
            return;
        }
        key.push(0);
        for (i, e) in self.elements.iter().enumerate() {
            if e.half_backlash > 0.0 && e.contact(e.deflection(q)).1 {
                set_bit(key, 2 * i);
            }
            if let Some(v) = &e.variation
                && v.stiffness(q[v.dof]) == v.k_double
            {
                set_bit(key, 2 * i + 1);
            }
        }
    }

    // inlined: the driver asks twice a communication step whether the brake acts, and the call with
    // its Option returned through memory took 3 % of the torsional FMU's step (perf)
    #[inline]
    fn friction(&self, u: &[f64]) -> Option<Friction> {
        self.brake.friction(self.generator, u[INPUT_BRAKE_COMMAND])
    }

    /// None when cut from the rotor: the grounded shaft has no rigid rotation.
    fn rigid_mode(&self) -> Option<(&[f64], usize)> {
        (self.section != Section::Drivetrain).then_some((&self.speed_ratio[..], 0))
    }
}
