//! `windrive gears`: every gear tooth of a gearbox rated from one series (ISO 6336 stresses, load
//! cycles from the speeds, two-slope S-N, Miner) through [`crate::analysis::rating::gear_set`].

use crate::analysis::rating::gear_set::{
    channels, fmu_mesh_force, gear_table, rate_series, table, with_dynamic_factor, with_model_face_load,
};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct GearsArgs {
    /// The series: a CSV of `windrive run` with the torsional FMU's mesh forces and speeds
    #[arg(required_unless_present = "channels")]
    pub series: Option<PathBuf>,
    /// Gear table: P, the paper's 1.5 MW gearbox (paper Table 4, a face width per mesh), or a
    /// gearbox6dof description, a preset (grc750, paper1p5mw, c2mw, nrel5mw, planetary-spur) or a file:
    /// its teeth, modules, helix angles, profile shifts and face widths, every gear case-carburised
    /// 18CrNiMo7-6 and every ring through-hardened 34CrNiMo6 (estimates: a description names no material)
    #[arg(long, default_value = "P")]
    pub gearbox: String,
    /// Which FMU's outputs the series holds: torsional (preset P; its mesh forces are transverse,
    /// torque over base radius) or gearbox6dof (gearbox = paper1p5mw; its mesh forces are normal to the
    /// teeth, larger by 1/cos β_b on the helical stage)
    #[arg(long, default_value = "torsional", value_parser = ["torsional", "gearbox6dof"])]
    pub fmu: String,
    /// The scene's name of that FMU, the channels' prefix [default: torsional for --fmu torsional,
    /// gearbox for --fmu gearbox6dof, as the repository's scenes name them]
    #[arg(long)]
    pub component: Option<String>,
    /// The face load factor K_Hβ (K_Fβ = K_Hβ^N_F): `one` rates the nominal stresses, as the paper
    /// does; `model` takes each sample's K_Hβ from gearbox6dof's face_load_factor_<mesh> outputs (its
    /// sliced meshes' largest over mean slice load: misalignment from the shafts, bearings and carrier,
    /// lead errors), with --fmu gearbox6dof
    #[arg(long, default_value = "one", value_parser = ["one", "model"])]
    pub face_load: String,
    /// ISO 6336-1's dynamic factor K_v on every mesh (σ_H ∝ √K_v, σ_F ∝ K_v): 1 rates the simulated load,
    /// which at mean mesh stiffness holds no tooth-mesh dynamics; IEC 61400-4 asks for at least 1.05
    /// (`windrive gearbox --dynamic-factor` gives each mesh's from the model and ISO's method B)
    #[arg(long, value_name = "K_V", default_value_t = 1.0)]
    pub dynamic_factor: f64,
    #[command(flatten)]
    pub rating: super::rating::RatingOptions,
}

pub fn run(args: &GearsArgs) -> anyhow::Result<()> {
    let (kind, default_component) = fmu_mesh_force(&args.fmu).expect("clap allows only the FMUs it knows");
    let component = args.component.as_deref().unwrap_or(default_component);
    let teeth = gear_table(&args.gearbox, component, kind).map_err(|e| {
        anyhow::anyhow!(
            "--gearbox {:?}: use P (the paper's gear table) or a gearbox6dof description: {e}",
            args.gearbox
        )
    })?;
    let teeth = if args.face_load == "model" {
        with_model_face_load(teeth).ok_or_else(|| {
            anyhow::anyhow!(
                "--face-load model reads gearbox6dof's face_load_factor_<mesh> outputs: use it with --fmu gearbox6dof"
            )
        })?
    } else {
        teeth
    };
    let teeth = with_dynamic_factor(teeth, args.dynamic_factor).ok_or_else(|| {
        anyhow::anyhow!(
            "--dynamic-factor {}: a number ≥ 1 (ISO 6336-1's K_v)",
            args.dynamic_factor
        )
    })?;
    args.rating.check()?;
    if args.rating.channels {
        println!("{}", channels(&teeth).join("\n"));
        return Ok(());
    }
    let series = args.series.as_ref().expect("clap requires it without --channels");
    let rated = rate_series(series, &teeth, args.rating.transient)?;
    super::rating::print_rated(&rated, args.rating.json, table)
}
