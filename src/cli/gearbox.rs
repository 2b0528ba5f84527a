//! `windrive gearbox`: a gearbox description at a steady operating point (static equilibrium under
//! rotor torque, gravity, the rotor's moments and thrust, the chain turning at rated speed): every
//! bearing's loads, rollers in contact and race stresses, every mesh's slice loads and contact
//! stress, and each roller set's stiffness there beside the linear value of its description.

use crate::physics::gearbox::statics::equilibrium;
use crate::physics::gearbox::{Description, Gearbox, description::BearingModel};
use anyhow::anyhow;
use serde::Serialize;

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
    /// Bearing model: linear or lamina (default: the description's)
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
}

#[derive(Serialize)]
struct BearingRow {
    name: String,
    model: &'static str,
    radial_n: f64,
    axial_n: f64,
    tilting_nm: f64,
    rollers_in_contact: usize,
    max_roller_load_n: f64,
    inner_race_pressure_pa: f64,
    outer_race_pressure_pa: f64,
    max_subsurface_shear_pa: f64,
    max_shear_depth_m: f64,
    /// The roller set's radial stiffness along the load (N/m), and the description's linear one.
    radial_stiffness_n_per_m: Option<f64>,
    linear_radial_stiffness_n_per_m: f64,
}

#[derive(Serialize)]
struct MeshRow {
    name: String,
    force_n: f64,
    max_slice_load_n: f64,
    face_load_factor: f64,
    contact_pressure_pa: f64,
    max_subsurface_shear_pa: f64,
    max_shear_depth_m: f64,
}

#[derive(Serialize)]
struct Report {
    gearbox: String,
    rotor_torque_nm: f64,
    rotor_speed_rad_s: f64,
    bearings: Vec<BearingRow>,
    meshes: Vec<MeshRow>,
    load_sharing_factor: Option<f64>,
}

/// The description with the command line's bearing model and gravity.
fn description(args: &GearboxArgs) -> anyhow::Result<Description> {
    let mut d = Description::load(&args.gearbox)?;
    match args.bearings.as_deref() {
        None => {}
        Some("linear") => d.model.bearings = BearingModel::Linear,
        Some("lamina") => d.model.bearings = BearingModel::Lamina,
        Some(other) => return Err(anyhow!("--bearings {other:?}: use linear or lamina")),
    }
    if let Some(g) = args.gravity {
        d.model.gravity = g;
    }
    Ok(d)
}

fn report(args: &GearboxArgs, d: &Description) -> anyhow::Result<Report> {
    let mut g = Gearbox::new(d).map_err(|e| anyhow!("{}: {e}", args.gearbox))?;
    g.external_moment = [args.tilt_moment, args.yaw_moment];
    g.thrust = args.thrust;
    let rated = g
        .rated_rotor_torque
        .ok_or_else(|| anyhow!("{}: the description gives no rated power and speed", args.gearbox))?;
    let torque = args.torque_ratio * rated;
    let speed = args.speed_ratio * d.rated_rotor_speed_rpm.unwrap_or(0.0) * std::f64::consts::TAU / 60.0;
    let (q, v) = equilibrium(&g, &[torque, torque / g.gear_ratio, 0.0], speed)
        .map_err(|e| anyhow!("{}: static equilibrium at {torque:.0} N·m: {e}", args.gearbox))?;
    let loads = g.loads(&q, &v);
    let bearings = g
        .bearings
        .iter()
        .zip(&loads.bearings)
        .map(|(b, l)| {
            let stiffness = b.rollers.map(|i| g.rollers[i].radial_stiffness(&q, &v));
            BearingRow {
                name: b.name.clone(),
                model: if b.rollers.is_some() { "lamina" } else { "linear" },
                radial_n: l.radial,
                axial_n: l.axial,
                tilting_nm: l.tilting,
                rollers_in_contact: l.rollers_in_contact,
                max_roller_load_n: l.max_roller_load,
                inner_race_pressure_pa: l.stresses.inner_pressure,
                outer_race_pressure_pa: l.stresses.outer_pressure,
                max_subsurface_shear_pa: l.stresses.max_shear,
                max_shear_depth_m: l.stresses.max_shear_depth,
                radial_stiffness_n_per_m: stiffness,
                linear_radial_stiffness_n_per_m: g.springs[b.springs[0]].stiffness,
            }
        })
        .collect();
    let meshes = g
        .meshes
        .iter()
        .zip(&loads.meshes)
        .map(|(m, r)| MeshRow {
            name: m.name.clone(),
            force_n: r.force,
            max_slice_load_n: r.max_slice,
            face_load_factor: r.face_load_factor,
            contact_pressure_pa: r.contact.pressure,
            max_subsurface_shear_pa: r.contact.max_shear,
            max_shear_depth_m: r.contact.max_shear_depth,
        })
        .collect();
    Ok(Report {
        gearbox: d.name.clone(),
        rotor_torque_nm: torque,
        rotor_speed_rad_s: speed,
        bearings,
        meshes,
        load_sharing_factor: g.load_sharing(&loads, ""),
    })
}

/// Mean radial load of the first stage's planets' upwind bearings over their downwind ones'.
fn upwind_over_downwind(r: &Report) -> Option<f64> {
    let mean = |end: &str| {
        let loads: Vec<f64> = r
            .bearings
            .iter()
            .filter(|b| b.name.starts_with("planet_") && b.name.ends_with(end))
            .map(|b| b.radial_n)
            .collect();
        (!loads.is_empty()).then(|| loads.iter().sum::<f64>() / loads.len() as f64)
    };
    Some(mean("_uw")? / mean("_dw")?)
}

/// Bisection on log k of the carrier webs: a stiffer carrier shares the load more evenly.
fn fit_webs(args: &GearboxArgs, target: f64) -> anyhow::Result<()> {
    use crate::physics::gearbox::description::Stage;
    let base = description(args)?;
    let ratio_at = |k: f64| -> anyhow::Result<f64> {
        let mut d = base.clone();
        let Some(Stage::Planetary(p)) = d.stages.first_mut() else {
            return Err(anyhow!("{}: the first stage is not planetary", args.gearbox));
        };
        let webs = p.carrier_webs.as_mut().ok_or_else(|| {
            anyhow!(
                "{}: the first planetary stage has no [stage.planetary.carrier_webs] to fit",
                args.gearbox
            )
        })?;
        webs.torsional = k;
        let r = report(args, &d)?;
        upwind_over_downwind(&r).ok_or_else(|| anyhow!("{}: no planet bearings named *_uw and *_dw", args.gearbox))
    };
    let (mut lo, mut hi) = (1e6f64.ln(), 1e12f64.ln());
    let (r_soft, r_stiff) = (ratio_at(lo.exp())?, ratio_at(hi.exp())?);
    if !(r_stiff..=r_soft).contains(&target) {
        return Err(anyhow!(
            "upwind/downwind {target} is outside what the webs can give here ({r_stiff:.3} rigid to {r_soft:.3} at 1e6 N·m/rad)"
        ));
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if ratio_at(mid.exp())? > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let k = (0.5 * (lo + hi)).exp();
    println!(
        "carrier webs torsional = {k:.4e} N·m/rad gives upwind/downwind {:.4} (target {target})",
        ratio_at(k)?
    );
    Ok(())
}

pub fn run(args: &GearboxArgs) -> anyhow::Result<()> {
    if let Some(target) = args.fit_webs {
        return fit_webs(args, target);
    }
    let r = report(args, &description(args)?)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&r)?);
        return Ok(());
    }
    println!(
        "{}: static equilibrium at {:.0} kN·m rotor torque, {:.3} rad/s{}",
        r.gearbox,
        r.rotor_torque_nm / 1e3,
        r.rotor_speed_rad_s,
        r.load_sharing_factor
            .map_or(String::new(), |k| format!(", K_γ = {k:.3}"))
    );
    println!(
        "\n{:<14} {:>7} {:>10} {:>9} {:>10} {:>7} {:>9} {:>8} {:>8} {:>8} {:>7} {:>11} {:>11}",
        "bearing",
        "model",
        "radial kN",
        "axial kN",
        "tilt kN·m",
        "rollers",
        "Q_max kN",
        "p_i MPa",
        "p_o MPa",
        "τ MPa",
        "z mm",
        "k_r GN/m",
        "linear GN/m"
    );
    for b in &r.bearings {
        println!(
            "{:<14} {:>7} {:>10.1} {:>9.1} {:>10.2} {:>7} {:>9.2} {:>8.0} {:>8.0} {:>8.0} {:>7.3} {:>11} {:>11.2}",
            b.name,
            b.model,
            b.radial_n / 1e3,
            b.axial_n / 1e3,
            b.tilting_nm / 1e3,
            b.rollers_in_contact,
            b.max_roller_load_n / 1e3,
            b.inner_race_pressure_pa / 1e6,
            b.outer_race_pressure_pa / 1e6,
            b.max_subsurface_shear_pa / 1e6,
            b.max_shear_depth_m * 1e3,
            b.radial_stiffness_n_per_m
                .map_or("-".into(), |k| format!("{:.2}", k / 1e9)),
            b.linear_radial_stiffness_n_per_m / 1e9
        );
    }
    println!(
        "\n{:<18} {:>10} {:>14} {:>7} {:>9} {:>8} {:>7}",
        "mesh", "force kN", "max slice kN", "K_Hβ", "p_H MPa", "τ MPa", "z mm"
    );
    for m in &r.meshes {
        println!(
            "{:<18} {:>10.1} {:>14.2} {:>7.3} {:>9.0} {:>8.0} {:>7.3}",
            m.name,
            m.force_n / 1e3,
            m.max_slice_load_n / 1e3,
            m.face_load_factor,
            m.contact_pressure_pa / 1e6,
            m.max_subsurface_shear_pa / 1e6,
            m.max_shear_depth_m * 1e3
        );
    }
    Ok(())
}
