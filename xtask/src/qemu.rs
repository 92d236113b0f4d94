//! Building the firmware examples and running them under QEMU.

use std::io::Read;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::thread;
use std::time::{Duration, Instant};

use crate::{cargo, root, run};

/// A Cortex-M target and the QEMU machine that runs it.
#[derive(Clone, Copy, Debug)]
pub struct Target {
    /// The rustup target triple.
    pub triple: &'static str,
    /// QEMU's `-cpu`.
    pub cpu: &'static str,
    /// QEMU's `-machine`.
    pub machine: &'static str,
    /// A short name for reports.
    pub core: &'static str,
}

/// The supported targets; the first is the default.
pub const TARGETS: [Target; 3] = [
    Target {
        triple: "thumbv7em-none-eabihf",
        cpu: "cortex-m4",
        machine: "mps2-an386",
        core: "Cortex-M4F",
    },
    Target {
        triple: "thumbv7m-none-eabi",
        cpu: "cortex-m3",
        machine: "mps2-an385",
        core: "Cortex-M3",
    },
    Target {
        triple: "thumbv6m-none-eabi",
        cpu: "cortex-m0",
        machine: "microbit",
        core: "Cortex-M0",
    },
];

/// Looks a target up by triple.
pub fn target(triple: &str) -> Result<Target, String> {
    TARGETS
        .iter()
        .copied()
        .find(|t| t.triple == triple)
        .ok_or_else(|| {
            let known: Vec<&str> = TARGETS.iter().map(|t| t.triple).collect();
            format!("unknown target `{triple}` (known: {})", known.join(", "))
        })
}

/// Builds a firmware example in release mode (features `firmware` and
/// `hal`); returns the ELF's path.
pub fn build(example: &str, target: Target) -> Result<PathBuf, String> {
    // `cycle_budget` runs every row unless `cargo xtask profile --rows`
    // names some.
    build_with_env(example, target, &[(PROFILE_ROWS_VARIABLE, None)])
}

/// The build-time variable that restricts `cycle_budget` to some rows
/// (comma-separated names): `cargo xtask profile --rows`.
pub const PROFILE_ROWS_VARIABLE: &str = "BREAKAWAY_PROFILE_ROWS";

/// As [`build`], with environment variables for the build (read by the
/// example with `option_env!`: cargo rebuilds it when they change); `None`
/// removes a variable.
pub fn build_with_env(
    example: &str,
    target: Target,
    envs: &[(&str, Option<&str>)],
) -> Result<PathBuf, String> {
    let mut command = cargo();
    for &(name, value) in envs {
        match value {
            Some(value) => command.env(name, value),
            None => command.env_remove(name),
        };
    }
    run(command.args([
        "build",
        "--quiet",
        "--release",
        "-p",
        "breakaway-firmware",
        "--features",
        "qemu",
        "--example",
        example,
        "--target",
        target.triple,
    ]))?;
    // Cargo's target directory: CARGO_TARGET_DIR when set, else ./target.
    let target_dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|dir| {
            if dir.is_absolute() {
                dir
            } else {
                root().join(dir)
            }
        })
        .unwrap_or_else(|| root().join("target"));
    Ok(target_dir
        .join(target.triple)
        .join("release")
        .join("examples")
        .join(example))
}

/// The longest run of an example [s] before it counts as hung.
const RUN_LIMIT: Duration = Duration::from_secs(120);

/// Runs an ELF under QEMU with semihosting; returns its standard output. A
/// non-zero exit status (panic, HardFault, failed check) or a run longer
/// than [`RUN_LIMIT`] is an error.
pub fn execute(elf: &PathBuf, target: Target) -> Result<String, String> {
    let mut child = spawn(elf, target, &[], Stdio::piped())?;
    let mut stdout = child.stdout.take().ok_or("no stdout pipe")?;
    let reader = thread::spawn(move || {
        let mut text = String::new();
        let _ = stdout.read_to_string(&mut text);
        text
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if start.elapsed() > RUN_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "{} on {} did not finish within {} s",
                elf.display(),
                target.machine,
                RUN_LIMIT.as_secs()
            ));
        }
        thread::sleep(Duration::from_millis(20));
    };
    let text = reader.join().unwrap_or_default();
    if status.success() {
        Ok(text)
    } else {
        let mut stderr = String::new();
        if let Some(mut e) = child.stderr.take() {
            let _ = e.read_to_string(&mut stderr);
        }
        let tail: Vec<&str> = text.lines().rev().take(3).collect();
        Err(format!(
            "{} on {} exited with {status}: {} {}",
            elf.display(),
            target.machine,
            tail.into_iter().rev().collect::<Vec<_>>().join(" | "),
            stderr.lines().next().unwrap_or("")
        ))
    }
}

/// Starts an ELF under QEMU with semihosting and extra QEMU arguments, its
/// standard output to `stdout`, its standard error piped.
pub fn spawn(
    elf: &PathBuf,
    target: Target,
    extra: &[&str],
    stdout: Stdio,
) -> Result<Child, String> {
    Command::new("qemu-system-arm")
        .args(["-cpu", target.cpu, "-machine", target.machine])
        .args(["-nographic", "-monitor", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .args(extra)
        .arg("-kernel")
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| {
            format!("could not start qemu-system-arm ({e}); install it: apt-get install qemu-system-arm")
        })
}

/// Builds and runs an example; returns its standard output.
pub fn run_example(example: &str, target: Target) -> Result<String, String> {
    let elf = build(example, target)?;
    eprintln!(
        "xtask: running {example} on {} ({})",
        target.core, target.machine
    );
    execute(&elf, target)
}
