//! `windrive step-response`: the rated-torque step of [`crate::reference::step`] on a drivetrain,
//! through its torsional FMU: a CSV, the peaks, the dominant frequency and the modes beside it.

use crate::fmi2::host::import::Fmu;
use crate::reference::step::{Scenario, column, response, run_fmi, write_csv};
use crate::studies::preset_modes::preset_modes;
use anyhow::Context;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct StepArgs {
    /// Drivetrain preset: A, B, C or D
    #[arg(long, default_value = "D")]
    pub preset: String,
    /// 2, 5 or full
    #[arg(long, default_value = "full")]
    pub fidelity: String,
    /// implicit or rk4
    #[arg(long, default_value = "implicit")]
    pub integrator: String,
    /// Simulated time, s
    #[arg(long, default_value_t = 5.0)]
    pub stop_time: f64,
    /// Communication step, s
    #[arg(long, default_value_t = 1e-3)]
    pub step: f64,
    /// When the torque steps, s
    #[arg(long, default_value_t = 0.5)]
    pub step_time: f64,
    /// CSV output (fmpy layout: time first, one column per variable)
    #[arg(long, default_value = "results/step-response.csv")]
    pub out: PathBuf,
    /// Also plot the HSS and LSS torque (.png or .svg)
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Use this .fmu instead of packing target/fmu/torsional.fmu
    #[arg(long)]
    pub fmu: Option<PathBuf>,
    /// Cycle through these communication step sizes (s) instead of --step, e.g. 0.5e-3,1e-3,2e-3
    #[arg(long, value_delimiter = ',')]
    pub step_pattern: Vec<f64>,
}

/// Opens the given FMU, or packs target/fmu/torsional.fmu from the workspace first.
pub fn torsional_fmu(path: Option<&Path>) -> anyhow::Result<Fmu> {
    let path = match path {
        Some(p) => p.to_path_buf(),
        None => {
            let root = crate::pack::workspace_root()?;
            crate::pack::pack(&root, "torsional")?
        }
    };
    Fmu::open(&path).with_context(|| format!("opening {}", path.display()))
}

pub fn run(args: &StepArgs) -> anyhow::Result<()> {
    let fmu = torsional_fmu(args.fmu.as_deref())?;
    let sc = Scenario {
        preset: args.preset.clone(),
        fidelity: args.fidelity.clone(),
        integrator: args.integrator.clone(),
        max_internal_step: args.step_pattern.iter().cloned().fold(args.step, f64::max),
        stop_time: args.stop_time,
        step: args.step,
        step_time: args.step_time,
        pattern: args.step_pattern.clone(),
    };
    let (rows, wall) = run_fmi(&fmu, &sc, true)?;
    write_csv(&args.out, &rows).with_context(|| format!("writing {}", args.out.display()))?;
    let r = response(&sc, &rows)?;
    println!(
        "Rated-torque step on drivetrain {} ({} fidelity, {} integrator), {} s at {} s steps through the FMU: {:.0}x real time",
        args.preset,
        args.fidelity,
        args.integrator,
        args.stop_time,
        args.step,
        args.stop_time / wall
    );
    println!(
        "  rated LSS torque {:.4e} N·m, rated HSS torque {:.4e} N·m",
        r.rated_lss_nm, r.rated_hss_nm
    );
    println!(
        "  peak LSS torque / rated: {:.3}   peak HSS torque / rated: {:.3}   (undamped step: 2.0)",
        r.peak_lss_ratio, r.peak_hss_ratio
    );
    println!("  dominant HSS-torque frequency: {:.3} Hz", r.dominant_hz);
    for boundary in ["disconnected", "connected", "locked"] {
        let (_, m) = preset_modes(&args.preset, &args.fidelity, boundary, "physical")?;
        let list: Vec<String> = m.frequencies_hz.iter().take(5).map(|f| format!("{f:.3}")).collect();
        println!("  modes, generator {boundary:<12}: {} Hz ...", list.join(", "));
    }
    println!("  CSV: {}", args.out.display());
    if let Some(plot) = &args.plot {
        let col = |name: &str| column(name).expect("a recorded channel");
        let over_rated = |c: usize, rated: f64| rows.iter().map(|row| (row[0], row[c] / rated)).collect();
        let lines = [
            ("LSS".to_string(), over_rated(col("lss_torque"), r.rated_lss_nm)),
            ("HSS".to_string(), over_rated(col("hss_torque"), r.rated_hss_nm)),
        ];
        let title = format!("Drivetrain {}: rated-torque step", args.preset);
        crate::plot::named_lines(plot, &title, "time / s", "torque / rated", &lines, &[])?;
        println!("  plot: {}", plot.display());
    }
    Ok(())
}
