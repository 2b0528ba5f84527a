//! `windrive gears`: every gear tooth of a gearbox rated from one series (ISO 6336 stresses, load
//! cycles from the speeds, two-slope S-N, Miner) through [`crate::analysis::rating::gear_set`].

use crate::analysis::rating::gear_set::{ToothDamage, channels, fmu_mesh_force, gear_table, rate_series};
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
    args.rating.check()?;
    if args.rating.channels {
        println!("{}", channels(&teeth).join("\n"));
        return Ok(());
    }
    let series = args.series.as_ref().expect("clap requires it without --channels");
    let rated = rate_series(series, &teeth, args.rating.transient)?;
    super::rating::print_rated(&rated, args.rating.json, text)
}

fn text(rated: &[ToothDamage]) -> String {
    let mut s = format!(
        "{:<5} {:<42} {:>6} {:>6} {:>10} {:>10} {:>11} {:>12} {:>12}\n",
        "tooth", "", "Y_F", "Y_S", "σ_H max", "σ_F max", "cycles", "D_flank/day", "D_root/day"
    );
    s.push_str(&format!(
        "{:<5} {:<42} {:>6} {:>6} {:>10} {:>10} {:>11} {:>12} {:>12}\n",
        "", "", "", "", "MPa", "MPa", "", "", ""
    ));
    let or_dash = |x: f64, f: &dyn Fn(f64) -> String| if x.is_nan() { "-".to_string() } else { f(x) };
    // a stress of 0 is one the tooth is not rated for
    let mpa = |x: f64| {
        if x > 0.0 {
            format!("{:.1}", x / 1e6)
        } else {
            "-".to_string()
        }
    };
    for r in rated {
        s.push_str(&format!(
            "{:<5} {:<42} {:>6} {:>6} {:>10} {:>10} {:>11.4e} {:>12} {:>12}\n",
            r.name,
            r.description,
            or_dash(r.y_f, &|x| format!("{x:.3}")),
            or_dash(r.y_s, &|x| format!("{x:.3}")),
            mpa(r.max_contact_stress),
            mpa(r.max_root_stress),
            r.load_cycles,
            or_dash(r.flank_damage_per_day, &|x| format!("{x:.4e}")),
            or_dash(r.root_damage_per_day, &|x| format!("{x:.4e}")),
        ));
    }
    s
}
