//! Time integration of second-order systems M(q)·a + f_int(t, q, v) = B·u(t), generic over the
//! model: the contract ([`system`]), implicit integrators of the generalised-α family with a Newton
//! iteration ([`alpha`]: Newmark average acceleration, HHT-α, generalised-α), explicit RK4
//! ([`rk4`]), cached factorisations ([`factor`], dense LU in [`lu`], LU on J's sparsity pattern in
//! [`pattern_lu`]) and the driver that sub-steps, halves and reports friction events within one
//! communication step ([`driver`]), and the norm their convergence tests take ([`norms`]). No module
//! here knows a model; `physics` implements [`system::SecondOrderSystem`]. Integrators keep their
//! scratch memory, so a step allocates nothing.

pub mod alpha;
pub mod driver;
pub mod factor;
pub mod lu;
pub mod norms;
pub mod pattern_lu;
pub mod rk4;
pub mod state;
pub mod system;

pub use driver::{Driver, Event, Method};
pub use state::{DynState, SolverError, Statistics};
pub use system::{Friction, InputLoad, Linearisation, Linearity, Mass, SecondOrderSystem};
