//! `windrive climate`: the DLC 1.2 wind bins of a wind climate, with their probabilities, hours in the
//! design life and the IEC normal turbulence model's intensity ([`WindDistribution::dlc_bins`]). The
//! campaign driver expands its DLC 1.2 cases from this output.

use crate::analysis::fatigue::operating_hours::WindDistribution;
use crate::physics::turbulence::class_reference_intensity;
use anyhow::bail;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive climate --rayleigh 10 --cut-in 4 --cut-out 25 --bin-width 2      IEC class I's Rayleigh climate, 2 m/s bins\n  \
    windrive climate --weibull 2,11 --cut-in 10 --cut-out 12 --class B --json  as a campaign reads it\n\n\
    Bin j is simulated at cut_in + j·width and covers ±width/2 around it, clipped to [cut-in, cut-out],\n\
    so the bins tile the operating range.")]
pub struct ClimateArgs {
    /// Weibull climate: shape,scale (k, A in m/s)
    #[arg(
        long,
        value_delimiter = ',',
        conflicts_with = "rayleigh",
        required_unless_present = "rayleigh"
    )]
    pub weibull: Option<Vec<f64>>,
    /// Rayleigh climate with this mean wind speed, m/s (IEC 61400-1 class I: 10, II: 8.5, III: 7.5)
    #[arg(long)]
    pub rayleigh: Option<f64>,
    /// Cut-in wind speed, m/s
    #[arg(long)]
    pub cut_in: f64,
    /// Cut-out wind speed, m/s
    #[arg(long)]
    pub cut_out: f64,
    /// Width of the wind-speed bins, m/s
    #[arg(long, default_value_t = 2.0)]
    pub bin_width: f64,
    /// Design life, years (hours = probability × 8760 × years)
    #[arg(long, default_value_t = 20.0)]
    pub years: f64,
    /// IEC 61400-1 turbulence class of the normal turbulence model's intensity: A, B or C
    #[arg(long, default_value = "A")]
    pub class: String,
    /// Print the bins as JSON
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &ClimateArgs) -> anyhow::Result<()> {
    let positive = |x: f64| x.is_finite() && x > 0.0;
    let wind = match (&args.weibull, args.rayleigh) {
        (Some(w), _) if w.len() == 2 && positive(w[0]) && positive(w[1]) => WindDistribution::Weibull {
            shape: w[0],
            scale: w[1],
        },
        (Some(w), _) => bail!("--weibull {w:?}: give shape,scale, both positive"),
        (None, Some(mean)) if positive(mean) => WindDistribution::Rayleigh { mean },
        (None, m) => bail!("--rayleigh {m:?}: give a positive mean wind speed"),
    };
    if !(args.cut_in.is_finite() && args.cut_in >= 0.0 && args.cut_out.is_finite() && args.cut_out > args.cut_in) {
        bail!(
            "--cut-in {} --cut-out {}: need 0 ≤ cut-in < cut-out",
            args.cut_in,
            args.cut_out
        );
    }
    if !positive(args.bin_width) || !positive(args.years) {
        bail!(
            "--bin-width {} --years {}: both must be positive",
            args.bin_width,
            args.years
        );
    }
    let Some(i_ref) = class_reference_intensity(&args.class) else {
        bail!("--class {:?}: use A, B or C", args.class);
    };
    let rows = wind.dlc12_bins(args.cut_in, args.cut_out, args.bin_width, args.years, i_ref);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    println!(
        "{:>8} {:>15} {:>12} {:>10} {:>8}",
        "v, m/s", "bin, m/s", "probability", "hours", "NTM TI"
    );
    for r in &rows {
        println!(
            "{:>8} {:>15} {:>12.6} {:>10.1} {:>8.4}",
            r.bin.speed,
            format!("{}–{}", r.bin.lo, r.bin.hi),
            r.bin.probability,
            r.hours,
            r.ntm_turbulence_intensity
        );
    }
    let hours: f64 = rows.iter().map(|r| r.hours).sum();
    println!("{hours:.1} h between cut-in and cut-out in {} years", args.years);
    Ok(())
}
