//! `windrive bode`: frequency response of the linear drivetrain between a torque and a speed or
//! shaft torque (the thesis's eigenfrequency analysis: LSS torque in, generator speed out).

use crate::linear::bode::{Bode, log_spaced};
use crate::linear::modes::{Boundary, modes};
use crate::linear::response::{Input, Output, frequency_response};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::torsional::{Fidelity, ModelOptions, TorsionalModel};
use crate::plot;
use anyhow::{anyhow, bail};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct BodeArgs {
    /// Drivetrain preset: A, B, C or D
    #[arg(long, default_value = "D")]
    pub preset: String,
    /// 2, 5 or full
    #[arg(long, default_value = "full")]
    pub fidelity: String,
    /// connected (K_gen to ground), disconnected (free–free) or locked (HSS held)
    #[arg(long, default_value = "disconnected")]
    pub generator: String,
    /// Torque input: rotor or generator
    #[arg(long, default_value = "rotor", value_parser = ["rotor", "generator"])]
    pub input: String,
    /// Output: generator-speed, rotor-speed, lss-torque or hss-torque
    #[arg(long, default_value = "generator-speed", value_parser = ["generator-speed", "rotor-speed", "lss-torque", "hss-torque"])]
    pub output: String,
    /// Frequency range [Hz]: low,high (log-spaced)
    #[arg(long, value_delimiter = ',', default_value = "0.1,1000")]
    pub range: Vec<f64>,
    #[arg(long, default_value_t = 600)]
    pub points: usize,
    /// Print {"frequency_hz": [...], "magnitude": [...], "phase_deg": [...], "modes_hz": [...]}
    #[arg(long)]
    pub json: bool,
    /// Magnitude plot (dB over log10 frequency) with the natural frequencies marked, .png or .svg
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

pub fn run(args: &BodeArgs) -> anyhow::Result<()> {
    let dt = Drivetrain::preset(&args.preset)
        .ok_or_else(|| anyhow!("unknown preset {:?}: use A, B, C or D", args.preset))?;
    let fidelity = Fidelity::parse(&args.fidelity)
        .ok_or_else(|| anyhow!("unknown fidelity {:?}: use 2, 5 or full", args.fidelity))?;
    let boundary = Boundary::parse(&args.generator).ok_or_else(|| {
        anyhow!(
            "unknown --generator {:?}: use connected, disconnected or locked",
            args.generator
        )
    })?;
    if args.range.len() != 2 || !(args.range[0] > 0.0 && args.range[1] > args.range[0]) || args.points < 2 {
        bail!(
            "--range {:?} --points {}: give low,high with 0 < low < high and at least 2 points",
            args.range,
            args.points
        );
    }
    let model = TorsionalModel::new(&dt, fidelity, &ModelOptions::default()).map_err(|e| anyhow!(e))?;
    // clap allows only the names these know
    let input = Input::named(&args.input).expect("clap checks --input");
    let output = Output::named(&args.output, &model).expect("clap checks --output");
    let f = log_spaced(args.range[0], args.range[1], args.points);
    let r = frequency_response(&model, boundary, dt.k_generator, input, output, &f).map_err(|e| anyhow!(e))?;
    let bode = Bode::new(f, &r);
    let (f, mag, phase) = (&bode.frequency_hz, &bode.magnitude, &bode.phase_deg);
    let modes_hz: Vec<f64> = modes(&model, boundary, dt.k_generator)
        .frequencies_hz
        .into_iter()
        .filter(|x| *x > 1e-6 && *x >= args.range[0] && *x <= args.range[1])
        .collect();
    if let Some(path) = &args.plot {
        let pts: Vec<(f64, f64)> = f
            .iter()
            .zip(mag)
            .map(|(x, m)| (x.log10(), 20.0 * m.max(1e-300).log10()))
            .collect();
        let marks: Vec<(f64, String)> = modes_hz.iter().map(|m| (m.log10(), format!("{m:.2} Hz"))).collect();
        let title = format!(
            "Drivetrain {}: {} torque → {} (generator {})",
            dt.name, args.input, args.output, args.generator
        );
        let lines = [(format!("{} / {} torque", args.output, args.input), pts)];
        plot::named_lines(path, &title, "log10 frequency [Hz]", "magnitude [dB]", &lines, &marks)?;
    }
    if args.json {
        println!(
            "{}",
            serde_json::json!({ "frequency_hz": f, "magnitude": mag, "phase_deg": phase, "modes_hz": modes_hz })
        );
        return Ok(());
    }
    let unit = if args.output.ends_with("speed") {
        "rad/s per N·m"
    } else {
        "N·m per N·m"
    };
    println!(
        "drivetrain {} ({} model, generator {}): {} torque → {} [{unit}]",
        dt.name, args.fidelity, args.generator, args.input, args.output
    );
    for i in bode.peaks() {
        println!(
            "  peak at {:>9.3} Hz: {:.4e} ({:+.1} dB, phase {:+.1}°)",
            f[i],
            mag[i],
            20.0 * mag[i].log10(),
            phase[i]
        );
    }
    println!(
        "  natural frequencies in range: {}",
        modes_hz
            .iter()
            .map(|m| format!("{m:.3}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}
