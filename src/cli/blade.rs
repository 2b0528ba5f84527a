//! `windrive blade import`: an AeroDyn v15 blade and its airfoil files written as a blade folder of
//! the rotor FMU (`blade.csv` and one polar CSV per airfoil).

use crate::physics::blade::Blade;
use crate::physics::blade::aerodyn::{AirfoilSource, import_files, read_elastodyn};
use anyhow::{Context, bail};
use serde_json::json;
use std::path::PathBuf;

#[derive(clap::Subcommand)]
pub enum BladeCommand {
    /// An AeroDyn v15 blade file and its airfoil files as a blade folder (blade.csv and one polar CSV
    /// per airfoil), for `windrive aero --blade DIR` and the rotor FMU's `blade` parameter.
    ///
    /// Spans, chords, twists and the polars' angle of attack, C_l and C_d are copied unchanged; the tip
    /// radius is written as hub radius + last BlSpn. Left out, and listed: precurve and sweep (BlCrvAC,
    /// BlSwpAC, BlCrvAng: the BEM's blade is straight), the unsteady-aerodynamics constants, C_m and
    /// any table after the first. BlAFID k is the k-th file of the AeroDyn primary file's AFNames
    /// (--aerodyn) or of --airfoils.
    ///
    /// Examples (the OpenFAST NREL 5 MW files under tests/data/nrel-5mw-aerodyn/):
    ///   windrive blade import 5MW_Baseline/NRELOffshrBsline5MW_AeroDyn_blade.dat --aerodyn onshore/AeroDyn.dat --hub-radius 1.5 --out nrel-5mw
    ///   windrive blade import blade.dat --polars Airfoils --airfoils Cylinder1.dat,Cylinder2.dat,DU40_A17.dat --hub-radius 1.5 --out b
    ///   windrive blade import blade.dat --aerodyn AeroDyn.dat --elastodyn ElastoDyn.dat --out b
    #[command(verbatim_doc_comment)]
    Import(ImportArgs),
}

#[derive(clap::Args)]
pub struct ImportArgs {
    /// The AeroDyn v15 blade file (BlSpn, BlCrvAC, BlSwpAC, BlCrvAng, BlTwist, BlChord, BlAFID)
    pub blade_file: PathBuf,
    /// AeroDyn's primary input file: its AFNames number the airfoils, its InCol_Alfa, InCol_Cl and
    /// InCol_Cd say which table columns to read
    #[arg(long, conflicts_with = "airfoils")]
    pub aerodyn: Option<PathBuf>,
    /// The airfoil files in BlAFID order (1, 2, ...), comma-separated; columns 1, 2, 3 are alpha, Cl, Cd
    #[arg(long, value_delimiter = ',')]
    pub airfoils: Vec<PathBuf>,
    /// The folder that holds the airfoil files: --airfoils are relative to it, and --aerodyn's AFNames
    /// are looked up in it by file name instead of at their paths
    #[arg(long)]
    pub polars: Option<PathBuf>,
    /// Hub radius [m] (AeroDyn's blade file has none: ElastoDyn's HubRad)
    #[arg(long)]
    pub hub_radius: Option<f64>,
    /// Number of blades (default: ElastoDyn's NumBl with --elastodyn, else 3)
    #[arg(long)]
    pub blades: Option<u32>,
    /// ElastoDyn's primary input file, for HubRad and NumBl (--hub-radius and --blades win)
    #[arg(long)]
    pub elastodyn: Option<PathBuf>,
    /// The blade folder to write
    #[arg(long)]
    pub out: PathBuf,
    /// Write into --out even if it already holds a blade.csv
    #[arg(long)]
    pub force: bool,
    /// Print the summary as JSON
    #[arg(long)]
    pub json: bool,
}

pub fn run(command: &BladeCommand) -> anyhow::Result<()> {
    match command {
        BladeCommand::Import(args) => import(args),
    }
}

fn import(args: &ImportArgs) -> anyhow::Result<()> {
    if args.aerodyn.is_none() && args.airfoils.is_empty() {
        bail!(
            "BlAFID numbers the airfoils by their place in AeroDyn's primary file: give --aerodyn AeroDyn.dat (its \
             AFNames) or --airfoils A.dat,B.dat,... in that order"
        );
    }
    if args.out.join("blade.csv").exists() && !args.force {
        bail!(
            "{} already holds a blade.csv: give --force to replace it, or another --out",
            args.out.display()
        );
    }
    let rotor = args.elastodyn.as_deref().map(read_elastodyn).transpose()?;
    let hub_radius = match (args.hub_radius, rotor) {
        (Some(r), _) => r,
        (None, Some(e)) => e.hub_radius_m,
        (None, None) => bail!(
            "no hub radius: AeroDyn's blade file does not hold it; give --hub-radius (ElastoDyn's HubRad) or --elastodyn"
        ),
    };
    let blades = args.blades.or(rotor.map(|e| e.blades)).unwrap_or(3);
    let airfoils = match &args.aerodyn {
        Some(p) => AirfoilSource::Primary(p.clone()),
        None => AirfoilSource::Files(match &args.polars {
            Some(dir) => args.airfoils.iter().map(|f| dir.join(f)).collect(),
            None => args.airfoils.clone(),
        }),
    };
    // --airfoils already carry the folder; --polars then only redirects a primary file's AFNames
    let polars = args.aerodyn.as_ref().and(args.polars.as_deref());
    let imported = import_files(&args.blade_file, &airfoils, polars, hub_radius, blades)?;
    let written = imported.folder.write(&args.out)?;
    // the folder must read back as the rotor reads it
    let blade = Blade::load(&args.out).with_context(|| format!("reading back {}", args.out.display()))?;
    let folder = &imported.folder;
    if args.json {
        let out = json!({
            "out": args.out.display().to_string(),
            "files": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
            "nodes": folder.nodes.len(),
            "hub_radius_m": folder.hub_radius_m,
            "tip_radius_m": blade.tip_radius(),
            "blades": folder.blades,
            "airfoils": folder.polars.iter().map(|p| json!({"name": p.name, "rows": p.alpha_deg.len()})).collect::<Vec<_>>(),
            "notes": imported.notes,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "{}: {} nodes, hub radius {} m, tip radius {} m, {} blades; airfoils {}",
            args.out.display(),
            folder.nodes.len(),
            folder.hub_radius_m,
            blade.tip_radius(),
            folder.blades,
            folder
                .polars
                .iter()
                .map(|p| format!("{} ({} rows)", p.name, p.alpha_deg.len()))
                .collect::<Vec<_>>()
                .join(", ")
        );
        for n in &imported.notes {
            println!("  {n}");
        }
    }
    Ok(())
}
