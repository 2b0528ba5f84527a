//! `windrive gearbox`: a gearbox description at a steady operating point (static equilibrium under
//! rotor torque, gravity, the rotor's moments and thrust, the chain turning at rated speed): every
//! bearing's loads, rollers in contact and race stresses, every mesh's slice loads and contact
//! stress, and each roller set's stiffness there beside the linear value of its description. The
//! study is [`crate::studies::operating_point`]; `--revolution` turns the carrier once at that point
//! instead ([`crate::studies::carrier_revolution`]).

use crate::physics::gearbox::{Description, Gearbox, description::BearingModel};
use crate::studies::carrier_revolution::revolution;
use crate::studies::dynamic_factor::{Timing, dynamic_factors};
use crate::studies::operating_point::{OperatingPoint, fit_carrier_webs, report};
use anyhow::anyhow;

#[derive(clap::Args)]
pub struct GearboxArgs {
    /// A preset (grc750, nrel5mw, c2mw, paper1p5mw, planetary-spur) or a description file
    #[arg(long, default_value = "grc750", value_name = "PRESET|FILE")]
    pub gearbox: String,
    /// Rotor torque over the description's rated rotor torque
    #[arg(long, default_value_t = 1.0)]
    pub torque_ratio: f64,
    /// Rotor speed over the rated speed (the frames' centripetal and gyroscopic loads)
    #[arg(long, default_value_t = 1.0)]
    pub speed_ratio: f64,
    /// Bearing model: linear, lamina or lamina-table (default: the description's)
    #[arg(long)]
    pub bearings: Option<String>,
    /// Rotor pitching (tilt) moment on the main shaft, N·m (positive: about the housing's horizontal axis)
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub tilt_moment: f64,
    /// Rotor yawing moment, N·m
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub yaw_moment: f64,
    /// Rotor thrust, N (positive downwind)
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub thrust: f64,
    /// Gravity, m/s² (default: the description's)
    #[arg(long)]
    pub gravity: Option<f64>,
    /// Print JSON instead of tables
    #[arg(long)]
    pub json: bool,
    /// Fit the first planetary stage's carrier-web torsional stiffness so that its planets'
    /// upwind bearings carry this many times the downwind ones' mean radial load at this operating
    /// point (the thesis's GRC: 1.41–1.47 at rated torque); prints the stiffness to write into the
    /// description's [stage.planetary.carrier_webs]
    #[arg(long, value_name = "RATIO")]
    pub fit_webs: Option<f64>,
    /// Turn the carrier once at this operating point instead (Newmark, 1 ms, from the static
    /// equilibrium) and print where each planet's upwind bearing load peaks and how far it swings
    /// (thesis §7.1.1, Fig. 7.3: the planet horizontal to the right of the sun seen from upwind)
    #[arg(long)]
    pub revolution: bool,
    /// The rotor body's mass, kg, in place of the description's: with a small value (1 kg) the
    /// overhung rotor's weight is gone, as on a dynamometer, which drives the main shaft through a
    /// coupling (the mass must be positive; its inertias stay the description's)
    #[arg(long, value_name = "KG")]
    pub rotor_mass: Option<f64>,
    /// Every mesh's dynamic factor K_v at this operating point's torque and speed instead (the
    /// rotor's moments and thrust are left out: they swing the carrier slowly, which the factor
    /// divides out): the largest mesh force with the tooth pairs' stiffness varying over the largest
    /// at mean stiffness, two runs from the static equilibrium (Newmark), beside ISO 6336-1 method B
    /// for the same perfect, unrelieved teeth
    #[arg(long, conflicts_with_all = ["revolution", "fit_webs"])]
    pub dynamic_factor: bool,
    /// With --dynamic-factor: the integration step, s [default: a fortieth of the stiffest pair's
    /// natural period or a hundredth of the fastest mesh period, whichever is shorter]
    #[arg(long, requires = "dynamic_factor")]
    pub step: Option<f64>,
}

/// The description with the command line's bearing model and gravity.
fn description(args: &GearboxArgs) -> anyhow::Result<Description> {
    let mut d = Description::load(&args.gearbox)?;
    match args.bearings.as_deref() {
        None => {}
        Some("linear") => d.model.bearings = BearingModel::Linear,
        Some("lamina") => d.model.bearings = BearingModel::Lamina,
        Some("lamina-table") => d.model.bearings = BearingModel::LaminaTable,
        Some(other) => return Err(anyhow!("--bearings {other:?}: use linear, lamina or lamina-table")),
    }
    if let Some(g) = args.gravity {
        d.model.gravity = g;
    }
    if let Some(m) = args.rotor_mass {
        if m <= 0.0 || !m.is_finite() {
            return Err(anyhow!("--rotor-mass {m}: a mass in kg above 0"));
        }
        let rotor = d
            .rotor
            .as_mut()
            .ok_or_else(|| anyhow!("--rotor-mass: {} has no [rotor]", args.gearbox))?;
        rotor.mass = Some(m);
    }
    Ok(d)
}

pub fn run(args: &GearboxArgs) -> anyhow::Result<()> {
    let point = OperatingPoint {
        torque_ratio: args.torque_ratio,
        speed_ratio: args.speed_ratio,
        tilt_moment_nm: args.tilt_moment,
        yaw_moment_nm: args.yaw_moment,
        thrust_n: args.thrust,
    };
    if let Some(target) = args.fit_webs {
        let (k, ratio) = fit_carrier_webs(&args.gearbox, &description(args)?, &point, target)?;
        println!("carrier webs torsional = {k:.4e} N·m/rad gives upwind/downwind {ratio:.4} (target {target})");
        return Ok(());
    }
    if args.revolution {
        return print_revolution(args, &point);
    }
    if args.dynamic_factor {
        return print_dynamic_factors(args, &point);
    }
    let r = report(&args.gearbox, &description(args)?, &point)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&r)?);
        return Ok(());
    }
    print!("{r}");
    Ok(())
}

/// The rated rotor torque and the operating point's speed (rad/s) of `d`, built as `g`.
fn rated(args: &GearboxArgs, d: &Description, g: &Gearbox, point: &OperatingPoint) -> anyhow::Result<(f64, f64)> {
    let rated = g
        .rated_rotor_torque
        .ok_or_else(|| anyhow!("{}: the description gives no rated power and speed", args.gearbox))?;
    let speed = point.speed_ratio * d.rated_rotor_speed_rpm.unwrap_or(0.0) * std::f64::consts::TAU / 60.0;
    Ok((point.torque_ratio * rated, speed))
}

/// Print a study's result as JSON or its table.
fn print<T: serde::Serialize + std::fmt::Display>(args: &GearboxArgs, r: &T) -> anyhow::Result<()> {
    if args.json {
        println!("{}", serde_json::to_string_pretty(r)?);
    } else {
        print!("{r}");
    }
    Ok(())
}

/// `--revolution`: the gearbox with the operating point's moments and thrust, turned once at its
/// torque and speed.
fn print_revolution(args: &GearboxArgs, point: &OperatingPoint) -> anyhow::Result<()> {
    let d = description(args)?;
    let mut g = Gearbox::new(&d).map_err(|e| anyhow!("{}: {e}", args.gearbox))?;
    g.external_moment = [point.tilt_moment_nm, point.yaw_moment_nm];
    g.thrust = point.thrust_n;
    let (torque, speed) = rated(args, &d, &g, point)?;
    print(args, &revolution(&d, &g, torque, speed, None)?)
}

/// `--dynamic-factor`: every mesh's K_v at the operating point's torque and speed (the rotor's
/// moments and thrust are not applied: they move the carrier slowly, which the factor divides out).
fn print_dynamic_factors(args: &GearboxArgs, point: &OperatingPoint) -> anyhow::Result<()> {
    let d = description(args)?;
    let g = Gearbox::new(&d).map_err(|e| anyhow!("{}: {e}", args.gearbox))?;
    let (torque, speed) = rated(args, &d, &g, point)?;
    let timing = Timing {
        step_s: args.step,
        ..Timing::default()
    };
    print(args, &dynamic_factors(&d, torque, speed, &timing)?)
}
