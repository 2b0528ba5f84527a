//! `windrive fidelity SCENE`: the fidelity ladder of a scene's drivetrain model (torsional 2-mass,
//! 5-mass, full; gearbox6dof with few and many slices, linear and lamina bearings), each level's CPU
//! time and error on the scene's quantities of interest against the top of the ladder, and the
//! cheapest level within every tolerance; beside it the modal reasoning: which of the full model's
//! modes lie inside the band the scene's inputs excite, and how well each reduced model keeps them.
//! The study is [`crate::studies::fidelity`].

use crate::cosim::Scene;
use crate::studies::fidelity::{Modal, ladder, measure_ladder, recommended, table, to_json};
use anyhow::bail;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive fidelity scenes/c-normal                  normal operation: is a 2-mass model enough? (about 20 s)\n  \
    windrive fidelity scenes/c-shutdown --json         the same for the shutdown, as JSON for scripts\n  \
    windrive fidelity scenes/c-shutdown-spring --repeat 1 --stop-time 10\n\n\
    The levels run at the scene's own macro step and algorithm; the reference is the top level with its coupled\n\
    equations converged every --reference-step. Quantities and tolerances: quantities.toml beside the scene.")]
pub struct FidelityArgs {
    /// Scene: a folder with SystemStructure.ssd, a .ssd file or a .ssp archive
    pub scene: PathBuf,
    /// Print {"recommended": NAME, "levels": [{"name", "cpu_s", "error", "within_tolerance"}, ...], ...}
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub study: super::study::StudyArgs,
}

pub fn run(args: &FidelityArgs) -> anyhow::Result<()> {
    if args.study.repeat == 0 {
        bail!("--repeat 0: at least one run per level");
    }
    let scene = Scene::open(&args.scene)?;
    let (levels, top) = ladder(&scene)?;
    let study = args.study.open(scene, top)?;
    let measured = measure_ladder(&study, &levels, args.study.repeat, |k, level| {
        eprintln!("level {}/{}: {} ...", k + 1, levels.len(), level.name)
    })?;
    let recommended = recommended(&study, &measured).map(|i| levels[i].name.clone());
    // modal reasoning, for the torsional ladder
    let modal = Modal::of(&study)?;
    if args.json {
        let out = to_json(&study, &levels, &measured, recommended.as_deref(), modal.as_ref());
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    print!("{}", study.describe_reference());
    print!("{}", table(&study, &levels, &measured, recommended.as_deref()));
    if let Some(modal) = &modal {
        print!("{modal}");
    }
    Ok(())
}
