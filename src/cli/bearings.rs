//! `windrive bearings`: every rolling bearing of a gearbox rated from one series of the `gearbox6dof`
//! FMU (ISO 281 rating from the roller sets, equivalent load, revolutions from the kinematics, Miner)
//! through [`crate::analysis::rating::bearing_set`], with ISO 281's modified life a_ISO·L10 beside the
//! basic L10 ([`crate::analysis::rating::life_modification`]).

use crate::analysis::rating::bearing_set;
use crate::analysis::rating::life_modification::Lubrication;
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
    /// The oil's kinematic viscosity at 40 °C and 100 °C, mm²/s, for a_ISO (default: 320,24, an ISO
    /// VG 320 mineral gear oil; an estimate, no source gives the gearbox's oil)
    #[arg(long, value_name = "NU40,NU100", value_delimiter = ',')]
    pub oil_viscosity: Option<Vec<f64>>,
    /// The bearings' operating temperature, °C, for a_ISO (default: 65, an estimate; 50–80 °C is the
    /// range to try)
    #[arg(long)]
    pub oil_temperature: Option<f64>,
    /// ISO 281's contamination factor e_C, for a_ISO (default: 0.5, an estimate: 0.8–0.6 normal
    /// cleanliness, 0.6–0.4 slight contamination for bearings of 100 mm pitch diameter and more)
    #[arg(long)]
    pub contamination: Option<f64>,
    #[command(flatten)]
    pub rating: super::rating::RatingOptions,
}

impl BearingsArgs {
    /// The lubrication the options give, checked.
    fn lubrication(&self) -> anyhow::Result<Lubrication> {
        let viscosity = match self.oil_viscosity.as_deref() {
            None => None,
            Some(&[v40, v100]) => Some([v40, v100]),
            Some(v) => anyhow::bail!("--oil-viscosity {v:?}: two values, ν at 40 °C and at 100 °C, e.g. 320,24"),
        };
        Lubrication::given(viscosity, self.oil_temperature, self.contamination)
            .map_err(|e| anyhow::anyhow!("--oil-viscosity, --oil-temperature, --contamination: {e}"))
    }
}

pub fn run(args: &BearingsArgs) -> anyhow::Result<()> {
    let mut table = bearing_table(&args.gearbox, &args.component)?;
    args.rating.check()?;
    table.lubrication = args.lubrication()?;
    if args.rating.channels {
        println!("{}", table.channels().join("\n"));
        return Ok(());
    }
    let series = args.series.as_ref().expect("clap requires it without --channels");
    let rated = table.rate_series(series, args.rating.transient)?;
    super::rating::print_rated(&rated, args.rating.json, bearing_set::table)
}
