//! `cargo xtask …`: set-up, demo and the full check of the breakaway
//! workspace (the cargo-xtask convention: plain Rust, no extra tools).
//!
//! - `cargo xtask setup` installs what is missing: the rustup targets of the
//!   supported Cortex-M cores, rustfmt and clippy, and `qemu-system-arm`
//!   through the system's package manager where that is allowed (else it
//!   says exactly what to run).
//! - `cargo xtask demo` sets up and runs the demo.
//! - `cargo xtask test` sets up and runs every check, the on-target checks
//!   under QEMU included.
//! - `cargo xtask qemu [NAME…]` runs the on-target checks (or those named).
//! - `cargo xtask profile` counts instructions per call under QEMU.

mod checks;
mod fuzz;
mod profile;
mod qemu;
mod sweep;

use std::env;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

const USAGE: &str = "usage: cargo xtask <setup|demo|test|qemu|profile|fuzz|sweep>
  setup    install the rustup targets, rustfmt, clippy and qemu-system-arm (where allowed)
  demo     set up, then run the firmware examples on the Cortex-M4F under QEMU
  test     set up, then run every check (fmt, clippy, host tests, on-target checks)
  qemu     [NAME…]  the on-target checks under QEMU (those whose name contains NAME)
  profile  [--target T] [--rows NAME,…] [--budget-hz 20000] [--cpu-hz 168000000] [--json]
           instructions per call of the hot functions under QEMU (--rows: only those rows)
  fuzz     [--seconds 60] [--target NAME]  the cargo-fuzz targets (nightly)
  sweep    [--seeds 100000..100160] [--kind mixed|model|outside] [--out DIR] [--json FILE]
           the discrepancy workflow scored on records of the independent generator";

fn main() -> ExitCode {
    let args: Vec<String> = env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("setup") => setup(),
        Some("demo") => setup().and_then(|()| demo()),
        Some("test") => setup().and_then(|()| test()),
        Some("qemu") => setup().and_then(|()| {
            checks::all(&args[1..]).map(|lines| lines.iter().for_each(|l| println!("{l}")))
        }),
        Some("profile") => profile::Options::parse(&args[1..])
            .and_then(|o| setup().and_then(|()| profile::run(&o))),
        Some("fuzz") => fuzz::Options::parse(&args[1..])
            .and_then(|o| setup().and_then(|()| fuzz::fuzz(&o)))
            .map(|lines| lines.iter().for_each(|l| println!("{l}"))),
        Some("sweep") => sweep::Options::parse(&args[1..]).and_then(|o| sweep::command(&o)),
        Some("-h" | "--help") => {
            println!("{USAGE}");
            Ok(())
        }
        _ => Err(USAGE.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("xtask: {message}");
            ExitCode::FAILURE
        }
    }
}

/// Cargo's target directory: `CARGO_TARGET_DIR` when set, else `./target`.
pub(crate) fn target_dir() -> PathBuf {
    env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|d| if d.is_absolute() { d } else { root().join(d) })
        .unwrap_or_else(|| root().join("target"))
}

/// The workspace root (the parent of this crate's directory).
pub(crate) fn root() -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest.parent().map(Path::to_path_buf).unwrap_or(manifest)
}

pub(crate) fn cargo() -> Command {
    let mut command = Command::new(env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    command.current_dir(root());
    command
}

/// Runs a command, echoing it; fails with its name on a non-zero exit.
pub(crate) fn run(command: &mut Command) -> Result<(), String> {
    let shown = format!("{command:?}").replace('"', "");
    eprintln!("xtask: $ {shown}");
    let status = command
        .status()
        .map_err(|e| format!("could not start `{shown}`: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`{shown}` failed ({status})"))
    }
}

/// Captures a command's stdout, or `None` when it cannot run or fails.
pub(crate) fn output(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

fn setup() -> Result<(), String> {
    setup_rust()?;
    setup_qemu();
    Ok(())
}

fn setup_rust() -> Result<(), String> {
    let Some(installed) = output("rustup", &["target", "list", "--installed"]) else {
        return Err(
            "rustup is not available: install the targets with `rustup target add \
             thumbv7em-none-eabihf thumbv7m-none-eabi thumbv6m-none-eabi`"
                .into(),
        );
    };
    let missing: Vec<&str> = qemu::TARGETS
        .iter()
        .map(|t| t.triple)
        .filter(|t| !installed.lines().any(|l| l.trim() == *t))
        .collect();
    if !missing.is_empty() {
        run(Command::new("rustup")
            .args(["target", "add"])
            .args(&missing))?;
    }
    let components = output("rustup", &["component", "list", "--installed"]).unwrap_or_default();
    for component in ["rustfmt", "clippy"] {
        if !components.lines().any(|l| l.starts_with(component)) {
            run(Command::new("rustup").args(["component", "add", component]))?;
        }
    }
    Ok(())
}

/// QEMU runs the firmware examples; it is optional until they exist, so a
/// failure to install it is reported, not fatal.
fn setup_qemu() {
    if output("qemu-system-arm", &["--version"]).is_some() {
        return;
    }
    let is_root = output("id", &["-u"]).is_some_and(|id| id.trim() == "0");
    let has_apt = output("apt-get", &["--version"]).is_some();
    if is_root && has_apt {
        let installed = run(Command::new("apt-get").arg("update").arg("-qq")).and_then(|()| {
            run(Command::new("apt-get")
                .args(["install", "-y", "-qq", "--no-install-recommends"])
                .arg("qemu-system-arm")
                .env("DEBIAN_FRONTEND", "noninteractive"))
        });
        if let Err(e) = installed {
            eprintln!("xtask: warning: could not install qemu-system-arm: {e}");
        }
    } else {
        eprintln!(
            "xtask: warning: qemu-system-arm is missing; install it with \
             `sudo apt-get install qemu-system-arm` (Debian/Ubuntu) or your system's package manager"
        );
    }
}

fn demo() -> Result<(), String> {
    let target = qemu::TARGETS[0];
    let table = qemu::run_example("breakaway_table", target)?;
    println!(
        "Break-away force F_ba(k) [N] computed on the {} (paper's Fig. 5 setting:",
        target.core
    );
    println!("Fc = 1 N, Fs = 1.5 N, V = 1 mm/s, delta = 1, z_max = 10 um, w_b = 0.95)\n");
    print_table(&table);
    let samples = qemu::run_example("presliding_loop", target)?;
    println!("\nPresliding friction along a trajectory with reversals and minor loops");
    println!("(every 60th of 1200 samples; counts of 10 nm; z_max = 1000 counts)\n");
    println!(
        "{:>8} {:>12} {:>14} {:>14}",
        "count", "v [m/s]", "F single [N]", "F closing [N]"
    );
    for line in samples.lines().filter(|l| l.starts_with("s ")).step_by(60) {
        let f: Vec<&str> = line.split_whitespace().collect();
        if let [_, x, v, a, b] = f[..] {
            println!("{x:>8} {v:>12} {a:>14} {b:>14}");
        }
    }
    println!();
    profile::run(&profile::Options::default())
}

/// Prints the `ba` rows of `breakaway_table` as one row per k.
fn print_table(output: &str) {
    let rows: Vec<Vec<&str>> = output
        .lines()
        .filter(|l| l.starts_with("ba "))
        .map(|l| l.split_whitespace().collect())
        .collect();
    println!(
        "{:>8} {:>10} {:>10} {:>10} {:>10}",
        "k [N/s]", "coulomb", "stiction", "mean", "consistent"
    );
    let ks: Vec<&str> = rows
        .iter()
        .filter(|r| r[1] == "coulomb")
        .map(|r| r[2])
        .collect();
    for k in ks {
        let value = |variant: &str| {
            rows.iter()
                .find(|r| r[1] == variant && r[2] == k)
                .and_then(|r| r.get(4))
                .and_then(|f| f.parse::<f64>().ok())
                .map_or("-".to_string(), |f| format!("{f:.5}"))
        };
        println!(
            "{k:>8} {:>10} {:>10} {:>10} {:>10}",
            value("coulomb"),
            value("stiction"),
            value("mean"),
            value("consistent")
        );
    }
}

fn test() -> Result<(), String> {
    run(cargo().args(["fmt", "--all", "--", "--check"]))?;
    run(cargo().args([
        "clippy",
        "--workspace",
        "--all-targets",
        "--",
        "-D",
        "warnings",
    ]))?;
    // The library on every Cortex-M target, with and without its features,
    // and the firmware examples.
    for target in qemu::TARGETS {
        let triple = target.triple;
        run(cargo().args(["build", "--lib", "--release", "--target", triple]))?;
        run(cargo().args([
            "clippy",
            "--lib",
            "--examples",
            "--target",
            triple,
            "--features",
            "defmt,firmware,hal",
            "--",
            "-D",
            "warnings",
        ]))?;
    }
    // The library's documentation builds without a warning.
    run(cargo()
        .args(["doc", "-p", "breakaway", "--no-deps"])
        .env("RUSTDOCFLAGS", "-D warnings"))?;
    run(cargo().args(["test", "--workspace"]))?;
    // The PWM adapter's tests need its feature.
    run(cargo().args([
        "test",
        "-p",
        "breakaway",
        "--features",
        "hal",
        "--test",
        "hal",
    ]))?;
    // The discrepancy workflow on a small fixed subset of the independent
    // generator's records (the full sweep: `cargo xtask sweep`).
    sweep::smoke()?;
    // On-target checks under QEMU against the host f64 reference.
    for line in checks::all(&[])? {
        println!("on-target: {line}");
    }
    profile::check_targets()?;
    // Every fuzz target builds and runs briefly (longer: `cargo xtask fuzz`).
    let smoke = fuzz::Options {
        seconds: 10,
        targets: Vec::new(),
    };
    for line in fuzz::fuzz(&smoke)? {
        println!("fuzz: {line}");
    }
    Ok(())
}
