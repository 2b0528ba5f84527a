//! `windrive modes`.

use crate::studies::preset_modes::preset_modes;
use crate::studies::reproduce::thesis_values;
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
    /// The 6-DOF gearbox instead of the torsional model: a preset (grc750, nrel5mw, c2mw,
    /// paper1p5mw, planetary-spur) or a description file; modes about the unloaded state with every
    /// mesh engaged, each classified (rigid, rotational, translational, planet, axial-tilting)
    #[arg(long, value_name = "PRESET|FILE")]
    pub gearbox: Option<String>,
    /// Print {"frequencies_hz": [...], "dof_names": [...], "shapes": [[...]]} for scripts (with
    /// --gearbox: {"frequencies_hz": [...], "modes": [{"frequency_hz", "family", "torsional_projection", "dominant_body"}]})
    #[arg(long)]
    pub json: bool,
    /// Write a mode-shape plot (.png or .svg)
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

/// `--gearbox`: the 6-DOF gearbox's modes, a table or JSON, and a plot of frequency against torsional share.
fn run_gearbox(args: &ModesArgs, name: &str) -> anyhow::Result<()> {
    use crate::linear::gearbox_modes;
    use crate::physics::gearbox::{Description, Gearbox};
    let d = Description::load(name)?;
    let g = Gearbox::new(&d).map_err(|e| anyhow!("{name}: {e}"))?;
    let m = gearbox_modes::modes(&g);
    if let Some(path) = &args.plot {
        crate::plot::gearbox_modes(path, &d.name, &m).with_context(|| format!("writing {}", path.display()))?;
    }
    if args.json {
        let frequencies: Vec<f64> = m.iter().map(|x| x.frequency_hz).collect();
        println!(
            "{}",
            serde_json::json!({"gearbox": d.name, "frequencies_hz": frequencies, "modes": m})
        );
        return Ok(());
    }
    println!(
        "{}: {} DOF (6 per body), gear ratio {:.3}; every mesh engaged, unloaded, at rest",
        d.name,
        g.dofs(),
        g.gear_ratio
    );
    print!("{}", gearbox_modes::table(&m));
    if let Some(path) = &args.plot {
        println!("plot written to {}", path.display());
    }
    Ok(())
}

pub fn run(args: &ModesArgs) -> anyhow::Result<()> {
    if let Some(name) = &args.gearbox {
        return run_gearbox(args, name);
    }
    let (dt, m) = preset_modes(&args.preset, &args.fidelity, &args.generator, &args.lumping)?;
    if let Some(path) = &args.plot {
        crate::plot::mode_shapes(
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
    if dt.name == "D" && m.dof_names.len() == 5 && args.generator.starts_with('d') {
        let thesis: Vec<String> = thesis_values("D 5-mass, free–free, mode")?
            .iter()
            .map(f64::to_string)
            .collect();
        let (last, rest) = thesis.split_last().context("no thesis values for D's 5-mass modes")?;
        println!(
            "thesis ch. 6 (Fig. 6.6) gives {} and {last} Hz for this model; its Table 4.2 values in its\n\
             Eq. 4.9 lumping give 2.524, 324.5, 476.7, 1974 Hz (--lumping thesis): the text's frequencies do not\n\
             follow from its own equations (docs/DRIVETRAINS.md)",
            rest.join(", ")
        );
    }
    if let Some(path) = &args.plot {
        println!("mode shapes written to {}", path.display());
    }
    Ok(())
}
