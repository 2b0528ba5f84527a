//! Natural frequencies of a preset's monolithic model: what the scenes' spectra are checked against.

use super::ReferenceError;
use crate::linear::modes::{Boundary, modes};

/// Lowest non-zero natural frequency of a preset at full fidelity under `boundary`, Hz.
pub fn lowest_mode(preset: &str, boundary: Boundary) -> Result<f64, ReferenceError> {
    let params = crate::slaves::torsional::Params {
        preset: preset.into(),
        fidelity: "full".into(),
        integrator: "implicit".into(),
        damping_scale: 1.0,
        contact_ratio: 1.6,
        ..Default::default()
    };
    let built = params.build()?;
    let m = modes(&built.model, boundary, built.drivetrain.k_generator);
    m.frequencies_hz
        .into_iter()
        .find(|f| *f > 1e-6)
        .ok_or_else(|| ReferenceError::Model(format!("preset {preset}: no non-zero mode")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Holding the HSS adds a constraint: the lowest mode drops below the free–free one (drivetrain C:
    /// 2.53 Hz free–free, 0.81 Hz held, as the shutdown summary prints).
    #[test]
    fn holding_the_hss_lowers_the_first_mode() {
        let free = lowest_mode("C", Boundary::Disconnected).unwrap();
        let held = lowest_mode("C", Boundary::HssLocked).unwrap();
        assert!(
            (free - 2.534).abs() < 0.01 && (held - 0.813).abs() < 0.01,
            "{free} {held}"
        );
        assert!(lowest_mode("Q", Boundary::Disconnected).is_err());
    }
}
