//! The d-shaft-cut scene's exact solution (scenes/d-shaft-cut: drivetrain D's undamped 2-mass model
//! cut in its main shaft across two torsional FMUs, free-free, rated rotor torque stepped at t = 0):
//! the two-mass problem, T_LSS(t) = T·J₂/(J₁ + J₂)·(1 − cos ωt), ω² = K·(1/J₁ + 1/J₂).

use crate::physics::torsional::TorsionalModel;
use crate::slaves::torsional::Params;

/// Rotor torque the scene applies at t = 0, N·m (scenes/d-shaft-cut/rotor.ssv).
pub const ROTOR_TORQUE: f64 = 385_000.0;

/// The parameters of the scene's two torsional FMUs (rotor.ssv, drivetrain.ssv): d-grid-step's
/// drivetrain (D, 2-mass, undamped) cut in two, with every shaft's stiffness scaled by
/// `stiffness_scale`.
pub fn params(stiffness_scale: f64) -> (Params, Params) {
    let section = |name: &str| Params {
        section: name.into(),
        shaft_stiffness_scale: stiffness_scale,
        ..super::grid_step::torsional_params()
    };
    (section("rotor"), section("drivetrain"))
}

/// The scene's two models, cut: (rotor section, drivetrain section).
pub fn models(stiffness_scale: f64) -> (TorsionalModel, TorsionalModel) {
    let (rotor, drivetrain) = params(stiffness_scale);
    let build = |p: Params| p.build().expect("preset D builds").model;
    (build(rotor), build(drivetrain))
}

/// The exact LSS torque of the scene at `times` (N·m) and its angular frequency (rad/s).
pub fn exact_lss_torque(stiffness_scale: f64, times: &[f64]) -> (Vec<f64>, f64) {
    let (rotor, drivetrain) = models(stiffness_scale);
    let lss = drivetrain.shafts[0].expect("an LSS");
    let e = &drivetrain.elements[lss.element];
    // the 2-mass shaft is LSS-referred: δ = θ_rotor − θ_generator/N, so J₂ = J_generator-side·N²
    let j1 = rotor.mass[0];
    let j2 = drivetrain.mass[0] / (e.coeffs[0].1 * e.coeffs[0].1);
    let omega = (e.stiffness * (1.0 / j1 + 1.0 / j2)).sqrt();
    let mean = ROTOR_TORQUE * j2 / (j1 + j2);
    (times.iter().map(|t| mean * (1.0 - (omega * t).cos())).collect(), omega)
}
