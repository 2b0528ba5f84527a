//! The natural frequencies and mode shapes of a drivetrain preset chosen by name, as the command line
//! and the thesis name the choices (preset A–D or P; fidelity 2, 5 or full; generator connected,
//! disconnected or locked; lumping physical or thesis): `windrive modes`, `campbell` and
//! `step-response` print them, the reproduction sets them beside the thesis's.

use crate::linear::modes::{Boundary, Modes, modes};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::torsional::{Fidelity, Lumping, ModelOptions, TorsionalModel};
use anyhow::anyhow;

/// The preset and the modes of its model at `fidelity` with the generator `generator`.
pub fn preset_modes(
    preset: &str,
    fidelity: &str,
    generator: &str,
    lumping: &str,
) -> anyhow::Result<(Drivetrain, Modes)> {
    let dt = Drivetrain::preset(preset).ok_or_else(|| anyhow!("unknown preset {preset:?}: use A, B, C, D or P"))?;
    let f = Fidelity::parse(fidelity).ok_or_else(|| anyhow!("unknown fidelity {fidelity:?}: use 2, 5 or full"))?;
    let b = Boundary::parse(generator)
        .ok_or_else(|| anyhow!("unknown --generator {generator:?}: use connected, disconnected or locked"))?;
    let lumping =
        Lumping::parse(lumping).ok_or_else(|| anyhow!("unknown --lumping {lumping:?}: use physical or thesis"))?;
    let options = ModelOptions {
        lumping,
        ..ModelOptions::default()
    };
    let model = TorsionalModel::new(&dt, f, &options).map_err(|e| anyhow!(e))?;
    let m = modes(&model, b, dt.k_generator);
    Ok((dt, m))
}
