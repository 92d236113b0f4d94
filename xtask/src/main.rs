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

// Units are written in brackets in the docs ([N], [s], [Hz]), which rustdoc
// would otherwise try to resolve as links.
#![allow(rustdoc::broken_intra_doc_links)]

mod checks;
mod fuzz;
mod profile;
mod qemu;
mod sweep;

use clap::{Parser, Subcommand};
use std::env;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

/// Set-up, demo and the full check of the breakaway workspace.
#[derive(Parser, Debug)]
#[command(name = "cargo xtask", bin_name = "cargo xtask")]
struct Cli {
    #[command(subcommand)]
    command: Task,
}

#[derive(Subcommand, Debug)]
enum Task {
    /// Install the rustup targets, rustfmt, clippy and qemu-system-arm (where allowed)
    Setup,
    /// Set up, then run the firmware examples on the Cortex-M4F under QEMU
    Demo,
    /// Set up, then run every check (fmt, clippy, host tests, on-target checks)
    Test,
    /// The on-target checks under QEMU
    Qemu {
        /// Only the checks whose name contains NAME
        #[arg(value_name = "NAME")]
        names: Vec<String>,
    },
    /// Instructions per call of the hot functions under QEMU
    Profile(ProfileArgs),
    /// The cargo-fuzz targets (nightly)
    Fuzz(fuzz::Options),
    /// The discrepancy workflow scored on records of the independent generator
    Sweep(sweep::Args),
}

/// The arguments of `cargo xtask profile`.
#[derive(clap::Args, Debug)]
struct ProfileArgs {
    /// Profile on this target only (repeatable; all when none is given)
    #[arg(long = "target", value_name = "T", value_parser = qemu::target)]
    targets: Vec<qemu::Target>,
    /// Only these rows (the example is built with the others left out)
    #[arg(long, value_name = "NAME,...", value_delimiter = ',', value_parser = row)]
    rows: Vec<String>,
    /// Control-loop rate [Hz]
    #[arg(long, value_name = "HZ", default_value = "20000", value_parser = positive)]
    budget_hz: f64,
    /// CPU clock [Hz]
    #[arg(long, value_name = "HZ", default_value = "168000000", value_parser = positive)]
    cpu_hz: f64,
    /// Print JSON instead of the table
    #[arg(long)]
    json: bool,
    /// After the table: per row at δ = 1, the calls per instruction count
    /// and the executed instructions of one call of each count
    #[arg(long)]
    listings: bool,
}

impl ProfileArgs {
    fn options(self) -> profile::Options {
        let defaults = profile::Options::default();
        profile::Options {
            targets: if self.targets.is_empty() {
                defaults.targets
            } else {
                self.targets
            },
            budget_hz: self.budget_hz,
            cpu_hz: self.cpu_hz,
            json: self.json,
            rows: self.rows,
            listings: self.listings,
        }
    }
}

/// A row name of the profile.
fn row(name: &str) -> Result<String, String> {
    if profile::ROWS.iter().any(|(_, n)| *n == name) {
        Ok(name.to_string())
    } else {
        let known: Vec<&str> = profile::ROWS.iter().map(|(_, n)| *n).collect();
        Err(format!("unknown row (known: {})", known.join(", ")))
    }
}

/// A finite positive number.
fn positive(text: &str) -> Result<f64, String> {
    text.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && *x > 0.0)
        .ok_or_else(|| "must be a positive number".to_string())
}

fn main() -> ExitCode {
    let print = |lines: Vec<String>| lines.iter().for_each(|l| println!("{l}"));
    let result = match Cli::parse().command {
        Task::Setup => setup(),
        Task::Demo => setup().and_then(|()| demo()),
        Task::Test => setup().and_then(|()| test()),
        Task::Qemu { names } => setup().and_then(|()| checks::all(&names).map(print)),
        Task::Profile(args) => setup().and_then(|()| profile::run(&args.options())),
        Task::Fuzz(options) => setup().and_then(|()| fuzz::fuzz(&options).map(print)),
        Task::Sweep(args) => sweep::command(&args.options()),
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
        run(cargo().args([
            "build",
            "-p",
            "breakaway",
            "--lib",
            "--release",
            "--target",
            triple,
        ]))?;
        run(cargo().args([
            "clippy",
            "-p",
            "breakaway",
            "--lib",
            "--target",
            triple,
            "--features",
            "defmt,cortex-m,hal",
            "--",
            "-D",
            "warnings",
        ]))?;
        run(cargo().args([
            "clippy",
            "-p",
            "breakaway-firmware",
            "--examples",
            "--target",
            triple,
            "--features",
            "qemu",
            "--",
            "-D",
            "warnings",
        ]))?;
    }
    package_check()?;
    // The documentation of every crate (the library's and the tools')
    // builds without a warning.
    run(cargo()
        .args(["doc", "--workspace", "--no-deps"])
        .env("RUSTDOCFLAGS", "-D warnings"))?;
    // The tests on real and outside records read `shared/data` beside the
    // repository and skip, with a note, where it is absent; where it is
    // present they must not skip (a test looking in the wrong place would
    // pass on nothing).
    let shared = root().join("../shared/data");
    let mut tests = cargo();
    tests.args(["test", "--workspace"]);
    if shared.is_dir() {
        tests.env("BREAKAWAY_REQUIRE_SHARED", "1");
    } else {
        println!(
            "note: {} is absent: the tests on the EMPS, Indy7 and outside records skip",
            shared.display()
        );
    }
    // Likewise the independent Python check of `breakaway --json`.
    let python = Command::new("python3").arg("--version").output();
    if python.is_ok_and(|o| o.status.success()) {
        tests.env("BREAKAWAY_REQUIRE_PYTHON", "1");
    } else {
        println!("note: python3 not found: the independent Python check of the break-away skips");
    }
    run(&mut tests)?;
    // The doctests that write to a PWM channel compile to an empty `main`
    // without `hal`, so the doctests run again with the feature.
    run(cargo().args(["test", "-p", "breakaway", "--features", "hal", "--doc"]))?;
    // The PWM adapter's tests and the README's recipe need its feature.
    run(cargo().args([
        "test",
        "-p",
        "breakaway",
        "--features",
        "hal",
        "--test",
        "hal",
        "--test",
        "readme",
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

/// The published package as a user gets it: packed (`cargo package`),
/// unpacked, and built as the dependency of a `no_std` library for the
/// Cortex-M0 with the features firmware uses. A build from the repository
/// does not show what the package lacks: its build script once emitted link
/// arguments for examples the package does not ship, which cargo refuses
/// on every `thumb*` target.
fn package_check() -> Result<(), String> {
    let dir = target_dir().join("package-check");
    let _ = std::fs::remove_dir_all(&dir);
    run(cargo()
        .args(["package", "-p", "breakaway", "--no-verify", "--allow-dirty"])
        .env("CARGO_TARGET_DIR", &dir))?;
    let packed = dir.join("package");
    let crate_file = std::fs::read_dir(&packed)
        .map_err(|e| format!("{}: {e}", packed.display()))?
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .find(|n| n.starts_with("breakaway-") && n.ends_with(".crate"))
        .ok_or_else(|| format!("{}: no breakaway-*.crate", packed.display()))?;
    run(Command::new("tar")
        .arg("xzf")
        .arg(packed.join(&crate_file))
        .arg("-C")
        .arg(&dir))?;
    let unpacked = dir.join(crate_file.trim_end_matches(".crate"));
    let user = dir.join("user");
    let write = |path: PathBuf, text: String| {
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
    };
    std::fs::create_dir_all(user.join("src")).map_err(|e| format!("{}: {e}", user.display()))?;
    write(
        user.join("Cargo.toml"),
        format!(
            "[package]\nname = \"package-user\"\nversion = \"0.0.0\"\nedition = \"2021\"\n\n\
             [dependencies]\nbreakaway = {{ path = {:?}, features = [\"hal\", \"defmt\"] }}\n\n\
             [workspace]\n",
            unpacked.display().to_string()
        ),
    )?;
    write(
        user.join("src/lib.rs"),
        "#![no_std]\n//! Uses the packaged library as a dependency.\npub use breakaway::{Model, Q16};\n".into(),
    )?;
    run(cargo()
        .args(["build", "--release", "--target", "thumbv6m-none-eabi"])
        .current_dir(&user)
        .env("CARGO_TARGET_DIR", dir.join("target")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    fn parses(line: &str) -> bool {
        let argv = std::iter::once("xtask").chain(line.split_whitespace());
        Cli::try_parse_from(argv).is_ok()
    }

    #[test]
    fn the_documented_calls_parse() {
        for line in [
            "demo",
            "test",
            "qemu closed_loop long_run",
            "profile --target thumbv6m-none-eabi --rows update_f32,stribeck_f32 --json",
            "profile --target thumbv7em-none-eabihf --rows update_f32 --listings",
            "fuzz --seconds 10 --target presliding",
            "sweep --seeds 700000..700160 --kind mixed --out /tmp/x --json /tmp/x.json",
            "sweep --seeds 700000..700160 --lab /tmp/old/breakaway-lab",
            "sweep --seeds 700000..700160 --out /tmp/x --rescore",
        ] {
            assert!(parses(line), "{line}");
        }
        for line in [
            "profile --rows nothing",
            "profile --budget-hz 0",
            "profile --target x86",
            "fuzz --seconds 0",
            "sweep --seeds 5..5",
            "sweep --kind any",
            "unknown",
        ] {
            assert!(!parses(line), "{line}");
        }
        let Ok(Cli {
            command: Task::Sweep(args),
        }) = Cli::try_parse_from(["xtask", "sweep"])
        else {
            panic!("sweep");
        };
        let o = args.options();
        assert_eq!((o.from, o.to, o.kind.as_str()), (100_000, 100_160, "mixed"));
        assert_eq!(o.out, root().join("target/sweep"));
        assert_eq!(o.lab, None);
        assert!(!o.rescore);
    }
}
