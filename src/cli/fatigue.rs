//! `windrive rainflow`, `del`, `ldd` and `spectrum`: cycle counting (lists and matrices),
//! damage-equivalent loads, load duration distributions and amplitude spectra of one CSV channel.

use crate::analysis::fatigue::damage;
use crate::analysis::fatigue::ldd;
use crate::analysis::fatigue::matrix;
use crate::analysis::fatigue::rainflow;
use crate::analysis::signal::series;
use crate::analysis::signal::spectrum;
use crate::plot;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct RainflowArgs {
    /// CSV file with a header `time,<name>,...` (fmpy's layout, or ours)
    pub file: PathBuf,
    /// Column to count, e.g. torsional.hss_torque
    #[arg(long)]
    pub channel: String,
    /// Print {"cycles": [[range, mean, count], ...]} for scripts (with --matrix:
    /// {"matrix": {"kind", "rows": [lo, hi, n], "cols": [lo, hi, n], "counts": [[...], ...]}})
    #[arg(long)]
    pub json: bool,
    /// Bin the cycles: range-mean (rows: range from 0, columns: mean) or from-to (levels)
    #[arg(long, value_parser = ["range-mean", "from-to"])]
    pub matrix: Option<String>,
    /// Bins per matrix axis: one number for both, or range,mean (range-mean matrices only)
    #[arg(long, value_delimiter = ',', default_value = "32")]
    pub bins: Vec<usize>,
    /// Draw the matrix (range–mean unless --matrix from-to) as a heat map, .png or .svg
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct LddArgs {
    /// CSV file with a header `time,<name>,...`
    pub file: PathBuf,
    /// Load column, e.g. torsional.hss_torque
    #[arg(long)]
    pub channel: String,
    /// Speed column in rad/s of the shaft whose revolutions count the load cycles, e.g. torsional.generator_speed
    #[arg(long)]
    pub speed: String,
    /// Load bins over the channel's extent
    #[arg(long, default_value_t = 20)]
    pub bins: usize,
    /// Print {"bins": [[load centre, seconds, revolutions], ...]} for scripts
    #[arg(long)]
    pub json: bool,
    /// Bar chart of seconds and revolutions per bin, .png or .svg
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct SpectrumArgs {
    /// CSV file with a header `time,<name>,...`, uniformly sampled
    pub file: PathBuf,
    /// Column to analyse
    #[arg(long)]
    pub channel: String,
    /// Time window [s]: from,to [default: the whole series]
    #[arg(long, value_delimiter = ',')]
    pub window: Option<Vec<f64>>,
    /// Frequency band searched for peaks [Hz]: low,high [default: 0.2 Hz to Nyquist]
    #[arg(long, value_delimiter = ',')]
    pub band: Option<Vec<f64>>,
    /// Number of peaks listed (largest first)
    #[arg(long, default_value_t = 5)]
    pub peaks: usize,
    /// Print {"peaks": [[frequency, amplitude], ...], "resolution": df} for scripts
    #[arg(long)]
    pub json: bool,
    /// Amplitude spectrum with the peaks marked, .png or .svg
    #[arg(long)]
    pub plot: Option<PathBuf>,
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
    /// Goodman mean-load correction with this ultimate load (MLife: L_RF = L_R (L_ult − |L_MF|)/(L_ult − |L_M|))
    #[arg(long)]
    pub goodman: Option<f64>,
    /// Fixed mean L_MF the Goodman-corrected ranges refer to
    #[arg(long, default_value_t = 0.0)]
    pub fixed_mean: f64,
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
    let from_to = args.matrix.as_deref() == Some("from-to");
    let (range_bins, mean_bins) = match args.bins[..] {
        [n] => (n, n),
        [r, m] if !from_to => (r, m),
        _ => anyhow::bail!(
            "--bins {:?}: give one count, or range,mean for a range-mean matrix",
            args.bins
        ),
    };
    if range_bins == 0 || mean_bins == 0 {
        anyhow::bail!("--bins {:?}: a matrix needs at least one bin per axis", args.bins);
    }
    let m = if from_to {
        matrix::from_to(&cycles, &x, range_bins)
    } else {
        matrix::range_mean(&cycles, range_bins, mean_bins)
    };
    if let Some(path) = &args.plot {
        let (xl, yl) = if from_to { ("to", "from") } else { ("mean", "range") };
        plot::heatmap(
            path,
            &format!(
                "{}: rainflow {} matrix",
                args.channel,
                if from_to { "from-to" } else { "range-mean" }
            ),
            &format!("{} {xl}", args.channel),
            &format!("{} {yl}", args.channel),
            &plot::Grid {
                x: (m.cols.lo, m.cols.hi, m.cols.n),
                y: (m.rows.lo, m.rows.hi, m.rows.n),
                counts: &m.counts,
            },
        )?;
        if !args.json {
            println!("plot: {}", path.display());
        }
    }
    if args.json && args.matrix.is_some() {
        let rows: Vec<&[f64]> = m.counts.chunks(m.cols.n).collect();
        let axis = |b: &matrix::Bins| serde_json::json!([b.lo, b.hi, b.n]);
        println!(
            "{}",
            serde_json::json!({ "matrix": {
                "kind": args.matrix, "rows": axis(&m.rows), "cols": axis(&m.cols), "counts": rows } })
        );
        return Ok(());
    }
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
    if let Some(m) = args.m.iter().find(|m| !(m.is_finite() && **m > 0.0)) {
        anyhow::bail!("Wöhler slope --m {m} must be a positive number");
    }
    if let Some(ultimate) = args.goodman
        && !(ultimate.is_finite() && ultimate > args.fixed_mean.abs())
    {
        anyhow::bail!(
            "--goodman {ultimate}: the ultimate load must exceed |--fixed-mean| ({})",
            args.fixed_mean
        );
    }
    let goodman_to = args.goodman.map(|ultimate| (ultimate, args.fixed_mean));
    let (sums, extent, bad) = damage::stream_damage(&args.file, &args.channel, &args.m, goodman_to)?;
    if let Some(e) = bad {
        anyhow::bail!("{} {}: {e}", args.file.display(), args.channel);
    }
    let duration = extent.duration();
    if duration <= 0.0 || args.feq <= 0.0 {
        anyhow::bail!(
            "{}: duration {duration} s and --feq {} must be positive",
            args.file.display(),
            args.feq
        );
    }
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

pub fn run_ldd(args: &LddArgs) -> anyhow::Result<()> {
    let (t, columns) = series::read_channels(&args.file, &[&args.channel, &args.speed])?;
    let (load, speed) = (&columns[0], &columns[1]);
    if args.bins == 0 {
        anyhow::bail!("--bins 0: the distribution needs at least one bin");
    }
    let l = ldd::load_duration(&t, load, speed, args.bins);
    let rows: Vec<[f64; 3]> = (0..l.bins.n)
        .map(|i| [l.bins.centre(i), l.seconds[i], l.revolutions[i]])
        .collect();
    if let Some(path) = &args.plot {
        let secs: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[1])).collect();
        let total_revs: f64 = l.revolutions.iter().sum();
        let total_secs: f64 = l.seconds.iter().sum();
        // revolutions scaled onto the seconds axis so both shapes compare
        let revs: Vec<(f64, f64)> = rows
            .iter()
            .map(|r| (r[0], r[2] * total_secs / total_revs.max(1e-300)))
            .collect();
        let scale = total_secs / total_revs.max(1e-300);
        let lines = [
            ("time at load".to_string(), secs),
            (format!("revolutions (× {scale:.3e} s/rev)"), revs),
        ];
        let title = format!("{}: load duration distribution", args.channel);
        plot::named_lines(path, &title, &args.channel, "seconds per bin", &lines, &[])?;
    }
    if args.json {
        println!("{}", serde_json::json!({ "bins": rows }));
        return Ok(());
    }
    println!(
        "{}: load duration distribution ({} bins of {:.6e})",
        args.channel,
        l.bins.n,
        l.bins.width()
    );
    println!("{:>16} {:>12} {:>14}", "load (centre)", "seconds", "revolutions");
    for r in &rows {
        println!("{:>16.6e} {:>12.4} {:>14.4}", r[0], r[1], r[2]);
    }
    Ok(())
}

pub fn run_spectrum(args: &SpectrumArgs) -> anyhow::Result<()> {
    for (name, v) in [("--window", &args.window), ("--band", &args.band)] {
        if let Some(v) = v
            && (v.len() != 2 || v[0] >= v[1] || !v.iter().all(|x| x.is_finite()))
        {
            anyhow::bail!("{name} {v:?}: give two increasing numbers, low,high");
        }
    }
    let (t, x) = series::read_channel(&args.file, &args.channel)?;
    let (t0, t1) = match &args.window {
        Some(w) => (w[0], w[1]),
        None => (t[0], t[t.len() - 1]),
    };
    let (samples, dt) = spectrum::window(&t, t0, t1).map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?;
    let n = samples.len();
    let (f, a) = spectrum::amplitude_spectrum(&x[samples], dt);
    let (lo, hi) = args.band.as_ref().map_or((0.2, f64::INFINITY), |b| (b[0], b[1]));
    let peaks = spectrum::peaks(&f, &a, lo, hi, args.peaks);
    let df = f[1] - f[0];
    if let Some(path) = &args.plot {
        let f_hi = if hi.is_finite() { hi } else { f[f.len() - 1] };
        let pts: Vec<(f64, f64)> = f
            .iter()
            .zip(&a)
            .filter(|(ff, _)| **ff <= f_hi * 1.2)
            .map(|(ff, aa)| (*ff, *aa))
            .collect();
        let marks: Vec<(f64, String)> = peaks.iter().map(|(pf, _)| (*pf, format!("{pf:.3} Hz"))).collect();
        let title = format!(
            "{}: amplitude spectrum, {t0:.2}-{t1:.2} s (Hann, detrended)",
            args.channel
        );
        let lines = [(args.channel.clone(), pts)];
        plot::named_lines(path, &title, "frequency [Hz]", "amplitude", &lines, &marks)?;
    }
    if args.json {
        println!("{}", serde_json::json!({ "peaks": peaks, "resolution": df }));
        return Ok(());
    }
    println!(
        "{}: {} samples at {dt} s over {t0}..{t1} s, resolution {df:.4} Hz",
        args.channel, n
    );
    for (k, (pf, pa)) in peaks.iter().enumerate() {
        println!("  peak {}: {pf:.4} Hz, amplitude {pa:.6e}", k + 1);
    }
    Ok(())
}
