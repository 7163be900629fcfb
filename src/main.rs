//! `topple`: command-line wiring only.

use std::io::{Read, Write};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use topple::jobs::Job;

#[derive(Parser)]
#[command(
    name = "topple",
    version,
    about = "Rocking and overturning of free-standing rigid blocks under cycloidal pulses"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a job spec (a file, or - for stdin) and print the result JSON.
    Run {
        /// Path of the job-spec JSON, or - for standard input.
        spec: String,
        /// Write a figure of the result to this SVG file.
        #[arg(long)]
        plot: Option<String>,
    },
    /// Print the work-precision table of the solvers and write its SVG diagram.
    Precision {
        /// Where to write the SVG diagram.
        #[arg(long, default_value = "precision.svg")]
        svg: String,
    },
}

fn read_spec(path: &str) -> Result<String, String> {
    if path == "-" {
        let mut text = String::new();
        std::io::stdin()
            .read_to_string(&mut text)
            .map_err(|e| format!("cannot read standard input: {e}"))?;
        Ok(text)
    } else {
        std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))
    }
}

fn run(spec_path: &str, plot: Option<&str>) -> Result<(), (u8, String)> {
    let text = read_spec(spec_path).map_err(|e| (2, e))?;
    let job = Job::parse(&text).map_err(|e| {
        let field = if e.pointer.is_empty() {
            "/".to_string()
        } else {
            e.pointer.clone()
        };
        (2, format!("invalid spec: {field}: {}", e.message))
    })?;
    let control = topple::spectrum::Control::new();
    let result = job
        .run(&control)
        .map_err(|e| (1, format!("computation failed: {e}")))?;
    if let Some(path) = plot {
        topple::plot::plot_result(&result, path).map_err(|e| (1, format!("cannot plot: {e}")))?;
    }
    let out = serde_json::to_string_pretty(&result).map_err(|e| (1, e.to_string()))?;
    // A closed pipe (`topple run spec | head`) is not an error worth a panic.
    let _ = writeln!(std::io::stdout().lock(), "{out}");
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Run { spec, plot } => run(&spec, plot.as_deref()),
        Command::Precision { svg } => topple::precision::report(&svg).map_err(|e| (1, e)),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err((code, message)) => {
            eprintln!("topple: {}", message.replace('\n', " "));
            ExitCode::from(code)
        }
    }
}
