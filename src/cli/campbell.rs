//! `windrive campbell --preset C`: natural frequencies against rotor speed with the excitation orders,
//! and the crossings inside the operating range.

use crate::linear::campbell::{crossings, distinct_modes, excitation_orders};
use crate::physics::drivetrain::operating_speed_range_rpm;
use crate::plot;
use crate::studies::preset_modes::preset_modes;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct CampbellArgs {
    /// Drivetrain preset: A, B, C or D
    #[arg(long, default_value = "C")]
    pub preset: String,
    /// Model for the natural frequencies: 2, 5 or full
    #[arg(long, default_value = "full")]
    pub fidelity: String,
    /// Generator boundary of the modes: disconnected (variable speed, free–free), connected (K_gen
    /// to ground) or locked
    #[arg(long, default_value = "disconnected")]
    pub generator: String,
    /// Harmonics of each gear-mesh frequency
    #[arg(long, default_value_t = 2)]
    pub harmonics: u32,
    /// Highest natural frequency considered [Hz] [default: the highest excitation at maximum speed]
    #[arg(long)]
    pub max_frequency: Option<f64>,
    /// Print {"modes_hz", "orders": [[name, order, thesis order|null]], "operating_rpm", "crossings": [[order, mode Hz, rpm]]}
    #[arg(long)]
    pub json: bool,
    /// Campbell diagram with the crossings circled, .png or .svg
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

pub fn run(args: &CampbellArgs) -> anyhow::Result<()> {
    if args.harmonics == 0 {
        anyhow::bail!("--harmonics 0: at least the mesh frequency itself (1)");
    }
    let (dt, m) = preset_modes(&args.preset, &args.fidelity, &args.generator, "physical")?;
    let (lo, hi) = operating_speed_range_rpm(&dt.name).expect("every preset has a speed range");
    let orders = excitation_orders(&dt, args.harmonics);
    let top = orders.iter().map(|o| o.order).fold(0.0, f64::max) * hi / 60.0;
    let f_max = args.max_frequency.unwrap_or(top * 1.05);
    if f_max.is_nan() || f_max <= 0.0 {
        anyhow::bail!("--max-frequency {f_max}: must be positive");
    }
    let (modes_hz, multiplicity): (Vec<f64>, Vec<usize>) = distinct_modes(&m.frequencies_hz, f_max).into_iter().unzip();
    let cross = crossings(&orders, &modes_hz, lo, hi);
    if let Some(path) = &args.plot {
        plot::campbell(
            path,
            &format!(
                "Drivetrain {}: Campbell diagram ({} model, generator {})",
                dt.name, args.fidelity, args.generator
            ),
            &modes_hz,
            &orders.iter().map(|o| (o.name.clone(), o.order)).collect::<Vec<_>>(),
            (lo, hi),
            &cross.iter().map(|c| (c.rotor_rpm, c.mode_hz)).collect::<Vec<_>>(),
            f_max,
        )?;
    }
    if args.json {
        let o: Vec<serde_json::Value> = orders
            .iter()
            .map(|o| serde_json::json!([o.name, o.order, o.thesis_order]))
            .collect();
        let c: Vec<serde_json::Value> = cross
            .iter()
            .map(|c| serde_json::json!([c.order, c.mode_hz, c.rotor_rpm]))
            .collect();
        println!(
            "{}",
            serde_json::json!({ "modes_hz": modes_hz, "orders": o, "operating_rpm": [lo, hi], "crossings": c })
        );
        return Ok(());
    }
    println!("drivetrain {}: operating range {lo}–{hi} rpm", dt.name);
    println!("excitation orders (× rotor speed):");
    for o in &orders {
        match o.thesis_order {
            Some(t) => println!(
                "  {:<18} {:>10.3}   (thesis convention z_sun × sun speed: {t:.3})",
                o.name, o.order
            ),
            None => println!("  {:<18} {:>10.3}", o.name, o.order),
        }
    }
    let listed: Vec<String> = modes_hz
        .iter()
        .zip(&multiplicity)
        .map(|(f, k)| {
            if *k > 1 {
                format!("{f:.2} (×{k})")
            } else {
                format!("{f:.2}")
            }
        })
        .collect();
    println!("natural frequencies up to {f_max:.1} Hz: {}", listed.join(", "));
    if cross.is_empty() {
        println!("no crossing inside the operating range");
    } else {
        println!("crossings inside the operating range:");
        for c in &cross {
            println!(
                "  {:<18} meets {:>9.3} Hz at {:>6.2} rpm",
                c.order, c.mode_hz, c.rotor_rpm
            );
        }
    }
    if let Some(p) = &args.plot {
        println!("plot: {}", p.display());
    }
    Ok(())
}
