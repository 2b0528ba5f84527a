//! `windrive reproduce`: every number of the thesis this project computes, beside ours, as a Markdown
//! table (docs/REPRODUCTION.md): the thesis value with where it stands, ours, the difference, whether
//! we claim to reproduce it (and to what tolerance), and a one-line reason where they differ. The
//! study, and the thesis's values as data, are [`crate::studies::reproduce`].

use crate::cosim::Scene;
use crate::studies::reproduce::{Row, rows};
use anyhow::Context;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ReproduceArgs {
    /// Markdown table to write
    #[arg(long, default_value = "results/reproduction.md")]
    pub out: PathBuf,
}

pub fn table(rows: &[Row]) -> String {
    let mut s = String::from(
        "# The thesis's numbers beside ours\n\nWritten by `windrive reproduce`. \"claimed\" rows are asserted by \
         tests/it/reproduction.rs within the tolerance shown; the others are shown with the reason they differ.\n\n\
         | quantity | thesis | where | ours | difference | claimed | reason |\n|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let claim = match r.claimed {
            Some(t) if r.reproduced() => format!("yes, ±{:.1} %", t * 100.0),
            Some(t) => format!("**no** (±{:.1} %)", t * 100.0),
            None => "—".into(),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:+.2} % | {} | {} |",
            r.quantity,
            r.thesis,
            r.source,
            format_ours(r.ours),
            r.difference() * 100.0,
            claim,
            r.reason
        );
    }
    s
}

fn format_ours(x: f64) -> String {
    if x.abs() >= 100.0 {
        format!("{x:.1}")
    } else {
        format!("{x:.4}")
    }
}

/// A scene of the repository's scenes/ folder, with our FMUs in place.
pub fn open_scene(name: &str) -> anyhow::Result<Scene> {
    let scene = Scene::open(&crate::pack::workspace_root()?.join("scenes").join(name))?;
    super::run::provide_own_fmus(&scene, false)?;
    Ok(scene)
}

pub fn run(args: &ReproduceArgs) -> anyhow::Result<()> {
    let rows = rows(&open_scene)?;
    let text = table(&rows);
    print!("{text}");
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).with_context(|| parent.display().to_string())?;
    }
    std::fs::write(&args.out, &text).with_context(|| args.out.display().to_string())?;
    let claimed = rows.iter().filter(|r| r.claimed.is_some()).count();
    let held = rows.iter().filter(|r| r.reproduced()).count();
    println!(
        "\n{held} of {claimed} claimed rows reproduced, {} shown; table written to {}",
        rows.len(),
        args.out.display()
    );
    Ok(())
}
