//! `cargo xtask profile`: deterministic instruction counts per call under
//! QEMU, with a cycle estimate.
//!
//! The `cycle_budget` example calls each hot function through a `bench_*`
//! wrapper. QEMU runs it with one guest instruction per translation block
//! (`-singlestep` on QEMU 7, `-accel tcg,one-insn-per-tb=on` on 8 and
//! later) and logs every executed instruction (`-d exec,nochain`) and the
//! disassembly of each block when it is translated (`-d in_asm`). A call
//! starts at the first instruction of `bench_X` reached by a `bl`/`blx`; it
//! ends when the program counter comes back to the instruction after that
//! call. Everything executed in between (callees such as `libm` included)
//! counts, the call and the return instructions too.
//!
//! Estimated cycles apply per-instruction timings to the executed stream:
//! for the Cortex-M4 and Cortex-M3, the instruction timing tables of the
//! ARM Cortex-M4 Technical Reference Manual (ARM DDI 0439B, Table 3-1
//! "Cortex-M4 instruction set summary", and Table 7-1 "FPU instruction set"
//! for the floating-point unit); for the Cortex-M0, Table 3-1 of the
//! Cortex-M0 Technical Reference Manual (ARM DDI 0432C). Pipeline refills
//! after a taken branch count P = 2 cycles (the manual gives 1–3); a
//! divide counts 7 (2–12, data dependent). QEMU models no pipeline, caches,
//! flash wait states or bus contention: on a 168 MHz part running from flash
//! the real figure is higher; the DWT cycle counter on hardware is the
//! judge.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::process::Command;
use std::time::Duration;

use crate::qemu::{self, Target};

/// Rows of the profile: the wrapper symbol and the reported name.
const ROWS: [(&str, &str); 9] = [
    ("bench_update_f32", "update_f32"),
    ("bench_stribeck_f32", "stribeck_f32"),
    ("bench_shape_f32", "shape_f32"),
    ("bench_breakaway_f32", "breakaway_f32"),
    ("bench_naive_libm_update", "naive_libm_update"),
    ("bench_update_fixed", "update_fixed"),
    ("bench_breakaway_fixed", "breakaway_fixed"),
    ("bench_new_model_f32", "new_model_f32"),
    ("bench_new_model_fixed", "new_model_fixed"),
];

/// Where the counted part of the trace ends: the harness's stack pass.
const END_SYMBOL: &str = "stack_pass";

/// Options of `cargo xtask profile`.
#[derive(Clone, Debug)]
pub struct Options {
    /// Targets to profile (all when none is given).
    pub targets: Vec<Target>,
    /// Control-loop rate [Hz].
    pub budget_hz: f64,
    /// CPU clock [Hz].
    pub cpu_hz: f64,
    /// Print JSON instead of the table.
    pub json: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            targets: qemu::TARGETS.to_vec(),
            budget_hz: 20_000.0,
            cpu_hz: 168_000_000.0,
            json: false,
        }
    }
}

impl Options {
    /// Parses `[--target T] [--budget-hz H] [--cpu-hz H] [--json]`.
    pub fn parse(args: &[String]) -> Result<Self, String> {
        let mut options = Options::default();
        let mut targets = Vec::new();
        let mut args = args.iter();
        while let Some(arg) = args.next() {
            let mut value = |name: &str| {
                args.next()
                    .cloned()
                    .ok_or_else(|| format!("profile: {name} needs a value"))
            };
            let number = |name: &str, text: String| {
                text.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite() && *x > 0.0)
                    .ok_or_else(|| {
                        format!("profile: {name} must be a positive number, got `{text}`")
                    })
            };
            match arg.as_str() {
                "--target" => targets.push(qemu::target(&value("--target")?)?),
                "--budget-hz" => options.budget_hz = number("--budget-hz", value("--budget-hz")?)?,
                "--cpu-hz" => options.cpu_hz = number("--cpu-hz", value("--cpu-hz")?)?,
                "--json" => options.json = true,
                other => return Err(format!("profile: unknown argument `{other}`")),
            }
        }
        if !targets.is_empty() {
            options.targets = targets;
        }
        Ok(options)
    }
}

/// The measured cost of one function on one target.
#[derive(Clone, Debug)]
pub struct Row {
    pub target: &'static str,
    pub name: &'static str,
    pub calls: usize,
    /// Mean instructions per call.
    pub instructions: f64,
    pub max_instructions: u64,
    /// Mean estimated cycles per call.
    pub est_cycles: f64,
    /// Deepest stack below the call [bytes], from the painted stack.
    pub max_stack_bytes: u64,
}

/// Runs the profile and prints it.
pub fn run(options: &Options) -> Result<(), String> {
    let mut rows = Vec::new();
    for &target in &options.targets {
        rows.extend(measure(target)?);
    }
    if options.json {
        let items: Vec<serde_json::Value> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "target": r.target,
                    "name": r.name,
                    "instructions": r.instructions,
                    "max_instructions": r.max_instructions,
                    "est_cycles": r.est_cycles,
                    "max_stack_bytes": r.max_stack_bytes,
                })
            })
            .collect();
        let text = serde_json::to_string_pretty(&items).map_err(|e| e.to_string())?;
        println!("{text}");
    } else {
        print_table(&rows, options);
        print_model_sizes();
    }
    Ok(())
}

/// Runs the profile on every target as part of `cargo xtask test`: the
/// pipeline must work and the figures must be plausible; the targets are
/// reported, not enforced.
pub fn check_targets() -> Result<(), String> {
    let mut rows = Vec::new();
    for target in qemu::TARGETS {
        let measured = measure(target)?;
        for row in &measured {
            if row.calls == 0 || row.instructions < 5.0 || row.max_stack_bytes < 4 {
                return Err(format!("profile: implausible row {row:?}"));
            }
        }
        rows.extend(measured);
    }
    print_table(&rows, &Options::default());
    Ok(())
}

/// RAM of a fixed-point model per table resolution K (points per octave of
/// the S table). The layout has no pointers and no `usize`, so the host's
/// size is the target's.
fn print_model_sizes() {
    use breakaway::{Model, Q16};
    use std::mem::size_of;
    println!("Model<Q16<K>> in RAM (S table 31·K cells of 2 bytes, in the model); the g table is shared, in flash:");
    println!("{:>5} {:>10}", "K", "RAM bytes");
    for (k, bytes) in [
        (4, size_of::<Model<Q16<4>>>()),
        (8, size_of::<Model<Q16<8>>>()),
        (16, size_of::<Model<Q16<16>>>()),
        (32, size_of::<Model<Q16<32>>>()),
        (64, size_of::<Model<Q16<64>>>()),
    ] {
        println!("{k:>5} {bytes:>10}");
    }
    println!(
        "g table (flash, every K): {} bytes\n",
        breakaway::fixed_point::SHAPE_TABLE_BYTES
    );
}

fn print_table(rows: &[Row], options: &Options) {
    let period = options.cpu_hz / options.budget_hz;
    println!(
        "Instructions per call under QEMU (exact, deterministic) and estimated cycles;\n\
         budget: {:.0} Hz loop at {:.0} MHz = {:.0} cycles per period.\n",
        options.budget_hz,
        options.cpu_hz / 1e6,
        period
    );
    println!(
        "{:<22} {:<20} {:>7} {:>10} {:>9} {:>11} {:>8} {:>7}",
        "target",
        "function",
        "calls",
        "instr/call",
        "max instr",
        "est. cycles",
        "budget",
        "stack B"
    );
    for r in rows {
        println!(
            "{:<22} {:<20} {:>7} {:>10.1} {:>9} {:>11.1} {:>7.2}% {:>7}",
            r.target,
            r.name,
            r.calls,
            r.instructions,
            r.max_instructions,
            r.est_cycles,
            100.0 * r.est_cycles / period,
            r.max_stack_bytes
        );
    }
    println!();
}

/// QEMU's switch for one instruction per translation block.
fn singlestep_args() -> Vec<&'static str> {
    let version = Command::new("qemu-system-arm")
        .arg("--version")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    let major = version
        .split("version ")
        .nth(1)
        .and_then(|v| v.split('.').next())
        .and_then(|m| m.trim().parse::<u32>().ok())
        .unwrap_or(7);
    if major >= 8 {
        vec!["-accel", "tcg,one-insn-per-tb=on"]
    } else {
        vec!["-singlestep"]
    }
}

/// Profiles `cycle_budget` on one target.
pub fn measure(target: Target) -> Result<Vec<Row>, String> {
    let elf = qemu::build("cycle_budget", target)?;
    let log = std::env::temp_dir().join(format!("breakaway-profile-{}.log", target.triple));
    let log_arg = log.to_string_lossy().into_owned();
    let mut args = singlestep_args();
    args.extend(["-d", "in_asm,exec,nochain", "-D", &log_arg]);
    eprintln!(
        "xtask: profiling cycle_budget on {} ({})",
        target.core, target.machine
    );
    let output = qemu::execute(&elf, target, &args, Duration::from_secs(900))?;
    let rows = parse_trace(&log, target);
    let _ = std::fs::remove_file(&log);
    let mut rows = rows?;
    for row in &mut rows {
        row.max_stack_bytes = output
            .lines()
            .filter_map(|line| line.strip_prefix("stack "))
            .find_map(|rest| {
                let (name, bytes) = rest.split_once(' ')?;
                (name == row.name).then(|| bytes.trim().parse().ok())?
            })
            .ok_or_else(|| {
                format!(
                    "profile: no stack figure for {} on {}",
                    row.name, target.triple
                )
            })?;
    }
    Ok(rows)
}

/// One decoded instruction.
#[derive(Clone, Debug)]
struct Insn {
    size: u32,
    mnemonic: String,
    operands: String,
}

/// A call being counted.
struct Open {
    row: usize,
    return_pc: u32,
    instructions: u64,
    cycles: u64,
}

#[derive(Default, Clone)]
struct Tally {
    calls: Vec<(u64, u64)>,
}

fn parse_trace(path: &std::path::Path, target: Target) -> Result<Vec<Row>, String> {
    let file = File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut insns: HashMap<u32, Insn> = HashMap::new();
    let mut tallies = vec![Tally::default(); ROWS.len()];
    let mut open: Option<Open> = None;
    // The previous executed instruction: pc, and its symbol.
    let mut prev: Option<(u32, String)> = None;
    let m0 = target.triple.starts_with("thumbv6m");
    for line in BufReader::new(file).lines() {
        let line = line.map_err(|e| e.to_string())?;
        if let Some((pc, insn)) = parse_in_asm(&line) {
            insns.insert(pc, insn);
            continue;
        }
        let Some((pc, symbol)) = parse_exec(&line) else {
            continue;
        };
        if symbol == END_SYMBOL {
            break;
        }
        // Charge the previous instruction now that we know where it went.
        if let (Some(call), Some((prev_pc, _))) = (open.as_mut(), prev.as_ref()) {
            if let Some(insn) = insns.get(prev_pc) {
                let taken = pc != prev_pc.wrapping_add(insn.size);
                call.cycles += u64::from(cycles(insn, taken, m0));
            }
        }
        if let Some(call) = open.as_ref() {
            if pc == call.return_pc {
                if let Some(call) = open.take() {
                    tallies[call.row]
                        .calls
                        .push((call.instructions, call.cycles));
                }
            }
        }
        if open.is_none() {
            if let Some(row) = ROWS.iter().position(|(sym, _)| *sym == symbol) {
                // Entered by a call from another function?
                if let Some((prev_pc, prev_symbol)) = prev.as_ref() {
                    let call = insns.get(prev_pc).filter(|i| i.mnemonic.starts_with("bl"));
                    if let (Some(call), true) = (call, prev_symbol != &symbol) {
                        open = Some(Open {
                            row,
                            return_pc: prev_pc.wrapping_add(call.size),
                            // The call instruction itself.
                            instructions: 1,
                            cycles: u64::from(cycles(call, true, m0)),
                        });
                    }
                }
            }
        }
        if let Some(call) = open.as_mut() {
            call.instructions += 1;
        }
        prev = Some((pc, symbol));
    }
    ROWS.iter()
        .zip(tallies)
        .map(|(&(symbol, name), tally)| {
            let n = tally.calls.len();
            if n == 0 {
                return Err(format!("profile: no call of {symbol} found in the trace"));
            }
            let total: u64 = tally.calls.iter().map(|c| c.0).sum();
            let cycles: u64 = tally.calls.iter().map(|c| c.1).sum();
            Ok(Row {
                target: target.triple,
                name,
                calls: n,
                instructions: total as f64 / n as f64,
                max_instructions: tally.calls.iter().map(|c| c.0).max().unwrap_or(0),
                est_cycles: cycles as f64 / n as f64,
                max_stack_bytes: 0,
            })
        })
        .collect()
}

/// `0x000004c0:  f005 ffab  bl       #0x635a` → (pc, insn).
fn parse_in_asm(line: &str) -> Option<(u32, Insn)> {
    let rest = line.strip_prefix("0x")?;
    let (address, rest) = rest.split_once(":  ")?;
    let pc = u32::from_str_radix(address, 16).ok()?;
    let mut halfwords = 0;
    let mut tail = rest.trim_start();
    loop {
        let (word, after) = tail.split_once(' ').unwrap_or((tail, ""));
        if word.len() == 4 && word.chars().all(|c| c.is_ascii_hexdigit()) {
            halfwords += 1;
            tail = after.trim_start();
        } else {
            break;
        }
    }
    let (mnemonic, operands) = tail.split_once(' ').unwrap_or((tail, ""));
    Some((
        pc,
        Insn {
            size: 2 * halfwords,
            mnemonic: mnemonic.to_string(),
            operands: operands.trim().to_string(),
        },
    ))
}

/// `Trace 0: 0x7fa2b4000100 [00800408/00000400/00000110/ff000201] Reset`
/// → (pc, symbol).
fn parse_exec(line: &str) -> Option<(u32, String)> {
    let rest = line.strip_prefix("Trace ")?;
    let (_, rest) = rest.split_once('[')?;
    let (fields, symbol) = rest.split_once(']')?;
    let pc = u32::from_str_radix(fields.split('/').nth(1)?, 16).ok()?;
    Some((pc, symbol.trim().to_string()))
}

/// Registers in a list such as `{r4, r5, r7, lr}` or `{d8-d11}`.
fn register_count(operands: &str) -> u32 {
    let Some(list) = operands.split('{').nth(1).and_then(|l| l.split('}').next()) else {
        return 1;
    };
    list.split(',')
        .map(|item| {
            let item = item.trim();
            match item.split_once('-') {
                Some((a, b)) => {
                    let n = |s: &str| {
                        s.trim_start_matches(|c: char| c.is_alphabetic())
                            .parse::<u32>()
                            .ok()
                    };
                    match (n(a), n(b)) {
                        (Some(a), Some(b)) if b >= a => b - a + 1,
                        _ => 1,
                    }
                }
                None => 1,
            }
        })
        .sum()
}

/// Estimated cycles of one executed instruction (see the module doc).
fn cycles(insn: &Insn, taken: bool, m0: bool) -> u32 {
    const P: u32 = 2;
    let base = insn.mnemonic.split('.').next().unwrap_or("");
    let ops = insn.operands.as_str();
    let conditions = [
        "eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt", "gt",
        "le",
    ];
    let is_cond_branch =
        base.len() == 3 && base.starts_with('b') && conditions.contains(&&base[1..]);
    let writes_pc = ops.contains("pc}") || ops.starts_with("pc,");
    if m0 {
        return match base {
            "b" => 3,
            _ if is_cond_branch && taken => 3,
            _ if is_cond_branch => 1,
            "bl" => 4,
            "bx" | "blx" => 3,
            "push" | "stm" | "stmia" | "ldm" | "ldmia" => 1 + register_count(ops),
            "pop" => register_count(ops) + if writes_pc { 3 } else { 1 },
            _ if base.starts_with("ldr") || base.starts_with("str") => 2,
            _ => 1,
        };
    }
    match base {
        "b" | "bl" | "bx" | "blx" => 1 + P,
        _ if (is_cond_branch || base == "cbz" || base == "cbnz") && taken => 1 + P,
        _ if is_cond_branch || base == "cbz" || base == "cbnz" => 1,
        "push" | "stm" | "stmia" | "stmdb" | "ldm" | "ldmia" | "ldmdb" => 1 + register_count(ops),
        "pop" => 1 + register_count(ops) + if writes_pc { P } else { 0 },
        "ldrd" | "strd" => 3,
        "sdiv" | "udiv" => 7,
        "mla" | "mls" => 2,
        "vdiv" | "vsqrt" => 14,
        "vmla" | "vmls" | "vnmla" | "vnmls" | "vfma" | "vfms" | "vfnma" | "vfnms" => 3,
        "vldr" | "vstr" => 2,
        "vpush" | "vpop" | "vldm" | "vldmia" | "vstm" | "vstmia" | "vstmdb" => {
            1 + register_count(ops)
        }
        _ if base.starts_with("ldr") => {
            if writes_pc {
                2 + P
            } else {
                2
            }
        }
        _ if base.starts_with("str") => 2,
        _ => 1,
    }
}
