//! `windrive bearings`: every rolling bearing of a gearbox rated from one series of the `gearbox6dof`
//! FMU (ISO 281 rating from the roller sets, equivalent load, revolutions from the kinematics, Miner)
//! through [`crate::analysis::rating::bearing_set`].

use crate::analysis::rating::bearing_set;
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
    super::rating::print_rated(&rated, args.rating.json, bearing_set::table)
}
