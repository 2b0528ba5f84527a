//! `windrive chart non-smooth`: chatter or its absence at the drivetrain's brake at standstill and
//! its meshes' backlash, printed as a table and drawn (the study: [`crate::studies::nonsmooth`]).

use crate::cosim::Scene;
use crate::reference::scene::DEFAULT_STEP;
use crate::studies::nonsmooth::{STEPS_MS, chart};
use anyhow::{Context, anyhow};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive chart non-smooth                                   c-shutdown, 100 µm backlash (about 1 min)\n  \
    windrive chart non-smooth --backlash 2e-4 --out /tmp/ns     a wider backlash")]
pub struct NonSmoothArgs {
    /// Shutdown scene with a `torsional` component whose brake locks
    #[arg(long, default_value = "scenes/c-shutdown")]
    pub scene: PathBuf,
    /// Total backlash of every mesh for the reversal study, m (an estimate: ISO 1328 flank play of
    /// modules 9-16 mm is 0.1-0.3 mm)
    #[arg(long, default_value_t = 1e-4)]
    pub backlash: f64,
    /// Output stem: STEM.png, STEM.svg (the backlash chart), STEM.csv
    #[arg(long, default_value = "results/non-smooth")]
    pub out: PathBuf,
}

pub fn run(args: &NonSmoothArgs) -> anyhow::Result<()> {
    if !(args.backlash > 0.0 && args.backlash < 0.01) {
        anyhow::bail!("--backlash {}: a total backlash in metres, e.g. 1e-4", args.backlash);
    }
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the output folder", dir.display()))?;
    }
    let scene = Scene::open(&args.scene)?;
    super::run::provide_own_fmus(&scene, false)?;
    let stop = scene
        .experiment
        .stop_time
        .ok_or_else(|| anyhow!("scene {}: no stop time", scene.name))?;
    let mut csv = String::from(
        "algorithm,step_s,brake_locked_changes,max_speed_locked,contact_changes,contact_changes_per_1000_points\n",
    );
    let mut brake_chatter = 0;
    let (reference, variations) = chart(
        &scene,
        stop,
        args.backlash,
        |reference| {
            println!(
                "{}: brake held after its first lock, and every mesh with {} µm backlash; reference (converged every {} ms):\n  \
                 brake_locked changes {}, largest generator speed while locked {:.2e} rad/s, sun-planet contact changes {} ({:.2} per 1000 points)\n",
                scene.name,
                args.backlash * 1e6,
                DEFAULT_STEP * 1e3,
                reference.brake_changes,
                reference.creep,
                reference.contact_changes,
                reference.contact_rate()
            );
            println!(
                "{:<26} {:>8} {:>16} {:>22} {:>18} {:>14}",
                "algorithm", "H [ms]", "brake changes", "speed locked [rad/s]", "contact changes", "per 1000 pts"
            );
        },
        |label, h_ms, m| {
            println!(
                "{label:<26} {h_ms:>8} {:>16} {:>22.2e} {:>18} {:>14.2}",
                m.brake_changes,
                m.creep,
                m.contact_changes,
                m.contact_rate()
            );
            brake_chatter += m.brake_changes;
        },
    )?;
    let mut contact_lines: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for v in &variations {
        for (h_ms, m) in &v.runs {
            writeln!(
                csv,
                // quoted: labels like "gs p0, internal 0.25 ms" hold a comma
                "\"{}\",{},{},{},{},{}",
                v.label,
                h_ms * 1e-3,
                m.brake_changes,
                m.creep,
                m.contact_changes,
                m.contact_rate()
            )?;
        }
        let line = v
            .runs
            .iter()
            .map(|(h_ms, m)| (h_ms.log10(), m.contact_rate().max(0.01).log10()));
        contact_lines.push((v.label.to_string(), line.collect()));
    }
    println!(
        "\nbrake at standstill: {}",
        if brake_chatter == 0 {
            "no chatter in any run (the implicit integrator holds the stick exactly, speed 0 while locked)".to_string()
        } else {
            format!("{brake_chatter} lock/release changes over all runs (see the table)")
        }
    );
    let reference_points = vec![
        (STEPS_MS[0].log10(), reference.contact_rate().max(0.01).log10()),
        (
            STEPS_MS[STEPS_MS.len() - 1].log10(),
            reference.contact_rate().max(0.01).log10(),
        ),
    ];
    contact_lines.push(("reference".into(), reference_points));
    let title = format!(
        "{}, {} µm backlash: sun-planet contact changes",
        scene.name,
        args.backlash * 1e6
    );
    crate::plot::write_chart_and_table(&args.out, &csv, |path| {
        crate::plot::named_lines(
            path,
            &title,
            "log10 macro step / ms",
            "log10 contact changes per 1000 communication points",
            &contact_lines,
            &[],
        )
    })
}
