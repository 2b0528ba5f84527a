//! `windrive modes`.

use crate::physics::drivetrain::Drivetrain;
use crate::physics::modes::{Boundary, Modes, modes};
use crate::physics::torsional::{Fidelity, Lumping, ModelOptions, TorsionalModel};
use anyhow::{Context, anyhow};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ModesArgs {
    /// Drivetrain preset: A, B, C or D (D = NREL GRC 750 kW)
    #[arg(long, default_value = "D")]
    pub preset: String,
    /// 2 (rotor + lumped rest), 5 (one DOF per stage) or full (one DOF per body)
    #[arg(long, default_value = "full")]
    pub fidelity: String,
    /// connected (K_gen to ground), disconnected (free–free) or locked (HSS held by the brake)
    #[arg(long, default_value = "connected")]
    pub generator: String,
    /// Inertia lumping of fidelity 2 and 5: physical (planet spin included, the default) or thesis
    /// (its Eq. 4.9 leaves the planets' spin out; moves D's fourth 5-mass mode by 8.6 %)
    #[arg(long, default_value = "physical")]
    pub lumping: String,
    /// Print {"frequencies_hz": [...], "dof_names": [...], "shapes": [[...]]} for scripts
    #[arg(long)]
    pub json: bool,
    /// Write a mode-shape plot (.png or .svg)
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

pub fn compute(preset: &str, fidelity: &str, generator: &str, lumping: &str) -> anyhow::Result<(Drivetrain, Modes)> {
    let dt = Drivetrain::preset(preset).ok_or_else(|| anyhow!("unknown preset {preset:?}: use A, B, C or D"))?;
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

pub fn run(args: &ModesArgs) -> anyhow::Result<()> {
    let (dt, m) = compute(&args.preset, &args.fidelity, &args.generator, &args.lumping)?;
    if let Some(path) = &args.plot {
        super::plot::mode_shapes(
            path,
            &format!(
                "Drivetrain {} ({} fidelity, generator {})",
                dt.name, args.fidelity, args.generator
            ),
            &m,
        )
        .with_context(|| format!("writing {}", path.display()))?;
    }
    if args.json {
        println!("{}", serde_json::to_string(&m)?);
        return Ok(());
    }
    println!(
        "Drivetrain {}: {} DOF, gear ratio {:.3}, generator {}{}",
        dt.name,
        m.dof_names.len(),
        dt.gear_ratio(),
        args.generator,
        if args.generator.starts_with('c') {
            format!(
                " (K_gen = {:.3e} N·m/rad{})",
                dt.k_generator,
                if dt.k_generator_estimated {
                    ", estimated: see README"
                } else {
                    ""
                }
            )
        } else {
            String::new()
        }
    );
    println!("{:>4}  {:>12}  dominant DOF", "mode", "f / Hz");
    println!("      (dominant DOF: largest share of the mode's kinetic energy)");
    for (i, (f, d)) in m.frequencies_hz.iter().zip(&m.dominant_dof).enumerate() {
        println!("{:>4}  {:>12.4}  {}", i + 1, f, m.dof_names[*d]);
    }
    if let Some(path) = &args.plot {
        println!("mode shapes written to {}", path.display());
    }
    Ok(())
}
