//! `cargo xtask …`: set-up, demo and the full check of the breakaway
//! workspace (the cargo-xtask convention: plain Rust, no extra tools).
//!
//! - `cargo xtask setup` installs what is missing: the rustup targets of the
//!   supported Cortex-M cores, rustfmt and clippy, and `qemu-system-arm`
//!   through the system's package manager where that is allowed (else it
//!   says exactly what to run).
//! - `cargo xtask demo` sets up and runs the demo.
//! - `cargo xtask test` sets up and runs every check.

use std::env;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

/// The Cortex-M targets the library is built for.
const TARGETS: [&str; 3] = [
    "thumbv7em-none-eabihf", // Cortex-M4F
    "thumbv7m-none-eabi",    // Cortex-M3
    "thumbv6m-none-eabi",    // Cortex-M0
];

const USAGE: &str = "usage: cargo xtask <setup|demo|test>
  setup   install the rustup targets, rustfmt, clippy and qemu-system-arm (where allowed)
  demo    set up, then print the break-away table of the paper's Fig. 5 setting
  test    set up, then run every check (fmt, clippy, tests, Cortex-M builds)";

fn main() -> ExitCode {
    let args: Vec<String> = env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("setup") => setup(),
        Some("demo") => setup().and_then(|()| demo()),
        Some("test") => setup().and_then(|()| test()),
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

/// The workspace root (the parent of this crate's directory).
fn root() -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest.parent().map(Path::to_path_buf).unwrap_or(manifest)
}

fn cargo() -> Command {
    let mut command = Command::new(env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    command.current_dir(root());
    command
}

/// Runs a command, echoing it; fails with its name on a non-zero exit.
fn run(command: &mut Command) -> Result<(), String> {
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
fn output(program: &str, args: &[&str]) -> Option<String> {
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
    let missing: Vec<&str> = TARGETS
        .iter()
        .copied()
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
    run(cargo().args([
        "run",
        "--quiet",
        "--release",
        "-p",
        "breakaway-lab",
        "--",
        "breakaway",
        "--model",
        "lab/models/fig5.toml",
        "--k",
        "0.01,0.1,1,3,10,30",
        "--variant",
        "all",
        "--dynamic",
    ]))
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
    // The library on every Cortex-M target, with and without its features.
    for target in TARGETS {
        run(cargo().args(["build", "--lib", "--release", "--target", target]))?;
        run(cargo().args([
            "clippy",
            "--lib",
            "--target",
            target,
            "--features",
            "defmt,cortex-m",
            "--",
            "-D",
            "warnings",
        ]))?;
    }
    run(cargo().args(["test", "--workspace"]))
}
