//! The `windrive` command line.

pub mod aero;
pub mod bearings;
pub mod bench;
pub mod blade;
pub mod bode;
pub mod calibrate;
pub mod campbell;
pub mod climate;
pub mod fatigue;
pub mod fidelity;
pub mod gearbox;
pub mod gears;
pub mod integrators;
pub mod life;
pub mod modes;
pub mod nonsmooth;
pub mod rating;
pub mod reproduce;
pub mod run;
pub mod shutdown;
pub mod stability;
pub mod step;
pub mod study;
pub mod wind;
pub mod work_precision;

use clap::{Parser, Subcommand};

/// An error and its causes on one line, "outer: inner: ...", without a backtrace.
pub fn error_chain(e: &anyhow::Error) -> String {
    format!("{e:#}")
}

#[derive(Parser)]
#[command(
    name = "windrive",
    version,
    about = "Wind-turbine drivetrain FMUs (FMI 2.0 Co-Simulation), their master and analysis",
    long_about = "Wind-turbine drivetrain FMUs (FMI 2.0 Co-Simulation), their master and analysis.\n\n\
        The main job: drivetrain C's normal operation and shutdown through the master, with CSVs, plots\n\
        and the torque-ratio summary under results/c-shutdown/:\n  \
        windrive shutdown --preset C\n  \
        windrive shutdown --preset D --spring               the same on the thesis's electrical spring, analytic C_p\n\n\
        Typical session:\n  \
        windrive pack                                       build and pack every FMU into target/fmu/\n  \
        windrive modes --preset D --fidelity 2 --generator connected\n  \
        windrive modes --gearbox grc750                     the 6-DOF gearbox's modes, classified\n  \
        windrive gearbox                                    the GRC at rated torque: bearing and gear stresses\n  \
        windrive run scenes/d-shutdown-6dof                 drivetrain D's shutdown with the 6-DOF gearbox\n  \
        windrive step-response --preset D                   rated-torque step through the FMU, modes beside it\n  \
        windrive bench torsional                            speed and accuracy of the FMU, with baselines\n  \
        windrive run scenes/d-grid-step --algorithm jacobi  a scene through the co-simulation master\n  \
        windrive run scenes/c-shutdown --isolate            each FMU in its own process (survives a crashing FMU)\n  \
        windrive aero --preset C --tsr 4,6,8 --pitch 0,10   the rotor's BEM: C_P, C_Q, C_T as JSON\n  \
        windrive reproduce                                  the thesis's numbers beside ours, row by row\n  \
        windrive calibrate --no-fit                         C's scenes against the thesis's measured statistics\n  \
        windrive chart work-precision scenes/c-shutdown --vary algorithm   error against CPU time, every algorithm\n  \
        windrive fidelity scenes/c-normal                   the cheapest drivetrain model within the scene's tolerances"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Build FMU crates (release) and write target/fmu/<name>.fmu; all FMUs when no name is given.
    Pack {
        /// FMU names (folders under fmus/), e.g. torsional
        names: Vec<String>,
    },
    /// Natural frequencies and mode shapes of a drivetrain preset.
    ///
    /// Solves K x = ω² M x by Cholesky reduction. --generator connected adds the thesis's electrical
    /// spring K_gen from the generator to ground (fixed-speed generator, free–fixed); disconnected
    /// leaves the drivetrain free–free with a zero mode (variable speed or tripped); locked holds the
    /// HSS at standstill (brake engaged).
    Modes(modes::ModesArgs),
    /// A 6-DOF gearbox at a steady operating point: every bearing's loads, rollers in contact, race
    /// pressures and subsurface shear; every mesh's slice loads, K_Hβ and contact stress; each roller
    /// set's radial stiffness there beside its description's linear value.
    ///
    /// Examples:
    ///   windrive gearbox                                   the GRC 750 kW at rated torque, gravity, lamina bearings
    ///   windrive gearbox --bearings linear --json          the same with the 6×6 linear bearings, as JSON
    ///   windrive gearbox --torque-ratio 1.3 --tilt-moment 2e5 --thrust 1e5   a shutdown's peak with the rotor's loads
    ///   windrive gearbox --revolution --rotor-mass 1       one carrier revolution without the rotor's weight (a dynamometer)
    ///   windrive gearbox --dynamic-factor --bearings linear   every mesh's K_v, the model's beside ISO 6336-1 method B
    #[command(verbatim_doc_comment)]
    Gearbox(gearbox::GearboxArgs),
    /// Rated-torque step on a drivetrain through its torsional FMU; prints peak torques, the dominant
    /// HSS-torque frequency and the modes, and writes a CSV.
    StepResponse(step::StepArgs),
    /// Benchmarks an FMU through the FMI boundary against named baselines in the same run.
    Bench(bench::BenchArgs),
    /// Rainflow cycles (ASTM E1049-85) of one CSV channel, as a list or a range–mean / from–to matrix.
    Rainflow(fatigue::RainflowArgs),
    /// Load duration distribution of one CSV channel: seconds and revolutions per load bin
    /// (revolutions from a speed channel in rad/s: n_i = Σ t_j ω_j / 2π).
    Ldd(fatigue::LddArgs),
    /// Amplitude spectrum of one CSV channel (detrended, Hann window, real FFT) and its largest peaks.
    Spectrum(fatigue::SpectrumArgs),
    /// Campbell diagram of a preset: natural frequencies against rotor speed with 1P, 3P and every
    /// stage's gear-mesh orders (physical z_ring·f_carrier beside the thesis's convention), and the
    /// crossings inside the operating speed range.
    Campbell(campbell::CampbellArgs),
    /// Frequency response (Bode) of the linear drivetrain: rotor or generator torque in, a speed or
    /// the LSS/HSS torque out, with the natural frequencies marked.
    Bode(bode::BodeArgs),
    /// Lifetime fatigue of a channel from a normal-operation and a shutdown series: operating hours
    /// from the wind climate, shutdowns per year, lifetime DELs with the shutdowns' share, and with
    /// --gear the ISO 6336 flank and root stresses, allowables and Miner damage.
    Life(Box<life::LifeArgs>),
    /// The DLC 1.2 wind bins of a wind climate (Weibull or Rayleigh): each bin's speed, extent,
    /// probability, hours in the design life and IEC normal-turbulence intensity.
    Climate(climate::ClimateArgs),
    /// Every gear tooth of a gearbox rated from one series, as the paper does it (its §1.3; docs/SOURCES.md §Paper).
    ///
    /// Per tooth: ISO 6336-2 contact and ISO 6336-3 root stress from the mesh force (nominal, no load
    /// factors, as the paper's Eqs. 2–3; with --face-load model each sample's K_Hβ from gearbox6dof's
    /// sliced meshes), load cycles from the speeds (its Eq. 1), a two-slope S-N curve
    /// per material (ISO 6336-5 MQ; second slope 2m − 1), Miner's sum in the window and per day (the
    /// window's damage repeated over 86 400 s). Sun and ring teeth see every planet; planets bend both
    /// ways (Y_M = 0.7) and have a flank against the sun (ps) and one against the ring (pr).
    ///
    /// Examples (p.csv from `windrive run scenes/p-normal --out p.csv`, g.csv from
    /// `windrive run scenes/p-normal-6dof --param gearbox.slices=5 --out g.csv`):
    ///   windrive gears p.csv --transient 20
    ///   windrive gears p.csv --transient 20 --json
    ///   windrive gears g.csv --fmu gearbox6dof --transient 20
    ///   windrive gears g.csv --fmu gearbox6dof --face-load model --transient 20
    ///   windrive gears --channels
    #[command(verbatim_doc_comment)]
    Gears(gears::GearsArgs),
    /// Every rolling bearing of a gearbox rated from one series of the gearbox6dof FMU, ISO 281's way.
    ///
    /// Per bearing with a roller set in the gearbox description: the basic dynamic load rating
    /// C_r = b_m·f_c·(i·L_we·cos α)^(7/9)·Z^(3/4)·D_we^(29/27), the dynamic equivalent load P = X·F_r + Y·F_a
    /// of every sample, the revolutions of its rings against each other (a planet bearing's are the
    /// planet's against its carrier) from the rotor speed and the gearbox's kinematics, and Miner's sum
    /// of revolutions over L10 = (C/P)^(10/3) million revolutions: in the window, per day, and as the
    /// window's L10 life in hours. Beside it, for comparison only, the thesis's count (ch. 5.4): rainflow
    /// cycles of P as load cycles over the same law (thesis/day), which makes a shutdown's few large
    /// swings count far more than hours of turning. Refuses a series whose generator-to-rotor speed ratio
    /// is not the gearbox's.
    ///
    /// Examples (d.csv from `windrive run scenes/d-shutdown-6dof --out d.csv`):
    ///   windrive bearings d.csv --transient 2
    ///   windrive bearings d.csv --json
    ///   windrive bearings --channels --gearbox grc750
    #[command(verbatim_doc_comment)]
    Bearings(bearings::BearingsArgs),
    /// Runs an SSP scene (folder, .ssd or .ssp) through the co-simulation master and writes a CSV.
    ///
    /// Loads every component's FMU (ours or another tool's), checks the system (names, types,
    /// unconnected inputs, algebraic loops), applies parameter bindings, propagates initial values,
    /// then steps with the chosen algorithm. If an FMU fails, every row up to the last good step is
    /// kept and the FMU, time and status are named.
    Run(Box<run::RunArgs>),
    /// The thesis's normal operation and shutdown of drivetrain A, B, C or D through the master: CSVs,
    /// plots (shaft torques, speeds, mesh forces, HSS spectrum with the modes, rainflow cloud) and
    /// the summary (torque ratios against the 1.35 design factor, ranges, braking frequencies). C and D
    /// run on the generators the thesis simulated (C a DFIG at 1680 rpm, D its cage machine at 1809 rpm)
    /// with the blade-element rotor; `--spring` runs the spring scenes instead.
    ///
    /// Examples:
    ///   windrive shutdown --preset C                       results/c-shutdown/: CSVs, plots, summary.txt
    ///   windrive shutdown --preset D --spring              D on the thesis's electrical spring K_gen
    ///   windrive shutdown --preset C --aerodynamics analytic --out-dir /tmp/c-analytic
    #[command(verbatim_doc_comment)]
    Shutdown(shutdown::ShutdownArgs),
    /// Fits the inputs of drivetrain C's scenes that no source gives (turbulence intensity, brake torque
    /// and ramp, pitch rate towards feather, trip delay) to the statistics the thesis measured on the
    /// field turbine (shaft-torque and sun–planet force ranges in normal operation and shutdown, the DEL
    /// ratio, the peak torque ratio, the mean torque after braking) by Nelder–Mead, each evaluation
    /// both scenes through the master; prints and writes target, achieved and misfit per statistic.
    ///
    /// Examples:
    ///   windrive calibrate --no-fit                      the scenes as they are against the thesis (2 s)
    ///   windrive calibrate                               the fit (about 3 min), table in results/calibration-c.md
    ///   windrive calibrate --apply --out docs/calibration-c.md   fit, write the values into the scenes and the docs table
    #[command(verbatim_doc_comment)]
    Calibrate(calibrate::CalibrateArgs),
    /// Every number of the thesis this project computes beside ours, as a Markdown table: modes, gear
    /// ratios, mesh orders, operating hours, rated speeds, and the shutdown scenes' frequencies, peaks
    /// and speeds; where we claim to reproduce a number, within what; where not, why.
    ///
    /// Examples:
    ///   windrive reproduce                                 table in results/reproduction.md (about 5 s)
    ///   windrive reproduce --out docs/REPRODUCTION.md      the documentation's copy
    #[command(verbatim_doc_comment)]
    Reproduce(reproduce::ReproduceArgs),
    /// Charts that answer "which method, step and model for my scene?": work-precision (error of the
    /// scene's quantities of interest against its reference, against CPU time), stability maps of the
    /// coupling and of the integrators, chatter at the brake and the backlash.
    #[command(subcommand)]
    Chart(ChartCommand),
    /// The fidelity a scene needs: runs its drivetrain model's ladder (torsional 2-mass, 5-mass, full;
    /// gearbox6dof with 5 and 35 slices, linear and lamina bearings), prints each level's CPU time and
    /// error on the scene's quantities of interest against the top level, recommends the cheapest
    /// within every tolerance, and shows which modes the scene's inputs excite.
    Fidelity(fidelity::FidelityArgs),
    /// The rotor FMU's blade-element momentum model: C_P, C_Q, C_T, torque and thrust as JSON over
    /// tip-speed ratios and pitch angles, optionally per element; with --preset (or --rated-power and
    /// --rated-rpm) also the rated wind speed the scaled blade is fitted to.
    ///
    /// Examples:
    ///   windrive aero --tsr 4,7,10 --pitch 0,5            the WindPACT 1.5 MW blade as stored (R = 35 m)
    ///   windrive aero --preset C --tsr 0 --pitch 90 --wind 16 --elements   drivetrain C's parked, feathered rotor
    ///   windrive aero --radius 35 --rated-power 1.5e6 --rated-rpm 17.5    the paper's 1.5 MW rotor's rated wind
    #[command(verbatim_doc_comment)]
    Aero(aero::AeroArgs),
    /// IEC 61400-1 ed. 3 full-field turbulence (TurbSim's IEC Kaimal model: u, v, w on a rotor-plane grid,
    /// exponential coherence of u, power-law shear, Veers' method) written as a TurbSim .bts file that
    /// OpenFAST's InflowWind reads; or a .bts file read and written again.
    ///
    /// Examples:
    ///   windrive wind --out turb.bts                             15×15 over 150 m, 90 m hub, 11.4 m/s, class A, 600 s
    ///   windrive wind --out turb.bts --wind 16 --class B --seed 3 --grid 21x15 --width 160 --height 120
    ///   windrive wind --from turbsim.bts --out copy.bts --json   our reader and writer on a TurbSim file
    #[command(verbatim_doc_comment)]
    Wind(wind::WindArgs),
    /// Blade data of the rotor's blade-element momentum model: importing an OpenFAST AeroDyn blade.
    #[command(subcommand)]
    Blade(blade::BladeCommand),
    /// Packs a scene folder into an .ssp archive, with our FMUs freshly built into its resources/.
    PackScene(run::PackSceneArgs),
    /// Damage-equivalent loads of one CSV channel: DEL = (Σ n_i S_i^m / N_eq)^(1/m), N_eq = feq × duration,
    /// optionally with MLife's Goodman mean-load correction.
    Del(fatigue::DelArgs),
    /// Hosts one FMU instance for a master run with --isolate (started by the master, not by hand).
    #[command(hide = true)]
    FmuHost(FmuHostArgs),
}

#[derive(Subcommand)]
pub enum ChartCommand {
    /// Error against CPU time over a grid of runs of a scene (algorithms, macro steps, extrapolation
    /// orders, integrators, internal steps, fidelities or slices), one line per method, the Pareto
    /// front marked; PNG, SVG and the table as CSV. The error of a run is the largest relative error of
    /// the scene's quantities of interest (quantities.toml beside it) against the scene's reference:
    /// its coupled equations converged at every 0.25 ms step.
    WorkPrecision(Box<work_precision::WorkPrecisionArgs>),
    /// Where each co-simulation algorithm holds on a stiff split (drivetrain D's 2-mass model | its
    /// generator's electrical spring): macro step × coupling stiffness, every algorithm and
    /// extrapolation order, runs against the theory's boundary (spectral radius of the macro-step map).
    Stability(stability::StabilityArgs),
    /// Where the torsional model's integrators are stable as the internal step crosses RK4's limit and
    /// the mesh stiffness moves it, runs against the limit 2.785/ω_max, and how much HHT-α damps the top
    /// modes there.
    Integrators(integrators::IntegratorsArgs),
    /// Chatter or its absence at the non-smooth places of a shutdown: the HSS brake holding at standstill
    /// and the meshes' backlash under torque reversal, counted at the communication points for each
    /// algorithm and macro step against the scene's reference.
    NonSmooth(nonsmooth::NonSmoothArgs),
}

#[derive(clap::Args)]
pub struct FmuHostArgs {
    /// The mailbox's memfd, inherited from the master
    #[arg(long)]
    pub fd: i32,
    /// The unpacked FMU
    #[arg(long)]
    pub dir: std::path::PathBuf,
    /// Instance name
    #[arg(long)]
    pub name: String,
    /// The master's process id (the host ends when it is gone)
    #[arg(long)]
    pub master: u32,
    #[arg(long)]
    pub logging: bool,
}

/// `windrive fmu-host`: serves until the master says quit or is gone.
pub fn fmu_host(args: &FmuHostArgs) -> anyhow::Result<()> {
    crate::fmi2::host::serve::serve(args.fd, &args.dir, &args.name, args.logging, args.master)
        .map_err(|e| anyhow::anyhow!("fmu-host {}: {e}", args.name))
}
