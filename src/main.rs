use clap::Parser;
use windrive::cli::{Cli, Command};

/// Errors reach the user as their message and causes, one per line: never a stack backtrace, even
/// with `RUST_BACKTRACE` set (anyhow's `Debug` form, which `fn main() -> Result` prints, appends one).
fn main() -> std::process::ExitCode {
    quiet_on_closed_pipe();
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", windrive::cli::error_chain(&e));
            std::process::ExitCode::FAILURE
        }
    }
}

/// `windrive gearbox | head` ends quietly as Unix tools do: Rust ignores SIGPIPE, so a closed pipe
/// would make `println!` panic with a backtrace; the default action ends the process instead.
fn quiet_on_closed_pipe() {
    #[cfg(target_os = "linux")]
    {
        unsafe extern "C" {
            fn signal(signum: i32, handler: usize) -> usize;
        }
        const SIGPIPE: i32 = 13;
        const SIG_DFL: usize = 0;
        // SAFETY: resetting a signal to its default action at start-up, before any thread exists.
        unsafe {
            signal(SIGPIPE, SIG_DFL);
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Pack { names } => {
            let root = windrive::pack::workspace_root()?;
            let names = if names.is_empty() {
                windrive::pack::fmu_names(&root)
            } else {
                names
            };
            for name in names {
                let path = windrive::pack::pack(&root, &name)?;
                println!("packed {}", path.display());
            }
            Ok(())
        }
        Command::Modes(args) => windrive::cli::modes::run(&args),
        Command::Gearbox(args) => windrive::cli::gearbox::run(&args),
        Command::StepResponse(args) => windrive::cli::step::run(&args),
        Command::Bench(args) => windrive::cli::bench::run(&args),
        Command::Rainflow(args) => windrive::cli::fatigue::run_rainflow(&args),
        Command::Life(args) => windrive::cli::life::run(&args),
        Command::Climate(args) => windrive::cli::climate::run(&args),
        Command::Gears(args) => windrive::cli::gears::run(&args),
        Command::Bearings(args) => windrive::cli::bearings::run(&args),
        Command::Bode(args) => windrive::cli::bode::run(&args),
        Command::Campbell(args) => windrive::cli::campbell::run(&args),
        Command::Spectrum(args) => windrive::cli::fatigue::run_spectrum(&args),
        Command::Ldd(args) => windrive::cli::fatigue::run_ldd(&args),
        Command::Del(args) => windrive::cli::fatigue::run_del(&args),
        Command::Run(args) => windrive::cli::run::run(&args),
        Command::PackScene(args) => windrive::cli::run::pack_scene(&args),
        Command::Shutdown(args) => windrive::cli::shutdown::run(&args),
        Command::Calibrate(args) => windrive::cli::calibrate::run(&args),
        Command::Reproduce(args) => windrive::cli::reproduce::run(&args),
        Command::Chart(windrive::cli::ChartCommand::WorkPrecision(args)) => windrive::cli::work_precision::run(&args),
        Command::Fidelity(args) => windrive::cli::fidelity::run(&args),
        Command::Chart(windrive::cli::ChartCommand::Stability(args)) => windrive::cli::stability::run(&args),
        Command::Chart(windrive::cli::ChartCommand::Integrators(args)) => windrive::cli::integrators::run(&args),
        Command::Chart(windrive::cli::ChartCommand::NonSmooth(args)) => windrive::cli::nonsmooth::run(&args),
        Command::Aero(args) => windrive::cli::aero::run(&args),
        Command::Wind(args) => windrive::cli::wind::run(&args),
        Command::Blade(command) => windrive::cli::blade::run(&command),
        Command::FmuHost(args) => windrive::cli::fmu_host(&args),
    }
}
