//! `breakaway-lab`: the command-line front of the f64 reference model
//! (`breakaway_reference`), following `MODEL.md` (the project's contract).
//!
//! Sub-commands:
//!
//! * `breakaway` — the quasi-static break-away predictor of MODEL.md §4 for the
//!   four `F̂` variants (`coulomb`, `stiction`, `mean`, `consistent`) over a grid
//!   of force rates `k`, optionally next to the full dynamics
//!   (`simulate_break_away`, MODEL.md §4 last paragraph).
//! * `validity-map` — sweeps the mass `m` and `k` and shows where the
//!   quasi-static prediction holds: the relative drift against the full
//!   dynamics, the inertia number `Λ` of MODEL.md §4 and the number `Π` of
//!   MODEL.md §8.
//! * `closed-loop` — friction compensators in a position loop
//!   ([`closed_loop`]).
//! * `diagnose`, `fit`, `validate`, `synth`, `static-curve` — the
//!   discrepancy workflow ([`workflow`]).
//!
//! The command line (options, defaults, value ranges, help) is [`cli`].
//! Model files are TOML as in MODEL.md §7 (read by `breakaway_reference`).
//! All the logic lives here so it can be tested; `main.rs` only maps
//! [`Error`] to a one-line message and an exit code.

// Units in brackets (`[m]`, `[N]`) are not intra-doc links (as in the
// reference crate); the `--help` texts of `cli` are doc comments too.
#![allow(rustdoc::broken_intra_doc_links)]

pub mod cli;
pub mod closed_loop;
pub mod commands;
pub mod data;
pub mod diagnose;
pub mod fit;
pub mod format;
pub mod linalg;
pub mod lugre;
pub mod progress;
pub mod residual;
pub mod static_curve;
pub mod steady;
pub mod svg;
pub mod synth;
pub mod workflow;

/// The reference crate (the only model implementation the lab uses).
pub(crate) use breakaway_reference as reference;

use std::fmt;
use std::io::Write;

/// A failure of the command line, reported as one line `error: …` on stderr.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Error {
    /// Bad arguments (exit code 2).
    Usage(String),
    /// Unreadable or invalid model file, failed computation, I/O (exit code 1).
    Runtime(String),
}

impl Error {
    /// The process exit code for this error: 2 for usage, 1 for runtime.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Usage(_) => 2,
            Error::Runtime(_) => 1,
        }
    }
}

impl fmt::Display for Error {
    /// The message on one line (line breaks of wrapped errors are folded).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let msg = match self {
            Error::Usage(m) | Error::Runtime(m) => m,
        };
        f.write_str(&one_line(msg))
    }
}

impl std::error::Error for Error {}

/// Folds a possibly multi-line message (e.g. a TOML parse error with a source
/// snippet) into one line.
pub fn one_line(msg: &str) -> String {
    msg.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs the command line `args` (without the program name), writing the
/// result to `out`. `--help` writes the help to `out`; a parse error is
/// [`Error::Usage`] with clap's message on one line.
pub fn run(args: &[String], out: &mut dyn Write) -> Result<(), Error> {
    let cli = match cli::parse(args) {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            let help = e.to_string();
            return emit(out, &format!("{}\n", help.trim_end()));
        }
        Err(e) => return Err(Error::Usage(cli::one_line_error(&e))),
    };
    match cli.command {
        cli::Command::Breakaway(a) => {
            let model = commands::load_model(&a.model)?;
            let w_b = a.boundary.w_b;
            let rows = commands::breakaway_rows(&model, &a.k, &a.variants, w_b, a.dynamic)?;
            let text = match a.output.format() {
                cli::Format::Json => format::breakaway_json(&rows),
                cli::Format::Markdown => format::breakaway_markdown(&rows, &a.variants),
                cli::Format::Table => format::breakaway_table(&rows, a.dynamic),
            };
            emit(out, &text)
        }
        cli::Command::ValidityMap(a) => {
            let model = commands::load_model(&a.model)?;
            let w_b = a.boundary.w_b;
            let blocks = commands::validity_map(&model, &a.masses, &a.k, &a.variants, w_b)?;
            let text = match a.output.format() {
                cli::Format::Json => format::validity_json(&blocks),
                cli::Format::Markdown => format::validity_markdown(&blocks, &a.variants, w_b),
                cli::Format::Table => format::validity_table(&blocks, &a.variants, w_b),
            };
            emit(out, &text)
        }
        cli::Command::ClosedLoop(a) => closed_loop::command(&a, out),
        cli::Command::Diagnose(a) => workflow::diagnose(a, out),
        cli::Command::Fit(a) => workflow::fit(a, out),
        cli::Command::Validate(a) => workflow::validate(a, out),
        cli::Command::Synth(a) => workflow::synth(a, out),
        cli::Command::StaticCurve(a) => workflow::static_curve(a, out),
    }
}

/// Writes `text` and flushes; a closed pipe (`… | head`) is not an error.
pub fn emit(out: &mut dyn Write, text: &str) -> Result<(), Error> {
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(Error::Runtime(format!("writing output: {e}")))
        }
        _ => Ok(()),
    }
}
