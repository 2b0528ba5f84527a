//! `windrive life`: parses the climate, the cases and the component ([`crate::studies::life`]), calls
//! [`crate::analysis::fatigue::lifetime`] and prints its lifetime DELs and gear or bearing damage.

use crate::analysis::fatigue::campaign::{self, CampaignTable};
use crate::analysis::fatigue::lifetime::{Case, Climate, GearLife, GearSpec, Lifetime};
use crate::analysis::rating::limits::LIMITS;
use crate::studies::life::{GearOptions, bearing_text, gear_spec, gear_text, named_bearing, wind_distribution};
use anyhow::{Context, bail};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct LifeArgs {
    /// Normal-operation CSV (stands for every operating hour)
    #[arg(long, required_unless_present = "cases")]
    pub normal: Option<PathBuf>,
    /// Shutdown CSV (one event)
    #[arg(long)]
    pub shutdown: Option<PathBuf>,
    /// Load channel, e.g. torsional.mesh_force_sun_planet_1 or torsional.hss_torque
    #[arg(long, required_unless_present_any = ["bearing_of", "cases"])]
    pub channel: Option<String>,
    /// Rayleigh climate with this mean wind speed [m/s] (thesis Table 7.1: 10.0)
    #[arg(long, default_value_t = 10.0)]
    pub mean_wind: f64,
    /// Weibull climate instead: shape,scale (k, C in m/s)
    #[arg(long, value_delimiter = ',')]
    pub weibull: Option<Vec<f64>>,
    /// Cut-in wind speed [m/s]
    #[arg(long, default_value_t = 4.0)]
    pub cut_in: f64,
    /// Cut-out wind speed [m/s]
    #[arg(long, default_value_t = 25.0)]
    pub cut_out: f64,
    /// Width of the wind-speed bins [m/s]. Bins are named by their upper edge, (v − width, v], as
    /// thesis Table 7.1 counts them, so the operating hours run from cut-in − width to cut-out
    /// (161 950 h in 20 years at a Rayleigh mean of 10 m/s); 0 counts exactly cut-in to cut-out
    #[arg(long, default_value_t = 1.0)]
    pub bin_width: f64,
    /// Design life [years]
    #[arg(long, default_value_t = 20.0)]
    pub years: f64,
    /// Shutdowns per year (Germanischer Lloyd: 1000 at cut-in + 50 at cut-out + 50 at rated)
    #[arg(long, default_value_t = 1100.0)]
    pub shutdowns_per_year: f64,
    /// Wöhler slopes of the lifetime DELs
    #[arg(long, value_delimiter = ',', default_value = "3,6,9")]
    pub m: Vec<f64>,
    /// Equivalent frequency of the lifetime DEL [Hz]
    #[arg(long, default_value_t = 1.0)]
    pub feq: f64,
    /// Gear pair of the mesh force: z1,z2,normal module [mm],helix [deg],face width [mm]
    #[arg(long, value_delimiter = ',')]
    pub gear: Option<Vec<f64>>,
    /// The pair is internal (z2 is the ring)
    #[arg(long)]
    pub internal: bool,
    /// Profile shifts x1,x2
    #[arg(long, value_delimiter = ',', default_value = "0,0")]
    pub shift: Vec<f64>,
    /// Normal pressure angle [deg]
    #[arg(long, default_value_t = 20.0)]
    pub pressure_angle: f64,
    /// Which tooth's life: sun, planet (alternating root bending, Y_M = 0.7), ring or parallel
    #[arg(long, default_value = "sun", value_parser = ["sun", "planet", "ring", "parallel"])]
    pub tooth: String,
    /// Planets of the stage (load cycles of sun and ring teeth)
    #[arg(long, default_value_t = 3)]
    pub planets: u32,
    /// Speed channel [rad/s] of the tooth's gear (the carrier's for the ring)
    #[arg(long)]
    pub speed: Option<String>,
    /// Speed channel subtracted from --speed (the carrier, for the sun's speed relative to it). Not for
    /// planets: the torsional FMU's planet speeds are their absolute spin, opposite to the carrier's, so
    /// the planet's speed relative to the carrier is the sum of the two (`windrive gears` counts it)
    #[arg(long)]
    pub relative_to: Option<String>,
    /// Load sharing K_γ (IEC 61400-4 mesh load factor: 1.10 for 3 planets, 1.25 for 4, 1.35 for 5)
    #[arg(long, default_value_t = 1.0)]
    pub k_gamma: f64,
    /// Application factor K_A
    #[arg(long, default_value_t = 1.0)]
    pub k_a: f64,
    /// Tooth form and stress correction factors Y_F,Y_S [default: from the root geometry, ISO 6336-3
    /// method B, for external teeth; the ring needs them given]
    #[arg(long, value_delimiter = ',')]
    pub y_fs: Option<Vec<f64>>,
    /// Basic rack of the hob that cut the teeth: dedendum h_fP, root radius ρ_fP (× module)
    #[arg(long, value_delimiter = ',', default_value = "1.25,0.38")]
    pub rack: Vec<f64>,
    /// Which member of --gear the tooth is: 1 (z1) or 2 (z2) [default: sun 1, planet 2 (1 with
    /// --internal), ring 2, parallel 1]
    #[arg(long)]
    pub member: Option<u8>,
    /// Bearing life instead of gear: the bearing's basic dynamic load rating C [N]; the channel is
    /// then its equivalent dynamic load P [N] and --speed its speed [rad/s] (ISO 281 L10, Miner over
    /// the load spectrum)
    #[arg(long, conflicts_with = "gear")]
    pub bearing: Option<f64>,
    /// With --bearing: a ball bearing (life exponent 3; roller bearings 10/3)
    #[arg(long, requires = "bearing")]
    pub ball: bool,
    /// A bearing of a gearbox6dof series by name (planet_1_uw, hss_a, …; `windrive bearings` lists
    /// them): C from its roller set, P = X·F_r + Y·F_a from its radial and axial load, its rings'
    /// revolutions from the rotor speed and the gearbox's kinematics; the DELs are P's
    #[arg(long, conflicts_with_all = ["channel", "bearing", "gear", "speed"])]
    pub bearing_of: Option<String>,
    /// With --bearing-of: the gearbox6dof description the series ran (a preset or a file)
    #[arg(long, default_value = "grc750", requires = "bearing_of")]
    pub gearbox: String,
    /// With --bearing-of: the scene's name of the gearbox6dof FMU
    #[arg(long, default_value = "gearbox", requires = "bearing_of")]
    pub component: String,
    /// With --gear: the channel is the mesh force normal to the teeth (the gearbox6dof FMU's); without,
    /// the transverse force along the line of action, torque over base radius (the torsional FMU's).
    /// They differ by cos β_b on helical gears
    #[arg(long, requires = "gear")]
    pub normal_force: bool,
    /// Print the results as JSON
    #[arg(long)]
    pub json: bool,
    /// A load-case campaign's lifetime instead, from its table of cases as JSON (`-` reads stdin):
    /// {"campaign", "years", "feq_hz", "ldd_bins": [{channel, speed, min, max, bins}], "columns": [...],
    /// "rows": [[...], ...]}, the columns those `windrive run --analyse` writes plus name, group, status,
    /// wind_speed, hours, events and analysed_s. Prints the lifetime DELs, LDDs, gear and bearing
    /// damage and the thesis's ratios as JSON (what `scripts/campaign report` shows)
    #[arg(long, conflicts_with_all = ["normal", "shutdown", "channel", "bearing_of", "gear", "bearing"])]
    pub cases: Option<PathBuf>,
}

/// `windrive life --cases`: the campaign's table read, its lifetime printed as JSON.
fn campaign(path: &Path) -> anyhow::Result<()> {
    let shown = path.display();
    let text = if path == Path::new("-") {
        std::io::read_to_string(std::io::stdin()).context("--cases -: reading stdin")?
    } else {
        std::fs::read_to_string(path).with_context(|| format!("--cases {shown}"))?
    };
    let table: CampaignTable = serde_json::from_str(&text).with_context(|| format!("--cases {shown}"))?;
    println!("{}", serde_json::to_string(&campaign::compute(&table)?)?);
    Ok(())
}

pub fn run(args: &LifeArgs) -> anyhow::Result<()> {
    let normal = match (&args.cases, &args.normal) {
        (Some(cases), _) => return campaign(cases),
        (None, Some(normal)) => normal,
        (None, None) => bail!("give --normal (a series) or --cases (a campaign's table)"),
    };
    let wind = wind_distribution(args.weibull.as_deref(), args.mean_wind)?;
    let climate = Climate {
        wind,
        cut_in: args.cut_in,
        cut_out: args.cut_out,
        bin_width: args.bin_width,
    };
    let options = "--cut-in, --cut-out, --bin-width, --years, --shutdowns-per-year";
    climate.validate().context(options)?;
    if args.bearing.is_some() && args.speed.is_none() {
        bail!("--bearing needs --speed: the bearing's life is counted in its revolutions");
    }
    let rated = args
        .bearing_of
        .as_deref()
        .map(|name| named_bearing(&args.gearbox, &args.component, name))
        .transpose()?;
    let read = |path: &PathBuf| -> anyhow::Result<Case> {
        Ok(match (&rated, &args.channel) {
            (Some((table, b)), _) => {
                let s = table.load_and_speed(b, path)?;
                Case::new(path, s.t, s.load, Some(s.speed))?
            }
            (None, Some(channel)) => Case::read(path, channel, args.speed.as_deref(), args.relative_to.as_deref())?,
            (None, None) => unreachable!("clap requires --channel without --bearing-of"),
        })
    };
    let normal = read(normal)?;
    let shutdown = args.shutdown.as_ref().map(read).transpose()?;
    let channel = match (&rated, &args.channel) {
        (Some((_, b)), _) => format!("{} equivalent load P", b.radial.trim_end_matches("_radial_load")),
        (None, Some(c)) => c.clone(),
        (None, None) => unreachable!("clap requires --channel without --bearing-of"),
    };
    let lifetime = Lifetime::new(normal, shutdown, &climate, args.years, args.shutdowns_per_year).context(options)?;
    let dels = lifetime.dels(&args.m, args.feq).context("--m, --feq")?;
    let capacity = args.bearing.or(rated.as_ref().map(|(_, b)| b.rating));
    let bearing = capacity
        .map(|c| {
            lifetime
                .bearing(c, !args.ball)
                .with_context(|| format!("--bearing {c}"))
        })
        .transpose()?;
    let gear = args.gear.as_ref().map(|g| gear_life(args, g, &lifetime)).transpose()?;

    let (operating_hours, life_hours) = (lifetime.operating_hours, lifetime.life_hours());
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "operating_hours": operating_hours, "life_hours": life_hours, "shutdowns": lifetime.shutdowns,
                "normal_time_factor": lifetime.normal_factor(), "lifetime_del": dels,
                "gear": gear.map(|(g, _)| g), "bearing": bearing,
            })
        );
        return Ok(());
    }
    println!(
        "{} over {} years: {operating_hours:.0} h in operation ({:.1} % of {life_hours:.0} h, {:?}, {}–{} m/s{}), {:.0} shutdowns",
        channel,
        args.years,
        100.0 * operating_hours / life_hours,
        climate.wind,
        args.cut_in,
        args.cut_out,
        if args.bin_width > 0.0 {
            format!(" in {} m/s bins (v − {0}, v] as thesis Table 7.1", args.bin_width)
        } else {
            String::new()
        },
        lifetime.shutdowns
    );
    println!(
        "normal operation: {:.1} s simulated, time factor {:.4e}",
        lifetime.normal.seconds,
        lifetime.normal_factor()
    );
    println!("\n{:>6} {:>16} {:>22}", "m", "lifetime DEL", "share from shutdowns");
    for d in &dels {
        println!("{:>6} {:>16.6e} {:>21.1}%", d.m, d.del, 100.0 * d.shutdown_share);
    }
    if let (Some((report, spec)), Some(g)) = (&gear, &args.gear) {
        print!("\n{}", gear_text(args.years, g, spec, report));
    }
    if let Some(b) = &bearing {
        print!("\n{}", bearing_text(args.years, b));
    }
    println!("\nallowable stresses (reference):");
    for (component, value, what, source) in LIMITS {
        println!("  {component:<24} {:>7.0} MPa  {what} ({source})", value / 1e6);
    }
    Ok(())
}

/// The gear options of the command line checked into a [`GearSpec`], and its lifetime.
fn gear_life(args: &LifeArgs, g: &[f64], lifetime: &Lifetime) -> anyhow::Result<(GearLife, GearSpec)> {
    let spec = gear_spec(&GearOptions {
        numbers: g,
        internal: args.internal,
        shift: &args.shift,
        rack: &args.rack,
        y_fs: args.y_fs.as_deref(),
        pressure_angle_deg: args.pressure_angle,
        tooth: &args.tooth,
        member: args.member,
        planets: args.planets,
        k_a: args.k_a,
        k_gamma: args.k_gamma,
        normal_force: args.normal_force,
    })?;
    if args.speed.is_none() {
        bail!("--gear needs --speed: the load cycles come from the gear's revolutions");
    }
    let report = lifetime
        .gear(&spec)
        .map_err(|e| anyhow::anyhow!("--gear {g:?}: {e} (--y-fs)"))?;
    Ok((report, spec))
}
