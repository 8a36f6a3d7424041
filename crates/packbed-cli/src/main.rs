//! The `packbed` command: argument parsing and dispatch onto the `packbed` library.
//! Every user error ends here as one line `packbed: error: …` and exit code 2
//! (a failed Slurm job of `packbed slurm --wait`: exit code 1).

mod analyze;
mod bed_file;
mod bench;
mod compare;
mod ensemble;
mod fragment;
mod parsers;
mod progress;
mod render;
mod run;
mod slurm;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

/// The commented default configuration printed by `packbed example`.
const EXAMPLE_CONFIG: &str = include_str!("../../../examples/default.toml");

/// Exit code of every user error (bad arguments, config or input files).
const EXIT_USER_ERROR: u8 = 2;

/// packbed: exact sequential deposition of packed beds of spheres (3D) and discs (2D).
#[derive(Debug, Parser)]
#[command(name = "packbed", version, arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Build one bed, analyse it and write its files (default bed without arguments).
    Run(run::RunArgs),
    /// Analyse an existing bed file (packbed CSV, plain x y [z] r, LAMMPS dump, XYZ, VTU).
    // This comment is also the `--help` text, where `[z]` reads as optional; it is no link.
    #[allow(rustdoc::broken_intra_doc_links)]
    Analyze(analyze::AnalyzeArgs),
    /// Contact forces of a bed file under load, and the order its bonds break.
    Fragment(fragment::FragmentArgs),
    /// Draw a bed file as a picture (PNG, or SVG in 2D).
    Render(render::RenderArgs),
    /// Build and analyse N replicate beds in parallel, with statistics.
    Ensemble(ensemble::EnsembleArgs),
    /// Compare runs, ensembles or sweeps: shared measures side by side, with Welch's t-test.
    Compare(compare::CompareArgs),
    /// Join the outputs of ensemble shards into the result of a single run.
    Merge(ensemble::MergeArgs),
    /// Write (and submit) a Slurm job array of ensemble shards and their merge.
    Slurm(slurm::SlurmArgs),
    /// Measure deposition throughput on a bed of equal spheres (or discs).
    Bench(bench::BenchArgs),
    /// Print a commented configuration file (the default bed).
    Example,
}

/// The system's allocator, with huge pages where a stage asks for them.
#[global_allocator]
static ALLOCATOR: packbed::Allocator = packbed::Allocator;

fn main() -> ExitCode {
    install_panic_hook();
    install_signal_handler();
    // The matches too: `analyze` tells an option given from its default.
    let matches = match Cli::command().try_get_matches() {
        Ok(m) => m,
        Err(e) => return clap_exit(e),
    };
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => return clap_exit(e.format(&mut Cli::command())),
    };
    let result = match cli.command {
        Command::Run(args) => run::run(args),
        Command::Analyze(args) => analyze::analyze(args, matches.subcommand_matches("analyze")),
        Command::Fragment(args) => fragment::fragment(args),
        Command::Render(args) => render::render(args),
        Command::Ensemble(args) => ensemble::ensemble(args),
        Command::Compare(args) => compare::compare(args),
        Command::Merge(args) => ensemble::merge(args),
        Command::Slurm(args) => slurm::slurm(args),
        Command::Bench(args) => bench::bench(args),
        Command::Example => {
            print!("{EXAMPLE_CONFIG}");
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.downcast_ref::<packbed::slurm::JobsFailed>().is_some() => {
            // The input was fine, a job on the cluster failed: exit code 1.
            eprintln!("packbed: error: {}", packbed::text::screen(&e.to_string()));
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!(
                "packbed: error: {}",
                packbed::one_line_naming(e.as_ref(), &|s| format!("--{s}"))
            );
            ExitCode::from(EXIT_USER_ERROR)
        }
    }
}

/// Help and version go to stdout with success (help for a missing command:
/// to stderr, as an error); usage errors become one line.
fn clap_exit(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind::*;
    let code = ExitCode::from(EXIT_USER_ERROR);
    match e.kind() {
        DisplayHelp | DisplayVersion | DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            if e.use_stderr() {
                code
            } else {
                ExitCode::SUCCESS
            }
        }
        _ => {
            let line = packbed::usage_line(&e.render().to_string());
            eprintln!("packbed: error: {line}");
            code
        }
    }
}

/// On SIGINT (Ctrl-C) or SIGTERM, removes the temporary files being written
/// (they would otherwise pile up as hidden `.NAME.PID.tmp` files) and exits
/// with the shell's code for the signal, 130 or 143. SIGKILL cannot be
/// caught: the next run into the same directory removes what it left.
#[cfg(unix)]
fn install_signal_handler() {
    use signal_hook::consts::signal::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
        // Without the handler the signals keep their default action.
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            packbed::abandon_in_flight();
            let name = if signal == SIGINT {
                "SIGINT"
            } else {
                "SIGTERM"
            };
            eprintln!("packbed: stopped by {name}; its temporary files are removed");
            std::process::exit(128 + signal);
        }
    });
}

#[cfg(not(unix))]
fn install_signal_handler() {}

/// A panic is a bug in packbed, never the user's fault: one line that says so.
fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        eprintln!("packbed: {}", packbed::panic_line(info));
    }));
}
