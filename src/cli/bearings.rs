//! `windrive bearings`: every rolling bearing of a gearbox rated from one series of the `gearbox6dof`
//! FMU (ISO 281 rating from the roller sets, equivalent load, revolutions from the kinematics, Miner)
//! through [`crate::analysis::rating::bearing_set`].

use crate::analysis::rating::bearing_set::BearingDamage;
use crate::studies::life::bearing_table;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct BearingsArgs {
    /// The series: a CSV of `windrive run` with the gearbox6dof FMU's bearing loads and speeds
    #[arg(required_unless_present = "channels")]
    pub series: Option<PathBuf>,
    /// The gearbox the series ran: a gearbox6dof preset (grc750, c2mw, paper1p5mw, nrel5mw,
    /// planetary-spur) or a description file. Its roller sets give each bearing's rating; bearings
    /// without one are not rated
    #[arg(long, default_value = "grc750")]
    pub gearbox: String,
    /// The scene's name of the gearbox6dof FMU, the channels' prefix
    #[arg(long, default_value = "gearbox")]
    pub component: String,
    #[command(flatten)]
    pub rating: super::rating::RatingOptions,
}

pub fn run(args: &BearingsArgs) -> anyhow::Result<()> {
    let table = bearing_table(&args.gearbox, &args.component)?;
    args.rating.check()?;
    if args.rating.channels {
        println!("{}", table.channels().join("\n"));
        return Ok(());
    }
    let series = args.series.as_ref().expect("clap requires it without --channels");
    let rated = table.rate_series(series, args.rating.transient)?;
    super::rating::print_rated(&rated, args.rating.json, text)
}

fn text(rated: &[BearingDamage]) -> String {
    let mut s = format!(
        "{:<14} {:<12} {:>3} {:>6} {:>8} {:>8} {:>9} {:>9} {:>11} {:>11} {:>11} {:>11}\n",
        "bearing", "type", "Z", "α", "C_r", "n/n_rot", "P_eq", "P_max", "revolutions", "D/day", "L10h", "thesis/day"
    );
    s.push_str(&format!(
        "{:<14} {:<12} {:>3} {:>6} {:>8} {:>8} {:>9} {:>9} {:>11} {:>11} {:>11} {:>11}\n",
        "", "", "", "deg", "kN", "", "kN", "kN", "", "", "h", ""
    ));
    for r in rated {
        let kind = serde_json::to_value(r.kind)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default();
        let rows = if r.rows > 1 {
            format!("{}×", r.rows)
        } else {
            String::new()
        };
        s.push_str(&format!(
            "{:<14} {:<12} {:>3} {:>6.1} {:>8.0} {:>8.3} {:>9.1} {:>9.1} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e}\n",
            r.name,
            format!("{rows}{kind}"),
            r.rollers,
            r.contact_angle_deg,
            r.dynamic_load_rating / 1e3,
            r.speed_ratio,
            r.equivalent_load / 1e3,
            r.max_equivalent_load / 1e3,
            r.revolutions,
            r.damage_per_day,
            r.life_hours,
            r.thesis_damage_per_day,
        ));
    }
    s
}
