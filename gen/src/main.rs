//! `breakaway-gen`: writes test records (`data.csv`, `truth.toml`,
//! `truth.json`) for the discrepancy workflow.
//!
//! ```text
//! breakaway-gen record --seed N [--family F] [--plant P] [--effects a,b] [--kind K] --out DIR
//! breakaway-gen suite --seeds A..B [--kind model|outside|steady|mixed] [--jobs J] --out DIR
//! ```
//!
//! Exit codes: 0 done, 1 a record could not be generated or written, 2 bad
//! command line.

// Units are written in square brackets ([m], [N], [s]); they are not links.
#![allow(rustdoc::broken_intra_doc_links)]

use breakaway_gen::draw::{Kind, Overrides};
use breakaway_gen::excite::Family;
use breakaway_gen::friction::Effect;
use breakaway_gen::plants::PlantKind;
use breakaway_gen::record::{self, Generated};
use breakaway_gen::write;
use clap::{Parser, Subcommand};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "breakaway-gen",
    version,
    about = "Independent generator of friction test records (CSV records and TOML truth models, as breakaway-lab reads them)"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Write one record: DIR/data.csv, DIR/truth.toml, DIR/truth.json.
    Record {
        /// Seed (the record depends on it alone, and on the overrides).
        #[arg(long)]
        seed: u64,
        /// Family: servo, velocity_loop, point_to_point, ramps, sinusoid, steady (drawn when absent).
        #[arg(long)]
        family: Option<String>,
        /// Plant: model, lugre, maxwell_slip, compliant, noisy_velocity (drawn when absent).
        #[arg(long)]
        plant: Option<String>,
        /// Hidden effects, comma-separated catalogue names, or `none`; steady
        /// records also take `stribeck-absent` (drawn when absent).
        #[arg(long)]
        effects: Option<String>,
        /// What to draw from when family/plant are absent: model, outside, steady, mixed, suite (issue 10's outside suite: servo records, its effect mix by seed mod 26, its ranges).
        #[arg(long, default_value = "mixed")]
        kind: String,
        /// Record length [s] (default: drawn, 20–40 s).
        #[arg(long)]
        duration: Option<f64>,
        /// Open-loop zero-force pause [s] before each ramp of a `servo`
        /// record, as the outside generator's servo records have it
        /// (default: none, the ramp starts as the servo lets go).
        #[arg(long)]
        ramp_pause: Option<f64>,
        /// Output directory (new or empty, unless --force).
        #[arg(long)]
        out: PathBuf,
        /// Write into a directory that is not empty (the record's files are
        /// replaced; others are left as they are).
        #[arg(long)]
        force: bool,
    },
    /// Write one record per seed: DIR/<name>/{data.csv,truth.toml,truth.json} and DIR/index.json.
    Suite {
        /// Seeds `A..B` (B excluded), `A..=B`, or one seed.
        #[arg(long)]
        seeds: String,
        /// model, outside, steady, mixed, or suite (issue 10's outside suite: servo records, its effect mix by seed mod 26, its ranges).
        #[arg(long, default_value = "mixed")]
        kind: String,
        /// Worker threads (default: the available cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// Open-loop zero-force pause [s] before each ramp of every `servo`
        /// record, as for `record` (default: none).
        #[arg(long)]
        ramp_pause: Option<f64>,
        /// Output directory (holding no record of these seeds, unless
        /// --force).
        #[arg(long)]
        out: PathBuf,
        /// Write although DIR holds records of these seeds (their folders
        /// are written over; a folder of another kind stays beside).
        #[arg(long)]
        force: bool,
    },
}

/// Prints a line to stdout, ignoring a closed pipe.
fn say(line: &str) {
    let mut o = std::io::stdout().lock();
    let _ = writeln!(o, "{line}");
}

/// One suite record: its summary line and truth JSON, or why it failed.
type Outcome = Result<(String, serde_json::Value), String>;

/// A command-line error (exit code 2).
struct Usage(String);

fn parse_kind(s: &str) -> Result<Kind, Usage> {
    Kind::from_name(s).ok_or_else(|| {
        Usage(format!(
            "unknown kind `{s}` (expected model, outside, steady, mixed or suite)"
        ))
    })
}

/// Most seeds one suite may hold.
const MAX_SEEDS: u64 = 1_000_000;

fn parse_seeds(s: &str) -> Result<Vec<u64>, Usage> {
    let bad = || {
        Usage(format!(
            "bad --seeds `{s}`: expected A..B (B excluded), A..=B or a single seed"
        ))
    };
    let num = |t: &str| t.trim().parse::<u64>().map_err(|_| bad());
    let (a, b) = if let Some((a, b)) = s.split_once("..=") {
        let (a, b) = (num(a)?, num(b)?);
        if b < a || b == u64::MAX {
            return Err(bad());
        }
        (a, b + 1)
    } else if let Some((a, b)) = s.split_once("..") {
        let (a, b) = (num(a)?, num(b)?);
        if b <= a {
            return Err(bad());
        }
        (a, b)
    } else {
        let a = num(s)?;
        if a == u64::MAX {
            return Err(bad());
        }
        (a, a + 1)
    };
    if b - a > MAX_SEEDS {
        return Err(Usage(format!(
            "--seeds `{s}` names {} seeds; at most {MAX_SEEDS} per suite",
            b - a
        )));
    }
    Ok((a..b).collect())
}

fn parse_effects(s: &str) -> Result<(Vec<Effect>, bool), Usage> {
    let mut out = Vec::new();
    let mut absent = false;
    for t in s.split(',').map(str::trim).filter(|t| !t.is_empty()) {
        if t == "none" || t == "null" {
            continue;
        }
        if t == "stribeck-absent" || t == "stribeck_absent" {
            absent = true;
            continue;
        }
        let e = Effect::from_name(t).ok_or_else(|| {
            Usage(format!(
                "unknown effect `{t}` (expected {}, stribeck-absent or none)",
                Effect::ALL.map(|e| e.name()).join(", ")
            ))
        })?;
        if out.contains(&e) {
            return Err(Usage(format!("effect `{t}` given twice")));
        }
        out.push(e);
    }
    Ok((out, absent))
}

/// The `what` called `name`, or a usage error listing the `names`.
fn by_name<T>(
    what: &str,
    name: &str,
    from_name: impl Fn(&str) -> Option<T>,
    names: &[&str],
) -> Result<T, Usage> {
    from_name(name).ok_or_else(|| {
        Usage(format!(
            "unknown {what} `{name}` (expected {})",
            names.join(", ")
        ))
    })
}

fn summary_line(g: &Generated, secs: f64) -> String {
    let d = &g.draw;
    let vis = g.visibilities(",").unwrap_or_else(|| {
        if d.stribeck_absent {
            "stribeck-absent"
        } else {
            "-"
        }
        .to_string()
    });
    format!(
        "{:<44} {:<15} {:<14} {:<40} Π={:<6.2} noise={:.3e} N  {:.2} s",
        g.name(),
        d.family.name(),
        d.plant.name(),
        vis,
        d.pi(),
        d.noise_std,
        secs
    )
}

/// `--ramp-pause`, checked: 0 … 5 s.
fn checked_pause(pause: Option<f64>) -> Result<Option<f64>, Usage> {
    match pause {
        Some(p) if !(p.is_finite() && (0.0..=5.0).contains(&p)) => {
            Err(Usage(format!("bad --ramp-pause {p}: expected 0 … 5 s")))
        }
        p => Ok(p),
    }
}

/// Refuses a record directory `out` that holds files already (unless
/// `force`): another record's report or model would sit beside this one.
fn empty_or_forced(out: &Path, force: bool) -> Result<(), Usage> {
    let first = std::fs::read_dir(out)
        .ok()
        .and_then(|mut d| d.next())
        .and_then(Result::ok);
    match first {
        Some(entry) if !force => Err(Usage(format!(
            "{} is not empty (it holds {}): give a new or empty directory, or --force to write the record there",
            out.display(),
            entry.file_name().to_string_lossy()
        ))),
        _ => Ok(()),
    }
}

/// Refuses a suite directory `out` that holds a record folder
/// (`s<seed>_…`) of one of `seeds` (unless `force`): the records of two
/// runs would be taken for one.
fn no_record_of(out: &Path, seeds: &[u64], force: bool) -> Result<(), Usage> {
    let Ok(entries) = std::fs::read_dir(out) else {
        return Ok(());
    };
    let found = entries.filter_map(Result::ok).find(|e| {
        let name = e.file_name().to_string_lossy().into_owned();
        name.strip_prefix('s')
            .and_then(|n| n.split('_').next())
            .and_then(|n| n.parse::<u64>().ok())
            .is_some_and(|seed| seeds.contains(&seed))
    });
    match found {
        Some(e) if !force => Err(Usage(format!(
            "{} already holds a record of these seeds ({}): give another directory, or --force to write over it",
            out.display(),
            e.file_name().to_string_lossy()
        ))),
        _ => Ok(()),
    }
}

fn record_cmd(
    seed: u64,
    family: Option<String>,
    plant: Option<String>,
    effects: Option<String>,
    kind: &str,
    (duration, ramp_pause): (Option<f64>, Option<f64>),
    (out, force): (&Path, bool),
) -> Result<Result<(), String>, Usage> {
    let kind = parse_kind(kind)?;
    let mut ov = Overrides {
        ramp_pause: checked_pause(ramp_pause)?,
        ..Overrides::default()
    };
    if let Some(f) = family {
        let names = Family::ALL.map(|f| f.name());
        ov.family = Some(by_name("family", &f, Family::from_name, &names)?);
    }
    if let Some(p) = plant {
        let names = PlantKind::ALL.map(|p| p.name());
        ov.plant = Some(by_name("plant", &p, PlantKind::from_name, &names)?);
    }
    if let Some(e) = effects {
        let (list, absent) = parse_effects(&e)?;
        ov.effects = Some(list);
        ov.stribeck_absent = Some(absent);
    }
    if let Some(d) = duration {
        if !(d.is_finite() && (1.0..=600.0).contains(&d)) {
            return Err(Usage(format!("bad --duration {d}: expected 1 … 600 s")));
        }
        ov.duration = Some(d);
    }
    // Inconsistent overrides are command-line errors.
    breakaway_gen::draw::draw(seed, 0, kind, &ov).map_err(Usage)?;
    empty_or_forced(out, force)?;
    let t0 = Instant::now();
    Ok(record::generate(seed, kind, &ov).and_then(|g| {
        write::write(&g, out)?;
        say(&summary_line(&g, t0.elapsed().as_secs_f64()));
        say(&format!("wrote {}", out.display()));
        Ok(())
    }))
}

fn suite_cmd(
    seeds: &str,
    kind: &str,
    (jobs, ramp_pause): (Option<usize>, Option<f64>),
    out: &Path,
    force: bool,
) -> Result<Result<(), String>, Usage> {
    let seeds = parse_seeds(seeds)?;
    let kind = parse_kind(kind)?;
    no_record_of(out, &seeds, force)?;
    let ov = Overrides {
        ramp_pause: checked_pause(ramp_pause)?,
        ..Overrides::default()
    };
    let jobs = match jobs {
        Some(0) => return Err(Usage("--jobs must be at least 1".into())),
        Some(j) => j,
        None => std::thread::available_parallelism().map_or(2, |n| n.get()),
    }
    .min(seeds.len());
    if let Err(e) = std::fs::create_dir_all(out) {
        return Ok(Err(format!("{}: cannot create: {e}", out.display())));
    }
    let bar = if std::io::stderr().is_terminal() {
        let b = indicatif::ProgressBar::new(seeds.len() as u64);
        if let Ok(st) = indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} records  {elapsed_precise} (eta {eta})",
        ) {
            b.set_style(st);
        }
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<(u64, Outcome)>> = Mutex::new(Vec::new());
    let t_all = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(&seed) = seeds.get(i) else { break };
                let t0 = Instant::now();
                let r = record::generate(seed, kind, &ov).and_then(|g| {
                    let dir = out.join(g.name());
                    write::write(&g, &dir)?;
                    Ok((
                        summary_line(&g, t0.elapsed().as_secs_f64()),
                        write::truth_json(&g),
                    ))
                });
                if let Ok(mut v) = results.lock() {
                    v.push((seed, r));
                }
                bar.inc(1);
            });
        }
    });
    bar.finish_and_clear();
    let mut results = results.into_inner().unwrap_or_default();
    results.sort_by_key(|(s, _)| *s);
    let mut index = Vec::new();
    let mut failed = Vec::new();
    for (seed, r) in &results {
        match r {
            Ok((line, json)) => {
                say(line);
                index.push(json.clone());
            }
            Err(e) => {
                eprintln!("seed {seed}: {e}");
                failed.push(*seed);
            }
        }
    }
    let idx = out.join("index.json");
    let text = serde_json::to_string_pretty(&index).unwrap_or_default();
    if let Err(e) = std::fs::write(&idx, text + "\n") {
        return Ok(Err(format!("{}: cannot write: {e}", idx.display())));
    }
    say(&format!(
        "{} records in {:.1} s ({} jobs) -> {}",
        index.len(),
        t_all.elapsed().as_secs_f64(),
        jobs,
        out.display()
    ));
    if failed.is_empty() {
        Ok(Ok(()))
    } else {
        Ok(Err(format!("{} seed(s) failed: {failed:?}", failed.len())))
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let r = match cli.cmd {
        Cmd::Record {
            seed,
            family,
            plant,
            effects,
            kind,
            duration,
            ramp_pause,
            out,
            force,
        } => record_cmd(
            seed,
            family,
            plant,
            effects,
            &kind,
            (duration, ramp_pause),
            (&out, force),
        ),
        Cmd::Suite {
            seeds,
            kind,
            jobs,
            ramp_pause,
            out,
            force,
        } => suite_cmd(&seeds, &kind, (jobs, ramp_pause), &out, force),
    };
    match r {
        Err(Usage(msg)) => {
            eprintln!("breakaway-gen: error: {msg}");
            ExitCode::from(2)
        }
        Ok(Err(msg)) => {
            eprintln!("breakaway-gen: error: {msg}");
            ExitCode::from(1)
        }
        Ok(Ok(())) => ExitCode::SUCCESS,
    }
}
