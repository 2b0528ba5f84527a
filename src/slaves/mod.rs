//! FMU faces of the physics: each maps one modelDescription's variables onto a model and implements
//! [`crate::fmi2::slave::Slave`]. The `fmus/<name>` crates only export them.

pub mod generator;
pub mod rotor;
pub mod torsional;

use crate::fmi2::slave::{SlaveError, SlaveResult};
use serde::{Deserialize, Serialize};

/// One Real input with the time derivatives a master may send (fmi2SetRealInputDerivatives,
/// orders 1 and 2): u(τ) = u + u'·τ + u''·τ²/2 after the communication point. Setting the value
/// clears the derivatives; a step moves the expansion point along the polynomial.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct InputPolynomial(pub [f64; 3]);

impl InputPolynomial {
    pub fn value(&self) -> f64 {
        self.0[0]
    }

    pub fn set(&mut self, value: f64) {
        self.0 = [value, 0.0, 0.0];
    }

    pub fn set_derivative(&mut self, order: i32, value: f64) -> SlaveResult<()> {
        match order {
            1 | 2 => {
                self.0[order as usize] = value;
                Ok(())
            }
            _ => Err(SlaveError::new(format!(
                "derivative order {order} not supported (1 or 2)"
            ))),
        }
    }

    /// u(τ)
    pub fn at(&self, tau: f64) -> f64 {
        let w = self.0;
        w[0] + w[1] * tau + w[2] * tau * tau / 2.0
    }

    /// Moves the expansion point forward by `h`.
    pub fn advance(&mut self, h: f64) {
        let w = self.0;
        self.0 = [self.at(h), w[1] + w[2] * h, w[2]];
    }
}
