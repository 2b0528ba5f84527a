//! `windrive aero`: the rotor FMU's blade-element momentum model at chosen tip-speed ratios and
//! pitch angles, as JSON (C_P, C_Q, C_T, torque, thrust, optionally the element loads), and the
//! rated point a blade reaches when scaled to a preset's rotor.

use crate::physics::aero::AIR_DENSITY;
use crate::physics::bem::BemRotor;
use crate::physics::blade::Blade;
use crate::physics::drivetrain::Drivetrain;
use crate::physics::rotor::preset_rotor;
use crate::studies::aero::{Sweep, rated_point, report};
use anyhow::{Context, anyhow, bail};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct AeroArgs {
    /// Blade data: a folder under fmus/rotor/resources/blades/ or a path to one
    #[arg(long, default_value = "windpact-1.5mw")]
    pub blade: String,
    /// Scale the blade to this drivetrain preset's rotor (A, B, C, D or P) and fit its rated point
    #[arg(long, conflicts_with = "radius")]
    pub preset: Option<String>,
    /// Scale the blade to this tip radius [m] (default: the blade as stored)
    #[arg(long)]
    pub radius: Option<f64>,
    /// With --rated-rpm: the rated power [W] whose rated wind speed is fitted
    #[arg(long, requires = "rated_rpm")]
    pub rated_power: Option<f64>,
    /// With --rated-power: the rated rotor speed [rpm]
    #[arg(long, requires = "rated_power")]
    pub rated_rpm: Option<f64>,
    /// Tip-speed ratios, comma-separated (0 = standstill, negative = reverse rotation)
    #[arg(long, value_delimiter = ',', default_value = "2,3,4,5,6,7,8,9,10,11,12")]
    pub tsr: Vec<f64>,
    /// Pitch angles [deg], comma-separated (positive towards feather)
    #[arg(long, value_delimiter = ',', default_value = "0")]
    pub pitch: Vec<f64>,
    /// Hub-height wind speed [m/s] for the dimensional torque and thrust
    #[arg(long, default_value_t = 10.0)]
    pub wind: f64,
    /// Print every station's loads (inflow and attack angles, induction, C_l, C_d, N', T') too
    #[arg(long)]
    pub elements: bool,
    /// Leave out Prandtl's tip loss
    #[arg(long)]
    pub no_tip_loss: bool,
    /// Leave out Prandtl's hub loss
    #[arg(long)]
    pub no_hub_loss: bool,
    /// Leave out the tangential induction (wake rotation)
    #[arg(long)]
    pub no_wake_rotation: bool,
    /// Leave drag out of the induction (it stays in the loads)
    #[arg(long)]
    pub no_drag_in_induction: bool,
}

/// A blade name under the rotor FMU's resources, or a path.
fn blade_dir(name: &str) -> anyhow::Result<PathBuf> {
    let path = PathBuf::from(name);
    if path.is_absolute() || path.join("blade.csv").is_file() {
        return Ok(path);
    }
    let root = crate::pack::workspace_root()?;
    Ok(root
        .join("fmus")
        .join("rotor")
        .join("resources")
        .join("blades")
        .join(name))
}

pub fn run(args: &AeroArgs) -> anyhow::Result<()> {
    if !(args.wind.is_finite() && args.wind > 0.0) {
        bail!("--wind {}: must be a positive wind speed", args.wind);
    }
    let dir = blade_dir(&args.blade)?;
    let reference = Blade::load(&dir).with_context(|| format!("loading blade {:?}", args.blade))?;
    let drivetrain = match &args.preset {
        Some(p) => Some(Drivetrain::preset(p).ok_or_else(|| anyhow!("unknown --preset {p:?}: use A, B, C, D or P"))?),
        None => None,
    };
    let radius = match (&drivetrain, args.radius) {
        (Some(d), _) => preset_rotor(d, &d.name).0,
        (None, Some(r)) if r.is_finite() && r > 0.0 => r,
        (None, Some(r)) => bail!("--radius {r}: must be positive"),
        (None, None) => reference.tip_radius(),
    };
    let mut rotor = BemRotor::new(reference.scaled(radius), AIR_DENSITY);
    rotor.options.tip_loss = !args.no_tip_loss;
    rotor.options.hub_loss = !args.no_hub_loss;
    rotor.options.wake_rotation = !args.no_wake_rotation;
    rotor.options.use_cd = !args.no_drag_in_induction;

    let rated = match (&drivetrain, args.rated_power, args.rated_rpm) {
        (Some(d), _, _) => Some((d.rated_power, d.rated_rotor_speed)),
        (None, Some(p), Some(rpm)) => Some((p, rpm * std::f64::consts::PI / 30.0)),
        _ => None,
    };
    let rated = rated
        .map(|(power, speed)| rated_point(&rotor, radius, power, speed))
        .transpose()
        .map_err(|e| anyhow!(e))?;
    for &pitch_deg in &args.pitch {
        for &tsr in &args.tsr {
            if !tsr.is_finite() || !pitch_deg.is_finite() {
                bail!("--tsr and --pitch take finite numbers (got {tsr}, {pitch_deg})");
            }
        }
    }
    let sweep = Sweep {
        tsr: &args.tsr,
        pitch_deg: &args.pitch,
        wind: args.wind,
        elements: args.elements,
    };
    let dir_shown = dir.display().to_string();
    let out = report(&reference.name, &dir_shown, &rotor, radius, rated, &sweep)?;
    println!("{}", serde_json::to_string_pretty(&out)?);
    Ok(())
}
