//! `windrive reproduce`: every number of the thesis this project computes, beside ours, as a Markdown
//! table (docs/REPRODUCTION.md): the thesis value with where it stands, ours, the difference, whether
//! we claim to reproduce it (and to what tolerance), and a one-line reason where they differ. The
//! study, and the thesis's values as data, are [`crate::studies::reproduce`].

use crate::cosim::Scene;
use crate::studies::reproduce::{markdown, rows};
use anyhow::Context;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ReproduceArgs {
    /// Markdown table to write
    #[arg(long, default_value = "results/reproduction.md")]
    pub out: PathBuf,
}

/// A scene of the repository's scenes/ folder, with our FMUs in place.
pub fn open_scene(name: &str) -> anyhow::Result<Scene> {
    let scene = Scene::open(&crate::pack::workspace_root()?.join("scenes").join(name))?;
    super::run::provide_own_fmus(&scene, false)?;
    Ok(scene)
}

pub fn run(args: &ReproduceArgs) -> anyhow::Result<()> {
    let rows = rows(&open_scene)?;
    let text = markdown(&rows);
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
