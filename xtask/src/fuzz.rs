//! `cargo xtask fuzz [--seconds N] [--target NAME]`: the `cargo fuzz`
//! (libFuzzer) targets in `fuzz/`, each for N seconds, with a summary of
//! executions, coverage and findings. Installs what is missing: the nightly
//! toolchain (`rustup toolchain install nightly`) and `cargo-fuzz`
//! (`cargo install cargo-fuzz`). A crash fails the run and names the
//! reproducer file under `fuzz/artifacts/`.

use std::process::Command;

use crate::{output, root, run};

/// Options of `cargo xtask fuzz`.
#[derive(clap::Args, Debug)]
pub struct Options {
    /// Seconds per target
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..))]
    pub seconds: u32,
    /// Only this target (repeatable; all when none is given)
    #[arg(long = "target", value_name = "NAME")]
    pub targets: Vec<String>,
}

/// Installs the nightly toolchain and cargo-fuzz when missing.
fn setup() -> Result<(), String> {
    let toolchains = output("rustup", &["toolchain", "list"]).unwrap_or_default();
    if !toolchains.lines().any(|l| l.starts_with("nightly")) {
        run(Command::new("rustup").args([
            "toolchain",
            "install",
            "nightly",
            "--profile",
            "minimal",
        ]))?;
    }
    if output("cargo", &["+nightly", "fuzz", "--version"]).is_none() {
        run(Command::new("cargo").args(["install", "cargo-fuzz", "--locked"]))?;
    }
    Ok(())
}

/// One target's result.
struct Outcome {
    target: String,
    runs: u64,
    seconds: u64,
    coverage: u64,
}

/// Runs the fuzz targets; returns the summary lines.
pub fn fuzz(options: &Options) -> Result<Vec<String>, String> {
    setup()?;
    let dir = root().join("fuzz");
    let listed = Command::new("cargo")
        .args(["+nightly", "fuzz", "list"])
        .current_dir(&dir)
        .output()
        .map_err(|e| format!("cargo fuzz list: {e}"))?;
    let all: Vec<String> = String::from_utf8_lossy(&listed.stdout)
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .map(str::to_string)
        .collect();
    let targets: Vec<String> = if options.targets.is_empty() {
        all
    } else {
        for t in &options.targets {
            if !all.contains(t) {
                return Err(format!(
                    "fuzz: unknown target `{t}` (known: {})",
                    all.join(", ")
                ));
            }
        }
        options.targets.clone()
    };
    run(Command::new("cargo")
        .args(["+nightly", "fuzz", "build"])
        .current_dir(&dir))?;
    let mut outcomes = Vec::new();
    for target in targets {
        eprintln!("xtask: fuzzing {target} for {} s", options.seconds);
        let result = Command::new("cargo")
            .args(["+nightly", "fuzz", "run", &target, "--"])
            .arg(format!("-max_total_time={}", options.seconds))
            .arg("-rss_limit_mb=4096")
            .current_dir(&dir)
            .output()
            .map_err(|e| format!("cargo fuzz run {target}: {e}"))?;
        let log = String::from_utf8_lossy(&result.stderr);
        if !result.status.success() {
            let artifact = log
                .lines()
                .find(|l| l.contains("Test unit written to"))
                .unwrap_or("(no artifact line)");
            let cause = log
                .lines()
                .find(|l| l.contains("panicked at") || l.contains("ERROR:"))
                .unwrap_or("");
            return Err(format!(
                "fuzz: {target} found a failure: {cause} {artifact}"
            ));
        }
        outcomes.push(parse_outcome(&target, &log));
    }
    Ok(outcomes
        .iter()
        .map(|o| {
            format!(
                "{:<14} {:>11} runs in {:>4} s ({:>8} exec/s), coverage {:>5} edges, 0 failures",
                o.target,
                o.runs,
                o.seconds,
                o.runs / o.seconds.max(1),
                o.coverage
            )
        })
        .collect())
}

/// Reads `Done N runs in S second(s)` and the last `cov: C` of libFuzzer.
fn parse_outcome(target: &str, log: &str) -> Outcome {
    let number_after = |line: &str, key: &str| -> Option<u64> {
        line.split(key)
            .nth(1)?
            .split_whitespace()
            .next()?
            .parse()
            .ok()
    };
    let done = log.lines().rev().find(|l| l.starts_with("Done "));
    let runs = done.and_then(|l| number_after(l, "Done ")).unwrap_or(0);
    let seconds = done.and_then(|l| number_after(l, "runs in ")).unwrap_or(0);
    let coverage = log
        .lines()
        .rev()
        .find_map(|l| number_after(l, "cov: "))
        .unwrap_or(0);
    Outcome {
        target: target.to_string(),
        runs,
        seconds,
        coverage,
    }
}
