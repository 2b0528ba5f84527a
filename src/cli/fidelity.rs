//! `windrive fidelity SCENE`: the fidelity ladder of a scene's drivetrain model (torsional 2-mass,
//! 5-mass, full; gearbox6dof with few and many slices, linear and lamina bearings), each level's CPU
//! time and error on the scene's quantities of interest against the top of the ladder, and the
//! cheapest level within every tolerance; beside it the modal reasoning: which of the full model's
//! modes lie inside the band the scene's inputs excite, and how well each reduced model keeps them.
//! The study is [`crate::studies::fidelity`].

use crate::cosim::Scene;
use crate::studies::fidelity::{Modal, SAME_COST, ladder, measure_ladder, recommended};
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
    let qs = &study.quantities;
    let recommended = recommended(&study, &measured).map(|i| levels[i].name.clone());
    // modal reasoning, for the torsional ladder
    let modal = Modal::of(&study)?;
    if args.json {
        let levels_json: Vec<serde_json::Value> = levels
            .iter()
            .zip(&measured)
            .map(|(l, m)| {
                serde_json::json!({
                    "name": l.name,
                    "cpu_s": m.cpu_s,
                    "error": m.worst(),
                    "error_in_tolerances": m.worst_in_tolerances(qs),
                    "within_tolerance": m.within(qs),
                    "errors": qs.iter().zip(&m.errors).map(|(q, e)| serde_json::json!({"quantity": q.name, "error": e, "tolerance": q.tolerance})).collect::<Vec<_>>(),
                })
            })
            .collect();
        let mut out = serde_json::json!({ "recommended": recommended, "levels": levels_json, "reference_step_s": study.reference.step });
        if let Some(modal) = &modal {
            out["excitation_band_hz"] = serde_json::json!(modal.band_hz);
            out["excitation_inputs"] = serde_json::json!(modal.inputs);
            out["preset"] = serde_json::json!(modal.preset);
            out["modes_hz"] = serde_json::json!(
                modal
                    .modes
                    .iter()
                    .map(|(n, f)| (n.to_string(), f.clone()))
                    .collect::<std::collections::BTreeMap<_, _>>()
            );
        }
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    print!("{}", study.describe_reference());
    println!(
        "\n{:<40} {:>9} {:>14} {:>12}  worst quantity",
        "level", "CPU [s]", "max rel err", "within tol"
    );
    for (l, m) in levels.iter().zip(&measured) {
        let worst = m
            .errors
            .iter()
            .zip(qs)
            .max_by(|a, b| (a.0 / a.1.tolerance).total_cmp(&(b.0 / b.1.tolerance)))
            .map(|(e, q)| format!("{} ({:.2} % of {:.1} %)", q.name, e * 100.0, q.tolerance * 100.0))
            .unwrap_or_default();
        println!(
            "{:<40} {:>9.3} {:>14.3e} {:>12}  {worst}",
            l.name,
            m.cpu_s,
            m.worst(),
            if m.within(qs) { "yes" } else { "no" }
        );
    }
    match &recommended {
        Some(r) => println!(
            "\nrecommended: {r} (the cheapest level with every quantity within its tolerance; levels within {:.0} % of its CPU time count as as cheap, the most accurate of them wins)",
            SAME_COST * 100.0
        ),
        None => println!(
            "\nno level is within every tolerance at the scene's macro step: refine the step or widen the tolerances"
        ),
    }
    if let Some(modal) = &modal {
        let band = modal.band_hz;
        println!(
            "\nexcitation: 99 % of the spectral energy of {} lies below {band:.2} Hz",
            modal.inputs.join(" and ")
        );
        println!(
            "free-free modes of drivetrain {} [Hz] (rigid mode left out):",
            modal.preset
        );
        let full = modal.full();
        for (name, f) in &modal.modes {
            let shown: Vec<String> = f.iter().take(6).map(|x| format!("{x:.2}")).collect();
            println!(
                "  {name:<16} {}{}   ({} inside the band)",
                shown.join(", "),
                if f.len() > 6 { ", ..." } else { "" },
                modal.inside(f)
            );
        }
        let inside_full = modal.inside(full);
        if inside_full == 0 {
            println!(
                "  no elastic mode lies inside the band: the drivetrain follows these inputs quasi-statically, and every level \
                 keeps the first mode ({:.2} Hz in the full model) within {:.1} %",
                full[0],
                modal.first_mode_spread() * 100.0
            );
        }
        for (name, f) in &modal.modes[..modal.modes.len() - 1] {
            let kept = f.len().min(inside_full);
            if inside_full > 0 && kept == inside_full {
                println!(
                    "  {name}: keeps every full-model mode inside the band ({inside_full}) within {:.1} %; condenses the {} above it",
                    modal.kept_error(f, kept) * 100.0,
                    full.len() - inside_full
                );
            } else if inside_full > 0 {
                println!(
                    "  {name}: has {} elastic modes, the band holds {inside_full} of the full model's: it cannot follow the rest",
                    f.len()
                );
            }
        }
        println!(
            "  what modes cannot tell: the transients (brake engagement, lock, mesh reversal) ring modes far above the band, \
             and a lumped model's HSS torque is its one shaft's torque over the gear ratio, carrying the gear stages' inertia \
             that the real HSS does not: the errors above say whether that matters for the scene's quantities"
        );
    }
    Ok(())
}
