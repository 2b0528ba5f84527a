//! `windrive life`: a channel's 20-year fatigue from one normal-operation and one shutdown series, as
//! the thesis does it (Ch. 7.2.4): normal operation scaled to the operating hours of a Rayleigh or
//! Weibull wind climate between cut-in and cut-out, shutdowns counted per year (Germanischer Lloyd:
//! 1000 at cut-in, 50 at cut-out, 50 at rated = 1100). Lifetime DELs and the shutdowns' share of the
//! damage; with `--gear`, ISO 6336 contact and root stresses of the mesh force, the allowable stresses
//! at the lifetime's load cycles, and the Miner damage of the flank and root (ISO 6336-6 style: stress
//! bins with their load cycles from the speed); with `--bearing`, the ISO 281 basic rating life of a
//! bearing whose load is the channel, as Miner damage over its load spectrum.

use crate::analysis::gear::{self, Factors, GearPair, Tooth, ToothStress};
use crate::analysis::limits::{LIMITS, limit};
use crate::analysis::tooth_root::{BasicRack, LoadPoint, root_form};
use crate::analysis::wind::{WindDistribution, time_factor};
use crate::analysis::{damage, ldd, life, rainflow, series};
use anyhow::{Context, bail};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct LifeArgs {
    /// Normal-operation CSV (stands for every operating hour)
    #[arg(long)]
    pub normal: PathBuf,
    /// Shutdown CSV (one event)
    #[arg(long)]
    pub shutdown: Option<PathBuf>,
    /// Load channel, e.g. torsional.mesh_force_sun_planet_1 or torsional.hss_torque
    #[arg(long)]
    pub channel: String,
    /// Rayleigh climate with this mean wind speed [m/s] (thesis Table 7.1: 10.0)
    #[arg(long, default_value_t = 10.0)]
    pub mean_wind: f64,
    /// Weibull climate instead: shape,scale (k, C in m/s)
    #[arg(long, value_delimiter = ',')]
    pub weibull: Option<Vec<f64>>,
    #[arg(long, default_value_t = 4.0)]
    pub cut_in: f64,
    #[arg(long, default_value_t = 25.0)]
    pub cut_out: f64,
    #[arg(long, default_value_t = 20.0)]
    pub years: f64,
    /// Shutdowns per year (Germanischer Lloyd: 1000 at cut-in + 50 at cut-out + 50 at rated)
    #[arg(long, default_value_t = 1100.0)]
    pub shutdowns_per_year: f64,
    /// Wöhler slopes of the lifetime DELs
    #[arg(long, value_delimiter = ',', default_value = "3,6,9")]
    pub m: Vec<f64>,
    /// Equivalent frequency of the lifetime DEL [Hz]
    #[arg(long, default_value_t = 1.0)]
    pub feq: f64,
    /// Gear pair of the mesh force: z1,z2,normal module [mm],helix [deg],face width [mm]
    #[arg(long, value_delimiter = ',')]
    pub gear: Option<Vec<f64>>,
    /// The pair is internal (z2 is the ring)
    #[arg(long)]
    pub internal: bool,
    /// Profile shifts x1,x2
    #[arg(long, value_delimiter = ',', default_value = "0,0")]
    pub shift: Vec<f64>,
    /// Normal pressure angle [deg]
    #[arg(long, default_value_t = 20.0)]
    pub pressure_angle: f64,
    /// Which tooth's life: sun, planet (alternating root bending, Y_M = 0.7), ring or parallel
    #[arg(long, default_value = "sun", value_parser = ["sun", "planet", "ring", "parallel"])]
    pub tooth: String,
    /// Planets of the stage (load cycles of sun and ring teeth)
    #[arg(long, default_value_t = 3)]
    pub planets: u32,
    /// Speed channel [rad/s] of the tooth's gear (the carrier's for the ring)
    #[arg(long)]
    pub speed: Option<String>,
    /// Speed channel subtracted from --speed (the carrier, for sun and planet speeds relative to it)
    #[arg(long)]
    pub relative_to: Option<String>,
    /// Load sharing K_γ (IEC 61400-4 mesh load factor: 1.10 for 3 planets, 1.25 for 4, 1.35 for 5)
    #[arg(long, default_value_t = 1.0)]
    pub k_gamma: f64,
    /// Application factor K_A
    #[arg(long, default_value_t = 1.0)]
    pub k_a: f64,
    /// Tooth form and stress correction factors Y_F,Y_S [default: from the root geometry, ISO 6336-3
    /// method B, for external teeth; the ring needs them given]
    #[arg(long, value_delimiter = ',')]
    pub y_fs: Option<Vec<f64>>,
    /// Basic rack of the hob that cut the teeth: dedendum h_fP, root radius ρ_fP (× module)
    #[arg(long, value_delimiter = ',', default_value = "1.25,0.38")]
    pub rack: Vec<f64>,
    /// Which member of --gear the tooth is: 1 (z1) or 2 (z2) [default: sun 1, planet 2 (1 with
    /// --internal), ring 2, parallel 1]
    #[arg(long)]
    pub member: Option<u8>,
    /// Bearing life instead of gear: the bearing's basic dynamic load rating C [N]; the channel is
    /// then its equivalent dynamic load P [N] and --speed its speed [rad/s] (ISO 281 L10, Miner over
    /// the load spectrum)
    #[arg(long, conflicts_with = "gear")]
    pub bearing: Option<f64>,
    /// With --bearing: a ball bearing (life exponent 3; roller bearings 10/3)
    #[arg(long, requires = "bearing")]
    pub ball: bool,
    /// Print the results as JSON
    #[arg(long)]
    pub json: bool,
}

struct Case {
    t: Vec<f64>,
    x: Vec<f64>,
    /// `--speed` less `--relative-to`, when a speed is named
    speed: Option<Vec<f64>>,
    seconds: f64,
}

/// The load channel and, when named, the speed channels of one file, read in one pass.
fn read(args: &LifeArgs, path: &Path) -> anyhow::Result<Case> {
    let mut names = vec![args.channel.as_str()];
    if let Some(speed) = &args.speed {
        names.push(speed);
        names.extend(args.relative_to.as_deref());
    }
    let (t, columns) = series::read_channels(path, &names)?;
    let mut columns = columns.into_iter();
    let x = columns.next().unwrap_or_default();
    let speed = columns.next().map(|w| match columns.next() {
        Some(carrier) => w.iter().zip(&carrier).map(|(a, b)| a - b).collect(),
        None => w,
    });
    let seconds = t[t.len() - 1] - t[0];
    if seconds <= 0.0 {
        bail!("{}: the series lasts {seconds} s", path.display());
    }
    Ok(Case { t, x, speed, seconds })
}

fn sums(x: &[f64], slopes: &[f64]) -> Vec<f64> {
    let mut s = damage::DamageSums::new(slopes);
    let mut counter = rainflow::Counter::new();
    counter.extend(x, &mut |c| s.add(&c));
    counter.finish(&mut |c| s.add(&c));
    s.sums()
}

/// Miner damage of one series' stress with load cycles from its speed: stress bins (LDD) with
/// n_i load cycles each, N_i from the S-N curve at σ_i/limit.
fn stress_damage(
    t: &[f64],
    stress: &[f64],
    speed: &[f64],
    cycles_per_rev: f64,
    limit: f64,
    sn: fn(f64) -> f64,
) -> (f64, f64) {
    let l = ldd::load_duration(t, stress, speed, 200);
    let mut damage = 0.0;
    let mut cycles = 0.0;
    for i in 0..l.bins.n {
        let n = l.revolutions[i] * cycles_per_rev;
        cycles += n;
        let s = l.bins.centre(i);
        if n > 0.0 && s > 0.0 {
            damage += n / sn(s / limit);
        }
    }
    (damage, cycles)
}

pub fn run(args: &LifeArgs) -> anyhow::Result<()> {
    if !(args.cut_in < args.cut_out && args.cut_in >= 0.0 && args.years > 0.0 && args.feq > 0.0) {
        bail!("need 0 ≤ --cut-in < --cut-out, --years > 0 and --feq > 0");
    }
    if args.shutdowns_per_year < 0.0 || args.m.iter().any(|m| m.is_nan() || *m <= 0.0) {
        bail!("--shutdowns-per-year must be ≥ 0 and every --m positive");
    }
    let climate = match &args.weibull {
        Some(w) if w.len() == 2 && w[0] > 0.0 && w[1] > 0.0 => WindDistribution::Weibull {
            shape: w[0],
            scale: w[1],
        },
        Some(w) => bail!("--weibull {w:?}: give shape,scale, both positive"),
        None if args.mean_wind > 0.0 => WindDistribution::Rayleigh { mean: args.mean_wind },
        None => bail!("--mean-wind {}: must be positive", args.mean_wind),
    };
    let life_hours = args.years * 8760.0;
    let operating_hours = life_hours * (climate.cdf(args.cut_out) - climate.cdf(args.cut_in));
    let shutdowns = args.shutdowns_per_year * args.years;
    let normal = read(args, &args.normal)?;
    let shutdown = args.shutdown.as_ref().map(|p| read(args, p)).transpose()?;
    let normal_factor = time_factor(operating_hours, normal.seconds);
    let life_seconds = life_hours * 3600.0;

    // lifetime DELs: Σ n S^m of each case times its repetitions
    let n_sums = sums(&normal.x, &args.m);
    let s_sums = shutdown
        .as_ref()
        .map_or(vec![0.0; args.m.len()], |s| sums(&s.x, &args.m));
    let dels: Vec<(f64, f64, f64)> = args
        .m
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let (a, b) = (n_sums[i] * normal_factor, s_sums[i] * shutdowns);
            (*m, ((a + b) / (args.feq * life_seconds)).powf(1.0 / m), b / (a + b))
        })
        .collect();

    let lifetime = Lifetime {
        normal: &normal,
        shutdown: shutdown.as_ref(),
        normal_factor,
        shutdowns,
    };
    let bearing_report = args.bearing.map(|c| bearing_life(args, c, &lifetime)).transpose()?;
    let gear_report = args.gear.as_ref().map(|g| gear_life(args, g, &lifetime)).transpose()?;

    if args.json {
        let d: Vec<serde_json::Value> = dels
            .iter()
            .map(|(m, del, share)| serde_json::json!({"m": m, "del": del, "shutdown_share": share}))
            .collect();
        println!(
            "{}",
            serde_json::json!({
                "operating_hours": operating_hours, "life_hours": life_hours, "shutdowns": shutdowns,
                "normal_time_factor": normal_factor, "lifetime_del": d, "gear": gear_report.map(|r| r.json),
                "bearing": bearing_report.map(|r| r.json),
            })
        );
        return Ok(());
    }
    println!(
        "{} over {} years: {operating_hours:.0} h in operation ({:.1} % of {life_hours:.0} h, {:?}, {}–{} m/s), {shutdowns:.0} shutdowns",
        args.channel,
        args.years,
        100.0 * operating_hours / life_hours,
        climate,
        args.cut_in,
        args.cut_out
    );
    println!(
        "normal operation: {:.1} s simulated, time factor {normal_factor:.4e}",
        normal.seconds
    );
    println!("\n{:>6} {:>16} {:>22}", "m", "lifetime DEL", "share from shutdowns");
    for (m, del, share) in &dels {
        println!("{m:>6} {del:>16.6e} {:>21.1}%", 100.0 * share);
    }
    if let Some(r) = gear_report.or(bearing_report) {
        print!("\n{}", r.text);
    }
    println!("\nallowable stresses (reference):");
    for (component, value, what, source) in LIMITS {
        println!("  {component:<24} {:>7.0} MPa  {what} ({source})", value / 1e6);
    }
    Ok(())
}

/// What every component's life is made of: normal operation scaled to the operating hours, and the
/// shutdown repeated once per shutdown.
struct Lifetime<'a> {
    normal: &'a Case,
    shutdown: Option<&'a Case>,
    normal_factor: f64,
    shutdowns: f64,
}

impl Lifetime<'_> {
    /// Each case with its name and how often it repeats in the lifetime.
    fn cases(&self) -> Vec<(&'static str, &Case, f64)> {
        let mut cases = vec![("normal", self.normal, self.normal_factor)];
        if let Some(s) = self.shutdown {
            cases.push(("shutdown", s, self.shutdowns));
        }
        cases
    }
}

/// ISO 281 basic rating life of a bearing loaded by the channel: each case's load spectrum (every
/// sample's |P| with the revolutions until the next sample) summed by Miner's rule against
/// L10(P) = (C/P)^p 10⁶ revolutions, repeated as often as the case occurs in the lifetime.
fn bearing_life(args: &LifeArgs, capacity: f64, lifetime: &Lifetime) -> anyhow::Result<Report> {
    if !(capacity.is_finite() && capacity > 0.0) {
        bail!("--bearing {capacity}: the dynamic load rating C must be a positive number of newtons");
    }
    let roller = !args.ball;
    let p = if roller { 10.0 / 3.0 } else { 3.0 };
    let mut rows = Vec::new();
    let (mut damage, mut revolutions, mut weighted, mut shutdown_damage) = (0.0, 0.0, 0.0, 0.0);
    for (name, case, repeat) in lifetime.cases() {
        // every sample holds its load for its time step (as in the LDD), with no binning error
        let w = case
            .speed
            .as_deref()
            .context("--bearing needs --speed: the bearing's life is counted in its revolutions")?;
        let spectrum: Vec<(f64, f64)> = ldd::sample_revolutions(&case.t, w)
            .zip(&case.x)
            .map(|((_, revolutions), load)| (load.abs(), revolutions))
            .collect();
        let d = life::bearing_damage(capacity, &spectrum, roller) * repeat;
        let n: f64 = spectrum.iter().map(|(_, n)| n).sum::<f64>() * repeat;
        weighted += spectrum.iter().map(|(load, n)| n * load.powf(p)).sum::<f64>() * repeat;
        let max = case.x.iter().map(|v| v.abs()).fold(0.0, f64::max);
        rows.push((name, max, n, d));
        (damage, revolutions) = (damage + d, revolutions + n);
        if name == "shutdown" {
            shutdown_damage = d;
        }
    }
    let equivalent_load = (weighted / revolutions.max(1e-300)).powf(1.0 / p);
    let l10 = life::bearing_l10(capacity, equivalent_load, roller) * 1e6;
    let mut text = format!(
        "{} bearing, C = {capacity:.4e} N, ISO 281 L10 = (C/P)^{} million revolutions\n",
        if roller { "roller" } else { "ball" },
        if roller { "10/3" } else { "3" }
    );
    text.push_str(&format!(
        "{:<10} {:>14} {:>16} {:>14}\n",
        "case", "max P [N]", "revolutions", "damage"
    ));
    for (name, max, n, d) in &rows {
        text.push_str(&format!("{name:<10} {max:>14.4e} {n:>16.4e} {d:>14.4e}\n"));
    }
    text.push_str(&format!(
        "lifetime: {revolutions:.4e} revolutions at P_eq = {equivalent_load:.4e} N (L10 {l10:.4e} revolutions)\n"
    ));
    text.push_str(&format!(
        "{}-year Miner damage {damage:.4e} ({:.1} % from shutdowns): L10 life {:.1} years\n",
        args.years,
        100.0 * shutdown_damage / damage.max(1e-300),
        args.years / damage.max(1e-300)
    ));
    let json = serde_json::json!({
        "cases": rows.iter().map(|(n, max, revs, d)| serde_json::json!({"case": n, "max_load": max, "revolutions": revs, "damage": d})).collect::<Vec<_>>(),
        "revolutions": revolutions, "equivalent_load": equivalent_load, "l10_revolutions": l10,
        "damage": damage, "shutdown_share": shutdown_damage / damage.max(1e-300), "l10_years": args.years / damage.max(1e-300),
    });
    Ok(Report { text, json })
}

struct Report {
    text: String,
    json: serde_json::Value,
}

fn gear_life(args: &LifeArgs, g: &[f64], lifetime: &Lifetime) -> anyhow::Result<Report> {
    if g.len() != 5 || g.iter().any(|v| !v.is_finite()) || g[0] < 3.0 || g[1] < 3.0 || g[2] <= 0.0 || g[4] <= 0.0 {
        bail!("--gear {g:?}: give z1,z2,module [mm],helix [deg],face width [mm] (teeth ≥ 3, module and width > 0)");
    }
    if args.shift.len() != 2 || args.rack.len() != 2 || args.y_fs.as_ref().is_some_and(|y| y.len() != 2) {
        bail!("--shift, --rack and --y-fs take two numbers each");
    }
    if !(args.rack[0] > 0.0 && args.rack[1] >= 0.0 && args.rack[1] < args.rack[0]) {
        bail!(
            "--rack {:?}: give the hob's dedendum h_fP > 0 and root radius 0 ≤ ρ_fP < h_fP, in modules",
            args.rack
        );
    }
    if args.speed.is_none() {
        bail!("--gear needs --speed: the load cycles come from the gear's revolutions");
    }
    let pair = GearPair {
        z1: g[0] as u32,
        z2: g[1] as u32,
        internal: args.internal,
        module: g[2] * 1e-3,
        pressure_angle: args.pressure_angle.to_radians(),
        helix_angle: g[3].to_radians(),
        face_width: g[4] * 1e-3,
        shift1: args.shift[0],
        shift2: args.shift[1],
        tip_diameters: None,
    };
    let tooth = match args.tooth.as_str() {
        "sun" => Tooth::Sun,
        "planet" => Tooth::Planet,
        "ring" => Tooth::Ring,
        _ => Tooth::Parallel,
    };
    let member = args.member.unwrap_or(match tooth {
        Tooth::Planet if !args.internal => 2,
        Tooth::Ring => 2,
        _ => 1,
    });
    let (y_f, y_s, root_note) = match &args.y_fs {
        Some(y) => (y[0], y[1], "given".to_string()),
        None => {
            let rack = BasicRack {
                dedendum: args.rack[0],
                root_radius: args.rack[1],
                protuberance: 0.0,
            };
            let r = root_form(&pair, member, &rack, LoadPoint::SinglePairContact)
                .map_err(|e| anyhow::anyhow!("--gear {g:?}, member {member}: {e} (--y-fs)"))?;
            let note = format!(
                "ISO 6336-3 method B, member {member}: s_Fn {:.2} mm, h_Fe {:.2} mm, ρ_F {:.2} mm",
                r.chord * 1e3,
                r.bending_arm * 1e3,
                r.fillet_radius * 1e3
            );
            (r.form_factor, r.stress_correction, note)
        }
    };
    let factors = Factors {
        k_a: args.k_a,
        k_gamma: args.k_gamma,
        y_f,
        y_s,
        ..Factors::default()
    };
    let st = ToothStress::steel(pair, factors);
    let per_rev = tooth.load_cycles(1.0, args.planets);
    let sigma_hlim = limit("gear flank, σ_Hlim MQ").expect("in the table");
    let sigma_fe = 2.0 * limit("gear root, σ_Flim MQ").expect("in the table") * tooth.mean_stress_factor();
    let mut rows = Vec::new();
    let (mut total_h, mut total_f, mut total_cycles) = (0.0, 0.0, 0.0);
    let mut shut_h = 0.0;
    let mut shut_f = 0.0;
    for (name, case, repeat) in lifetime.cases() {
        let ft: Vec<f64> = case.x.iter().map(|f| st.tangential_from_normal(*f)).collect();
        let sh: Vec<f64> = ft.iter().map(|f| st.contact(*f)).collect();
        let sf: Vec<f64> = ft.iter().map(|f| st.bending(*f)).collect();
        let w = case.speed.as_deref().context("read with --speed")?;
        let (dh, n) = stress_damage(&case.t, &sh, w, per_rev, sigma_hlim, gear::contact_cycles_to_failure);
        let (df, _) = stress_damage(&case.t, &sf, w, per_rev, sigma_fe, gear::bending_cycles_to_failure);
        let max = |v: &[f64]| v.iter().cloned().fold(0.0, f64::max);
        rows.push((name, max(&sh), max(&sf), n * repeat, dh * repeat, df * repeat));
        total_h += dh * repeat;
        total_f += df * repeat;
        total_cycles += n * repeat;
        if name == "shutdown" {
            shut_h = dh * repeat;
            shut_f = df * repeat;
        }
    }
    let z_nt = gear::contact_life_factor(total_cycles);
    let y_nt = gear::bending_life_factor(total_cycles);
    let (allow_h, allow_f) = (sigma_hlim * z_nt, sigma_fe * y_nt);
    let mut text = format!(
        "gear {}/{} m_n {} mm β {}° b {} mm ({:?} tooth, {} load cycles per revolution): ε_α {:.3}, ε_β {:.3}\n",
        pair.z1,
        pair.z2,
        g[2],
        g[3],
        g[4],
        tooth,
        per_rev,
        pair.geometry().transverse_contact_ratio,
        pair.geometry().overlap_ratio
    );
    text.push_str(&format!("Y_F {y_f:.4}, Y_S {y_s:.4} ({root_note})\n"));
    text.push_str(&format!(
        "{:<10} {:>12} {:>12} {:>16} {:>14} {:>14}\n",
        "case", "max σ_H MPa", "max σ_F MPa", "load cycles", "flank damage", "root damage"
    ));
    for (name, h, f, n, dh, df) in &rows {
        text.push_str(&format!(
            "{name:<10} {:>12.1} {:>12.1} {n:>16.4e} {dh:>14.4e} {df:>14.4e}\n",
            h / 1e6,
            f / 1e6
        ));
    }
    text.push_str(&format!(
        "lifetime: {total_cycles:.4e} load cycles → Z_NT {z_nt:.3}, Y_NT {y_nt:.3}; limits σ_Hlim·Z_NT = {:.0} MPa, σ_FE·Y_M·Y_NT = {:.0} MPa\n",
        allow_h / 1e6,
        allow_f / 1e6
    ));
    text.push_str(&format!(
        "20-year Miner damage: flank {total_h:.4e} ({:.1} % from shutdowns), root {total_f:.4e} ({:.1} % from shutdowns)\n",
        100.0 * shut_h / total_h.max(1e-300),
        100.0 * shut_f / total_f.max(1e-300)
    ));
    let json = serde_json::json!({
        "cases": rows.iter().map(|(n, h, f, c, dh, df)| serde_json::json!({"case": n, "max_contact_stress": h, "max_root_stress": f, "load_cycles": c, "flank_damage": dh, "root_damage": df})).collect::<Vec<_>>(),
        "load_cycles": total_cycles, "y_f": y_f, "y_s": y_s, "z_nt": z_nt, "y_nt": y_nt, "flank_damage": total_h, "root_damage": total_f,
        "flank_shutdown_share": shut_h / total_h.max(1e-300), "root_shutdown_share": shut_f / total_f.max(1e-300),
    });
    Ok(Report { text, json })
}
