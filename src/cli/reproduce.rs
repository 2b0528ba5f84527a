//! `windrive reproduce`: every number of the thesis this project computes, beside ours, as a Markdown
//! table (docs/REPRODUCTION.md): the thesis value with where it stands, ours, the difference, whether
//! we claim to reproduce it (and to what tolerance), and a one-line reason where they differ. The
//! study, and the thesis's values as data, are [`crate::studies::reproduce`]. With `--set`, the rows
//! that the named estimates act on, at those values, as JSON: one evaluation of the sensitivity
//! campaign (`scripts/campaign sensitivity`).

use crate::cosim::Scene;
use crate::studies::estimates::{self, Setting};
use crate::studies::reproduce::{Band, Row, markdown, read_bands, report, rows_where};
use anyhow::Context;
use std::collections::HashMap;
use std::path::PathBuf;

const EXAMPLES: &str = "\
Examples:
  windrive reproduce --out docs/REPRODUCTION.md
      every row, as the page in docs/ (about a minute)
  windrive reproduce --estimates
      the inputs no source gives, with their ranges and reasons, as JSON
  windrive reproduce --set a_brake_torque=2.0 --set a_trip_delay=0.5
      the rows drivetrain A's shutdown gives, with its brake at 2 × rated and a 0.5 s trip delay, as JSON";

#[derive(clap::Args)]
#[command(after_help = EXAMPLES)]
pub struct ReproduceArgs {
    /// Markdown table to write [default: results/reproduction.md; with --set, none unless given]
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Set an estimate (NAME=VALUE, in its unit; repeatable) and compute only the rows whose scenes
    /// it acts on, printed as JSON
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Print the estimates (inputs no source gives: nominal, range, reason, where they go) as JSON
    #[arg(long, conflicts_with = "set")]
    pub estimates: bool,
}

/// A scene of the repository's scenes/ folder, with our FMUs in place.
pub fn open_scene(name: &str) -> anyhow::Result<Scene> {
    let scene = Scene::open(&crate::pack::workspace_root()?.join("scenes").join(name))?;
    super::run::provide_own_fmus(&scene, false)?;
    Ok(scene)
}

pub fn run(args: &ReproduceArgs) -> anyhow::Result<()> {
    if args.estimates {
        println!("{}", serde_json::to_string_pretty(&estimates::all()?)?);
        return Ok(());
    }
    if !args.set.is_empty() {
        return run_set(args);
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("results/reproduction.md"));
    // a folder that cannot be made fails now, not after the scenes' minute of runs
    make_parent(&out)?;
    let report = report(&open_scene)?;
    let text = report.markdown(&bands()?)?;
    let rows = &report.rows;
    print!("{text}");
    write(&out, &text)?;
    let claimed = rows.iter().filter(|r| r.claimed.is_some()).count();
    let held = rows.iter().filter(|r| r.reproduced()).count();
    println!(
        "\n{held} of {claimed} claimed rows reproduced, {} shown; table written to {}",
        rows.len(),
        out.display()
    );
    Ok(())
}

/// What the sensitivity campaign found (docs/sensitivity/bands.json), none before it has run.
pub fn bands() -> anyhow::Result<HashMap<String, Band>> {
    let path = crate::pack::workspace_root()?.join("docs/sensitivity/bands.json");
    match std::fs::read_to_string(&path) {
        Ok(text) => read_bands(&text).with_context(|| path.display().to_string()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(HashMap::new()),
        Err(e) => Err(e).with_context(|| path.display().to_string()),
    }
}

fn make_parent(out: &std::path::Path) -> anyhow::Result<()> {
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).with_context(|| parent.display().to_string())?;
    }
    Ok(())
}

fn write(out: &std::path::Path, text: &str) -> anyhow::Result<()> {
    make_parent(out)?;
    std::fs::write(out, text).with_context(|| out.display().to_string())
}

/// The rows the set estimates act on, at the set values, as a JSON array on stdout.
fn run_set(args: &ReproduceArgs) -> anyhow::Result<()> {
    let folder = std::env::temp_dir().join(format!("windrive-estimates-{}", std::process::id()));
    let result = (|| {
        if let Some(out) = &args.out {
            make_parent(out)?;
        }
        let setting = Setting::parse(&args.set, &folder)?;
        let open = |name: &str| -> anyhow::Result<Scene> {
            let mut scene = open_scene(name)?;
            setting.apply(name, &mut scene)?;
            Ok(scene)
        };
        // a row is recomputed when a scene it runs is one the setting acts on (each scene asked once)
        let known = std::cell::RefCell::new(std::collections::HashMap::new());
        let acts = |ours: &crate::studies::reproduce::Ours| {
            ours.scenes().iter().any(|s| {
                *known
                    .borrow_mut()
                    .entry(s.clone())
                    .or_insert_with(|| open_scene(s).is_ok_and(|scene| setting.acts_on(s, &scene)))
            })
        };
        let rows = rows_where(&open, &acts)?;
        if rows.is_empty() {
            anyhow::bail!("--set: no row of the reproduction runs a scene these estimates act on");
        }
        if let Some(out) = &args.out {
            write(out, &markdown(&rows, &HashMap::new()))?;
        }
        println!("{}", serde_json::to_string_pretty(&json(&rows))?);
        Ok(())
    })();
    let _ = std::fs::remove_dir_all(&folder);
    result
}

fn json(rows: &[Row]) -> serde_json::Value {
    serde_json::Value::Array(
        rows.iter()
            .map(|r| {
                serde_json::json!({
                    "quantity": r.quantity,
                    "source": r.source,
                    "thesis": r.thesis.to_string(),
                    "ours": r.ours,
                    "verdict": r.verdict().label(),
                })
            })
            .collect(),
    )
}
