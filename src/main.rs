use clap::Parser;
use windrive::cli::{Cli, Command};

/// Errors reach the user as their message and causes, one per line: never a stack backtrace, even
/// with `RUST_BACKTRACE` set (anyhow's `Debug` form, which `fn main() -> Result` prints, appends one).
fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", windrive::cli::error_chain(&e));
            std::process::ExitCode::FAILURE
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
        Command::Bode(args) => windrive::cli::bode::run(&args),
        Command::Campbell(args) => windrive::cli::campbell::run(&args),
        Command::Spectrum(args) => windrive::cli::fatigue::run_spectrum(&args),
        Command::Ldd(args) => windrive::cli::fatigue::run_ldd(&args),
        Command::Del(args) => windrive::cli::fatigue::run_del(&args),
        Command::Run(args) => windrive::cli::run::run(&args),
        Command::PackScene(args) => windrive::cli::run::pack_scene(&args),
        Command::Shutdown(args) => windrive::cli::shutdown::run(&args),
        Command::Aero(args) => windrive::cli::aero::run(&args),
    }
}
