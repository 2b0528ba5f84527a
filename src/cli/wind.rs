//! `windrive wind`: an IEC 61400-1 ed. 3 full turbulence field (u, v, w on a rotor-plane grid) written
//! as a TurbSim .bts file, or a .bts file read and written again (our reader and writer in one trip).

use crate::physics::turbulence::{TurbulenceModel, Variance, class_reference_intensity, iec_sigma};
use crate::physics::wind_field::{COMPONENTS, FieldSpec, Grid, WindField, bts, generate};
use anyhow::{Context, bail};
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive wind --out turb.bts                                   15×15 over 150 m at a 90 m hub, 11.4 m/s, class A NTM, 600 s at 0.05 s\n  \
    windrive wind --out turb.bts --wind 16 --class B --seed 3 --grid 21x15 --width 160 --height 120\n  \
    windrive wind --out etm.bts --model etm --v-ref 42.5          extreme turbulence of a class II turbine\n  \
    windrive wind --from turbsim.bts --out copy.bts --json         read a TurbSim file, write it again, print its statistics\n\n\
    The field is periodic over --period (ID 8 in the file) with exactly the power-law mean profile over it;\n\
    σ is read as IEC's 10-minute σ1: v and w hold 0.8σ1 and 0.5σ1 at every point, u σ1 over the grid.")]
pub struct WindArgs {
    /// The TurbSim .bts file to write
    #[arg(long)]
    pub out: PathBuf,
    /// Read this .bts file instead of generating a field
    #[arg(long, conflicts_with_all = ["wind", "hub_height", "class", "model", "v_ref", "intensity", "shear", "grid", "width", "height", "period", "dt", "seed"])]
    pub from: Option<PathBuf>,
    /// Mean wind speed at hub height, m/s
    #[arg(long, default_value_t = 11.4)]
    pub wind: f64,
    /// Hub height, m (Λ1 = 0.7·z_hub below 60 m, else 42 m)
    #[arg(long, default_value_t = 90.0)]
    pub hub_height: f64,
    /// IEC 61400-1 turbulence class: A, B or C
    #[arg(long, default_value = "A")]
    pub class: String,
    /// IEC turbulence model: ntm (normal) or etm (extreme)
    #[arg(long, default_value = "ntm")]
    pub model: String,
    /// Reference wind speed of the turbine class for the ETM, m/s (I 50, II 42.5, III 37.5)
    #[arg(long, default_value_t = 50.0)]
    pub v_ref: f64,
    /// Turbulence intensity σ1/V instead of the IEC model's
    #[arg(long)]
    pub intensity: Option<f64>,
    /// Power-law shear exponent α of the mean wind profile
    #[arg(long, default_value_t = 0.2)]
    pub shear: f64,
    /// Grid points: N (N×N) or NYxNZ (across × up)
    #[arg(long, default_value = "15")]
    pub grid: String,
    /// Grid width, m (the rotor diameter plus a margin)
    #[arg(long, default_value_t = 150.0)]
    pub width: f64,
    /// Grid height, m (default: the width)
    #[arg(long)]
    pub height: Option<f64>,
    /// Period of the field, s: it repeats after it (σ from IEC's 10 minutes held exactly from 600 s on)
    #[arg(long, default_value_t = 600.0)]
    pub period: f64,
    /// Largest time step, s (the step is the period over an even count)
    #[arg(long, default_value_t = 0.05)]
    pub dt: f64,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print the header and every grid point's mean and σ per component (before quantisation) as JSON
    #[arg(long)]
    pub json: bool,
}

fn grid_counts(text: &str) -> anyhow::Result<(usize, usize)> {
    let parse = |s: &str| {
        s.trim()
            .parse::<usize>()
            .with_context(|| format!("--grid {text:?}: use N or NYxNZ"))
    };
    match text.split_once(['x', 'X', '×']) {
        Some((y, z)) => Ok((parse(y)?, parse(z)?)),
        None => parse(text).map(|n| (n, n)),
    }
}

fn spec(args: &WindArgs) -> anyhow::Result<(FieldSpec, String)> {
    let Some(i_ref) = class_reference_intensity(&args.class) else {
        bail!("--class {:?}: use A, B or C", args.class);
    };
    let model = match args.model.trim() {
        "ntm" => TurbulenceModel::Ntm,
        "etm" => TurbulenceModel::Etm,
        other => bail!("--model {other:?}: use ntm or etm"),
    };
    let (sigma, source) = match args.intensity {
        Some(ti) if ti.is_finite() && ti >= 0.0 => (ti * args.wind, format!("intensity {ti}")),
        Some(ti) => bail!("--intensity {ti}: must be finite and not negative"),
        None => (
            iec_sigma(model, args.wind, i_ref, args.v_ref),
            format!(
                "{} class {}",
                args.model.trim().to_uppercase(),
                args.class.trim().to_uppercase()
            ),
        ),
    };
    let (ny, nz) = grid_counts(&args.grid)?;
    let spec = FieldSpec {
        mean_wind: args.wind,
        sigma,
        hub_height: args.hub_height,
        shear_exponent: args.shear,
        grid: Grid {
            ny,
            nz,
            width: args.width,
            height: args.height.unwrap_or(args.width),
        },
        period: args.period,
        max_dt: args.dt,
        variance: Variance::TenMinute,
        seed: args.seed,
    };
    let description = format!(
        "windrive: IEC 61400-1 ed. 3 Kaimal full field, {source}, sigma1 {sigma:.4} m/s, alpha {}, seed {}",
        args.shear, args.seed
    );
    Ok((spec, description))
}

pub fn run(args: &WindArgs) -> anyhow::Result<()> {
    let start = std::time::Instant::now();
    let (field, description) = match &args.from {
        Some(path) => (bts::read(path)?, format!("windrive: copy of {}", path.display())),
        None => {
            let (spec, description) = spec(args)?;
            (generate(&spec).context("windrive wind")?, description)
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    bts::write(&args.out, &field, &description)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary(&field, seconds))?);
    } else {
        print_summary(&field, seconds, args);
    }
    Ok(())
}

fn summary(field: &WindField, seconds: f64) -> serde_json::Value {
    let moments: Vec<Vec<(f64, f64)>> = (0..3).map(|c| field.point_moments(c)).collect();
    serde_json::json!({
        "ny": field.ny, "nz": field.nz, "nt": field.nt,
        "dy": field.dy, "dz": field.dz, "dt": field.dt,
        "z_bottom": field.z_bottom, "hub_height": field.hub_height, "mean_hub": field.mean_hub,
        "periodic": field.periodic,
        "mean": moments.iter().map(|m| m.iter().map(|x| x.0).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "std": moments.iter().map(|m| m.iter().map(|x| x.1).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "seconds": seconds,
    })
}

fn print_summary(field: &WindField, seconds: f64, args: &WindArgs) {
    let what = if args.from.is_some() { "read" } else { "generated" };
    println!(
        "{} × {} points (dy {:.3} m, dz {:.3} m, bottom {:.2} m), {} steps of {:.6} s ({:.3} s{}), {what} in {seconds:.2} s",
        field.ny,
        field.nz,
        field.dy,
        field.dz,
        field.z_bottom,
        field.nt,
        field.dt,
        field.duration(),
        if field.periodic { ", periodic" } else { "" }
    );
    for c in 0..3 {
        let moments = field.point_moments(c);
        let sigma = (moments.iter().map(|m| m.1 * m.1).sum::<f64>() / moments.len() as f64).sqrt();
        let (lo, hi) = moments.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), m| {
            (lo.min(m.0), hi.max(m.0))
        });
        println!(
            "{}: mean {lo:.3} to {hi:.3} m/s, σ over the grid {sigma:.4} m/s",
            COMPONENTS[c]
        );
    }
    println!("wrote {}", args.out.display());
}
