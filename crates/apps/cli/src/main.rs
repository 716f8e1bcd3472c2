//! `spraysim`: command-line front end of the spraysim library.
//!
//! [`cli`] declares what the command line accepts; [`commands`] carries out each subcommand,
//! one file each; [`backend`] picks what flies a run's particles (CPU or GPU); [`summary`] prints a run's tables, [`recorder`] draws the 3D views a run asks
//! for, and [`control`] holds the run's Ctrl-C handling and the fault tests' pause points.

use anyhow::Result;
use clap::Parser;
use cli::Command;
use std::io::ErrorKind;
use std::process::ExitCode;

/// `println!` to stdout that returns an error instead of panicking when stdout is closed.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)?
    }};
}

mod backend;
mod cli;
mod commands;
mod control;
mod recorder;
mod summary;

fn main() -> ExitCode {
    match dispatch(cli::Cli::parse().command) {
        Ok(()) => ExitCode::SUCCESS,
        // The reader went away (`spraysim presets | head`): what it wanted, it has.
        Err(e) if e.downcast_ref::<std::io::Error>().is_some_and(|e| e.kind() == ErrorKind::BrokenPipe) => {
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

/// The whole chain of causes on one line, without a backtrace; a cause whose text its
/// parent already quotes (as the library's errors do) is not repeated.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !line.contains(&text) {
            line = format!("{line}: {text}");
        }
    }
    line
}

/// Carries out `command`.
fn dispatch(command: Command) -> Result<()> {
    use commands::{bench, calibrate, check, render, run, validate};
    match command {
        Command::Run(args) => run::run(&args),
        Command::Resume(args) => run::resume(&args),
        Command::Check(args) => check::check(&args),
        Command::Calibrate(args) => calibrate::calibrate(&args),
        Command::Validate(args) => validate::validate(&args),
        Command::Presets => commands::presets(),
        Command::Render(args) => render::render(&args),
        Command::View(args) => render::view(&args),
        Command::Bench(args) => bench::bench(&args),
    }
}
