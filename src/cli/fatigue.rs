//! `windrive rainflow` and `windrive del`: cycle counting and damage-equivalent loads of one CSV channel.

use crate::analysis::{damage, rainflow, series};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct RainflowArgs {
    /// CSV file with a header `time,<name>,...` (fmpy's layout, or ours)
    pub file: PathBuf,
    /// Column to count, e.g. torsional.hss_torque
    #[arg(long)]
    pub channel: String,
    /// Print {"cycles": [[range, mean, count], ...]} for scripts
    #[arg(long)]
    pub json: bool,
}

#[derive(clap::Args)]
pub struct DelArgs {
    /// CSV file with a header `time,<name>,...`
    pub file: PathBuf,
    /// Column to evaluate
    #[arg(long)]
    pub channel: String,
    /// Wöhler slopes, one DEL each (3 welded steel, 6 forged, 9 cast; the thesis uses 6)
    #[arg(long, value_delimiter = ',', default_value = "3,6,9")]
    pub m: Vec<f64>,
    /// Equivalent frequency in Hz: N_eq = feq × (last time − first time)
    #[arg(long, default_value_t = 1.0)]
    pub feq: f64,
    /// Print {"del": {"3": ..., "6": ...}} for scripts
    #[arg(long)]
    pub json: bool,
}

fn fmt_m(m: f64) -> String {
    if m.fract() == 0.0 {
        format!("{}", m as i64)
    } else {
        format!("{m}")
    }
}

pub fn run_rainflow(args: &RainflowArgs) -> anyhow::Result<()> {
    let (_, x) = series::read_channel(&args.file, &args.channel)?;
    let cycles = rainflow::cycles(&x);
    if args.json {
        let list: Vec<[f64; 3]> = cycles.iter().map(|c| [c.range, c.mean, c.count]).collect();
        println!("{}", serde_json::json!({ "cycles": list }));
        return Ok(());
    }
    let full: f64 = cycles.iter().filter(|c| c.count == 1.0).count() as f64;
    let half = cycles.iter().filter(|c| c.count == 0.5).count();
    let largest = cycles.iter().map(|c| c.range).fold(0.0, f64::max);
    println!(
        "{}: {} samples, {} full and {} half cycles, largest range {:.6e}",
        args.channel,
        x.len(),
        full,
        half,
        largest
    );
    Ok(())
}

pub fn run_del(args: &DelArgs) -> anyhow::Result<()> {
    let (t, x) = series::read_channel(&args.file, &args.channel)?;
    let duration = t[t.len() - 1] - t[0];
    if duration <= 0.0 || args.feq <= 0.0 {
        anyhow::bail!(
            "{}: duration {duration} s and --feq {} must be positive",
            args.file.display(),
            args.feq
        );
    }
    if let Some(m) = args.m.iter().find(|m| !(m.is_finite() && **m > 0.0)) {
        anyhow::bail!("Wöhler slope --m {m} must be a positive number");
    }
    // every slope in the same streaming pass
    let mut sums = damage::DamageSums::new(&args.m);
    let mut counter = rainflow::Counter::new();
    for &v in &x {
        counter.push(v, &mut |c| sums.add(&c));
    }
    counter.finish(&mut |c| sums.add(&c));
    let n_eq = args.feq * duration;
    let dels: Vec<(String, f64)> = args.m.iter().map(|&m| fmt_m(m)).zip(sums.dels(n_eq)).collect();
    if args.json {
        let map: serde_json::Map<String, serde_json::Value> = dels.into_iter().map(|(k, v)| (k, v.into())).collect();
        println!("{}", serde_json::json!({ "del": map }));
        return Ok(());
    }
    println!("{}: {} s, N_eq = {n_eq} ({} Hz)", args.channel, duration, args.feq);
    for (m, del) in dels {
        println!("  m = {m:<4} DEL = {del:.6e}");
    }
    Ok(())
}
