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
//! The example runs its passes in groups, one per shape exponent δ: every
//! row with the Fig. 5 model (δ = 1), then the rows whose cost depends on δ
//! ([`DELTA_ROWS`]) at each δ of [`EXTRA_DELTAS`], on the same trajectory. A
//! group starts with a call of its marker, `profile_delta_<δ>` with `_` for
//! the decimal point; a call is attributed to the δ of the last marker
//! entered before it. Each row reports its δ: the δ of the model it uses
//! (1 for the rows that do not depend on δ).
//!
//! `--rows a,b` restricts the profile to some rows: the example is built
//! with `BREAKAWAY_PROFILE_ROWS=a,b` and runs only their passes (the
//! traced run is then short: on the M0 one row took one minute, build
//! included, against three and a half for every row).
//!
//! `--listings` prints, after the table, for every row at δ = 1 and every
//! distinct instruction count of its calls, how many calls took that count
//! and the executed instructions of the first of them (address, function,
//! disassembly as QEMU logged it): one listing per path through the code.
//! The counts times the calls sum to the row's total.
//!
//! The example runs twice per target. A plain run (no log, well under a
//! second) gives what it prints: the stack depths of its stack pass. The
//! traced run writes one log line per executed instruction, which is what
//! the profile's time goes into (QEMU writes each line with its own system
//! call); the log is read while QEMU writes it, and QEMU is stopped as soon
//! as the trace reaches `stack_pass`, so the stack pass and what follows it
//! are never logged. The log's name carries the process id: profiles may
//! run side by side.
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
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::qemu::{self, Target};

/// Rows of the profile: the wrapper symbol and the reported name.
pub(crate) const ROWS: [(&str, &str); 9] = [
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

/// The rows measured at every δ (names of [`ROWS`]).
const DELTA_ROWS: [&str; 3] = ["update_f32", "naive_libm_update", "update_fixed"];

/// The shape exponents of the groups after the first (δ = 1): each runs
/// [`DELTA_ROWS`].
const EXTRA_DELTAS: [f64; 3] = [0.7, 1.3, 2.0];

/// The δ of the first group, every row's.
const BASE_DELTA: f64 = 1.0;

/// The prefix of the δ markers: `profile_delta_1_3` marks δ = 1.3.
const DELTA_MARKER: &str = "profile_delta_";

/// Where the counted part of the trace ends: the harness's stack pass.
const END_SYMBOL: &str = "stack_pass";

/// δ from a marker's symbol (`profile_delta_0_7` → 0.7).
fn marker_delta(symbol: &str) -> Option<f64> {
    symbol
        .strip_prefix(DELTA_MARKER)?
        .replace('_', ".")
        .parse()
        .ok()
}

/// Every (row, δ) the profile reports, in the order it reports them: the
/// rows of [`ROWS`] at δ = 1 (today's rows, first, so that the first row of
/// a name is still its δ = 1 row), then each of [`DELTA_ROWS`] at every δ
/// of [`EXTRA_DELTAS`]; only the rows named in `only` when it is not empty.
fn expected_rows(only: &[String]) -> Vec<(usize, f64)> {
    let selected = |i: usize| only.is_empty() || only.iter().any(|n| n == ROWS[i].1);
    let mut rows: Vec<(usize, f64)> = (0..ROWS.len())
        .filter(|&i| selected(i))
        .map(|i| (i, BASE_DELTA))
        .collect();
    for name in DELTA_ROWS {
        if let Some(i) = ROWS.iter().position(|(_, n)| *n == name) {
            if selected(i) {
                rows.extend(EXTRA_DELTAS.iter().map(|&delta| (i, delta)));
            }
        }
    }
    rows
}

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
    /// Only these rows (names of [`ROWS`]; all when empty): the example is
    /// built with the others left out, so that the traced run is short.
    pub rows: Vec<String>,
    /// Print the executed instructions of one call per distinct count.
    pub listings: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            targets: qemu::TARGETS.to_vec(),
            budget_hz: 20_000.0,
            cpu_hz: 168_000_000.0,
            json: false,
            rows: Vec::new(),
            listings: false,
        }
    }
}

/// The measured cost of one function on one target.
#[derive(Clone, Debug)]
pub struct Row {
    pub target: &'static str,
    pub name: &'static str,
    /// The shape exponent δ of the model the row uses.
    pub delta: f64,
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
    let mut listings_text = String::new();
    for &target in &options.targets {
        let (measured, listings) = measure(target, &options.rows, options.listings)?;
        rows.extend(measured);
        listings_text.push_str(&listings);
    }
    if options.json {
        let items: Vec<serde_json::Value> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "target": r.target,
                    "name": r.name,
                    "delta": r.delta,
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
    // Not in the JSON: on the error stream then.
    if options.json {
        eprint!("{listings_text}");
    } else {
        print!("{listings_text}");
    }
    Ok(())
}

/// Runs the profile on every target as part of `cargo xtask test`: the
/// pipeline must work and the figures must be plausible; the targets are
/// reported, not enforced.
pub fn check_targets() -> Result<(), String> {
    let mut rows = Vec::new();
    for target in qemu::TARGETS {
        let (measured, _) = measure(target, &[], false)?;
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
    use breakaway::{Model, TableCurves, Q16};
    use std::mem::size_of;
    println!("Model<Q16, TableCurves<K>> in RAM (S table 31·K cells of 2 bytes, in the model); the g table is shared, in flash:");
    println!("{:>5} {:>10}", "K", "RAM bytes");
    for (k, bytes) in [
        (4, size_of::<Model<Q16, TableCurves<4>>>()),
        (8, size_of::<Model<Q16, TableCurves<8>>>()),
        (16, size_of::<Model<Q16, TableCurves<16>>>()),
        (32, size_of::<Model<Q16, TableCurves<32>>>()),
        (64, size_of::<Model<Q16, TableCurves<64>>>()),
    ] {
        println!("{k:>5} {bytes:>10}");
    }
    println!(
        "g table (flash, every K): {} bytes\n",
        breakaway::fixed_point::SHAPE_TABLE_BYTES
    );
    println!(
        "Model<f32> in RAM: {} bytes, of which the Stribeck table ({} segments) {} bytes; \
         the g tables are shared, in flash: {} bytes\n",
        size_of::<Model<f32>>(),
        breakaway::curves::STRIBECK_SEGMENTS,
        breakaway::curves::STRIBECK_TABLE_BYTES,
        breakaway::curves::SHAPE_TABLE_BYTES
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
        "{:<22} {:<20} {:>4} {:>7} {:>10} {:>9} {:>11} {:>8} {:>7}",
        "target",
        "function",
        "δ",
        "calls",
        "instr/call",
        "max instr",
        "est. cycles",
        "budget",
        "stack B"
    );
    for r in rows {
        println!(
            "{:<22} {:<20} {:>4} {:>7} {:>10.1} {:>9} {:>11.1} {:>7.2}% {:>7}",
            r.target,
            r.name,
            r.delta,
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

/// Profiles `cycle_budget` on one target: a plain run for the figures the
/// example prints (the stack depths), then a traced run for the instruction
/// counts, read while QEMU writes it and stopped where the counted part ends
/// (the stack pass and what follows it are never logged in full).
///
/// `only` restricts the profile to some rows (all when empty): the example
/// is built with [`qemu::PROFILE_ROWS_VARIABLE`] naming them and runs only their passes.
/// With `listings`, the text of [`Trace::listings`] comes back too (empty
/// without).
pub fn measure(
    target: Target,
    only: &[String],
    listings: bool,
) -> Result<(Vec<Row>, String), String> {
    let filter = only.join(",");
    // Unset for every row: the same build as `cargo xtask qemu`'s.
    let value = (!only.is_empty()).then_some(filter.as_str());
    let elf = qemu::build_with_env(
        "cycle_budget",
        target,
        &[(qemu::PROFILE_ROWS_VARIABLE, value)],
    )?;
    eprintln!(
        "xtask: profiling cycle_budget on {} ({})",
        target.core, target.machine
    );
    // Deterministic: tracing changes no guest state, so the plain run
    // prints what the traced run would.
    let output = qemu::execute(&elf, target)?;
    // One log per process: profiles may run side by side.
    let log = std::env::temp_dir().join(format!(
        "breakaway-profile-{}-{}.log",
        target.triple,
        std::process::id()
    ));
    let _ = std::fs::remove_file(&log);
    let log_arg = log.to_string_lossy().into_owned();
    let mut args = singlestep_args();
    args.extend(["-d", "in_asm,exec,nochain", "-D", &log_arg]);
    let mut child = qemu::spawn(&elf, target, &args, Stdio::null())?;
    let traced = follow_trace(
        &log,
        &mut child,
        Trace::new(target, only, listings),
        Duration::from_secs(900),
    );
    // Done with QEMU (running or not): it would go on logging the stack pass.
    let _ = child.kill();
    let _ = child.wait();
    let _ = std::fs::remove_file(&log);
    let trace = traced?;
    let listing_text = if listings {
        trace.listings()
    } else {
        String::new()
    };
    let mut rows = trace.rows()?;
    for row in &mut rows {
        row.max_stack_bytes = output
            .lines()
            .filter_map(|line| line.strip_prefix("stack "))
            .find_map(|rest| {
                let mut fields = rest.split_whitespace();
                let (name, delta) = (fields.next()?, fields.next()?.parse::<f64>().ok()?);
                (name == row.name && delta == row.delta).then(|| fields.next()?.parse().ok())?
            })
            .ok_or_else(|| {
                format!(
                    "profile: no stack figure for {} at δ = {} on {}",
                    row.name, row.delta, target.triple
                )
            })?;
    }
    Ok((rows, listing_text))
}

/// Reads QEMU's log at `path` as `child` writes it, up to [`END_SYMBOL`],
/// and returns the trace. An error if QEMU stops before the log reaches it or
/// the run takes longer than `limit`.
fn follow_trace(
    path: &Path,
    child: &mut Child,
    mut trace: Trace,
    limit: Duration,
) -> Result<Trace, String> {
    let target = trace.target;
    let start = Instant::now();
    let pause = Duration::from_millis(2);
    let timeout = || {
        format!(
            "profile: the traced run on {} did not reach {END_SYMBOL} within {} s",
            target.machine,
            limit.as_secs()
        )
    };
    let stopped = |child: &mut Child, status: std::process::ExitStatus| {
        let mut stderr = String::new();
        if let Some(mut e) = child.stderr.take() {
            let _ = e.read_to_string(&mut stderr);
        }
        format!(
            "profile: QEMU on {} stopped ({status}) before the trace reached {END_SYMBOL}: {}",
            target.machine,
            stderr.lines().next().unwrap_or("")
        )
    };
    // QEMU creates the log when it starts.
    let file = loop {
        if let Ok(file) = File::open(path) {
            break file;
        }
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            return Err(stopped(child, status));
        }
        if start.elapsed() > limit {
            return Err(timeout());
        }
        std::thread::sleep(pause);
    };
    let mut reader = BufReader::with_capacity(1 << 20, file);
    let mut line = String::new();
    // Once QEMU has exited, what remains in the log is read to its end.
    let mut exited = None;
    loop {
        let n = reader
            .read_line(&mut line)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        if line.ends_with('\n') {
            if trace.feed(&line)? {
                return Ok(trace);
            }
            line.clear();
        } else if n == 0 {
            // The end of what QEMU has written so far.
            if let Some(status) = exited {
                return Err(stopped(child, status));
            }
            exited = child.try_wait().map_err(|e| e.to_string())?;
            if exited.is_none() {
                if start.elapsed() > limit {
                    return Err(timeout());
                }
                std::thread::sleep(pause);
            }
        }
    }
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
    /// Index into [`ROWS`].
    row: usize,
    /// δ of the group the call belongs to.
    delta: f64,
    return_pc: u32,
    instructions: u64,
    cycles: u64,
    /// The executed instructions' addresses, when listings are kept.
    pcs: Vec<u32>,
}

#[derive(Default, Clone)]
struct Tally {
    calls: Vec<(u64, u64)>,
    /// The executed addresses of the first call of each instruction count
    /// (when listings are kept).
    firsts: std::collections::BTreeMap<u64, Vec<u32>>,
}

/// The state of the trace parser, fed one log line at a time.
struct Trace {
    target: Target,
    m0: bool,
    /// Every instruction translated so far, by address, with its estimated
    /// cycles when it falls through and when it branches.
    insns: HashMap<u32, (Insn, [u32; 2])>,
    /// The (row, δ) pairs reported, and their calls.
    expected: Vec<(usize, f64)>,
    tallies: Vec<Tally>,
    open: Option<Open>,
    /// δ of the last marker entered.
    delta: Option<f64>,
    /// The previous executed instruction's address.
    prev_pc: Option<u32>,
    /// The previous executed instruction's symbol.
    prev_symbol: String,
    /// Keep the executed addresses of calls (`--listings`).
    listings: bool,
    /// The symbol of each executed address (for the listings).
    symbols: HashMap<u32, String>,
}

impl Trace {
    fn new(target: Target, only: &[String], listings: bool) -> Self {
        let expected = expected_rows(only);
        Self {
            target,
            m0: target.triple.starts_with("thumbv6m"),
            insns: HashMap::new(),
            tallies: vec![Tally::default(); expected.len()],
            expected,
            open: None,
            delta: None,
            prev_pc: None,
            prev_symbol: String::new(),
            listings,
            symbols: HashMap::new(),
        }
    }

    /// Takes one line of the log; `true` once the counted part has ended
    /// (the first instruction of [`END_SYMBOL`]).
    fn feed(&mut self, line: &str) -> Result<bool, String> {
        let line = line.trim_end();
        if let Some((pc, insn)) = parse_in_asm(line) {
            let cost = [cycles(&insn, false, self.m0), cycles(&insn, true, self.m0)];
            self.insns.insert(pc, (insn, cost));
            return Ok(false);
        }
        let Some((pc, symbol)) = parse_exec(line) else {
            return Ok(false);
        };
        // In another function than the previous instruction.
        let entered = symbol != self.prev_symbol;
        if entered && symbol == END_SYMBOL {
            return Ok(true);
        }
        // Charge the previous instruction now that we know where it went.
        if let (Some(call), Some(prev_pc)) = (self.open.as_mut(), self.prev_pc) {
            if let Some((insn, cost)) = self.insns.get(&prev_pc) {
                let taken = pc != prev_pc.wrapping_add(insn.size);
                call.cycles += u64::from(cost[usize::from(taken)]);
            }
        }
        if let Some(call) = self.open.as_ref() {
            if pc == call.return_pc {
                if let Some(call) = self.open.take() {
                    let slot = self
                        .expected
                        .iter()
                        .position(|&(row, delta)| row == call.row && delta == call.delta)
                        .ok_or_else(|| {
                            format!(
                                "profile: a call of {} at δ = {}, a row the profile does not report",
                                ROWS[call.row].0, call.delta
                            )
                        })?;
                    let tally = &mut self.tallies[slot];
                    tally.calls.push((call.instructions, call.cycles));
                    if self.listings {
                        tally.firsts.entry(call.instructions).or_insert(call.pcs);
                    }
                }
            }
        }
        if self.open.is_none() && entered {
            if let Some(d) = marker_delta(symbol) {
                self.delta = Some(d);
            }
            // Entered by a call?
            let row = ROWS.iter().position(|(sym, _)| *sym == symbol);
            let call = self
                .prev_pc
                .and_then(|prev_pc| Some((prev_pc, self.insns.get(&prev_pc)?)))
                .filter(|(_, (insn, _))| insn.mnemonic.starts_with("bl"));
            if let (Some(row), Some((prev_pc, (call, cost)))) = (row, call) {
                let delta = self
                    .delta
                    .ok_or_else(|| format!("profile: a call of {symbol} before any δ marker"))?;
                self.open = Some(Open {
                    row,
                    delta,
                    return_pc: prev_pc.wrapping_add(call.size),
                    // The call instruction itself.
                    instructions: 1,
                    cycles: u64::from(cost[1]),
                    pcs: if self.listings {
                        vec![prev_pc]
                    } else {
                        Vec::new()
                    },
                });
            }
        }
        if let Some(call) = self.open.as_mut() {
            call.instructions += 1;
            if self.listings {
                call.pcs.push(pc);
                self.symbols.entry(pc).or_insert_with(|| symbol.to_string());
            }
        }
        self.prev_pc = Some(pc);
        if entered {
            self.prev_symbol.clear();
            self.prev_symbol.push_str(symbol);
        }
        Ok(false)
    }

    /// For every row at δ = 1 and every distinct instruction count of its
    /// calls: the count, the number of calls with it, and the executed
    /// instructions of the first such call, one per line (address, function,
    /// mnemonic, operands; the call instruction's function is the caller).
    fn listings(&self) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        for (&(row, delta), tally) in self.expected.iter().zip(&self.tallies) {
            if delta != BASE_DELTA {
                continue;
            }
            for (&count, pcs) in &tally.firsts {
                let calls = tally.calls.iter().filter(|c| c.0 == count).count();
                let _ = writeln!(
                    out,
                    "listing {} {} δ = 1: {count} instructions, {calls} of {} calls",
                    self.target.triple,
                    ROWS[row].1,
                    tally.calls.len()
                );
                for pc in pcs {
                    let symbol = self.symbols.get(pc).map_or("(caller)", String::as_str);
                    let (mnemonic, operands) = self.insns.get(pc).map_or(("?", ""), |(i, _)| {
                        (i.mnemonic.as_str(), i.operands.as_str())
                    });
                    let _ = writeln!(out, "  {pc:#010x} {symbol:<32} {mnemonic:<8} {operands}");
                }
            }
        }
        out
    }

    /// The rows, in the order of [`expected_rows`].
    fn rows(&self) -> Result<Vec<Row>, String> {
        let target = self.target;
        self.expected
            .iter()
            .zip(&self.tallies)
            .map(|(&(row, delta), tally)| {
                let (symbol, name) = ROWS[row];
                let n = tally.calls.len();
                if n == 0 {
                    return Err(format!(
                        "profile: no call of {symbol} at δ = {delta} found in the trace"
                    ));
                }
                let total: u64 = tally.calls.iter().map(|c| c.0).sum();
                let cycles: u64 = tally.calls.iter().map(|c| c.1).sum();
                Ok(Row {
                    target: target.triple,
                    name,
                    delta,
                    calls: n,
                    instructions: total as f64 / n as f64,
                    max_instructions: tally.calls.iter().map(|c| c.0).max().unwrap_or(0),
                    est_cycles: cycles as f64 / n as f64,
                    max_stack_bytes: 0,
                })
            })
            .collect()
    }
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
fn parse_exec(line: &str) -> Option<(u32, &str)> {
    let rest = line.strip_prefix("Trace ")?;
    let (_, rest) = rest.split_once('[')?;
    let (fields, symbol) = rest.split_once(']')?;
    let pc = u32::from_str_radix(fields.split('/').nth(1)?, 16).ok()?;
    Some((pc, symbol.trim()))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A log of three calls of `bench_shape_f32` after the δ = 1 marker:
    /// 5, 6 and 5 instructions, the call instruction included.
    fn log() -> Vec<String> {
        let mut lines = vec![
            "0x00000100:  f000 f800  bl       #0x200".to_string(),
            "0x00000104:  f000 f800  bl       #0x200".to_string(),
            "0x00000108:  f000 f800  bl       #0x300".to_string(),
            "0x00000200:  4770       bx       lr".to_string(),
            "0x00000300:  2001       movs     r0, #1".to_string(),
            "0x00000302:  2800       cmp      r0, #0".to_string(),
            "0x00000304:  d100       bne      #0x308".to_string(),
            "0x00000306:  2002       movs     r0, #2".to_string(),
            "0x00000308:  4770       bx       lr".to_string(),
        ];
        let exec = |pc: u32, symbol: &str| {
            format!("Trace 0: 0x7f0000000000 [00000000/{pc:08x}/00000110/ff000201] {symbol}")
        };
        lines.push(exec(0x100, "main"));
        lines.push(exec(0x200, "profile_delta_1"));
        lines.push(exec(0x104, "main"));
        // bne taken: 0x300, 0x302, 0x304, 0x308; not taken: 0x306 too.
        for skip in [true, false, true] {
            lines.push(exec(0x108, "main"));
            for pc in [0x300, 0x302, 0x304, 0x306, 0x308] {
                if !(skip && pc == 0x306) {
                    lines.push(exec(pc, "bench_shape_f32"));
                }
            }
            // The return, not counted.
            lines.push(exec(0x10c, "main"));
        }
        lines.push(exec(0x400, END_SYMBOL));
        lines
    }

    #[test]
    fn listings_give_one_call_per_count_and_sum_to_the_total() {
        let only = ["shape_f32".to_string()];
        let mut trace = Trace::new(qemu::TARGETS[0], &only, true);
        let mut ended = false;
        for line in log() {
            ended = trace.feed(&line).unwrap();
        }
        assert!(ended);
        let rows = trace.rows().unwrap();
        assert_eq!(rows.len(), 1);
        assert_eq!((rows[0].calls, rows[0].max_instructions), (3, 6));
        // The call instruction counts: 1 + 4 (+ 1 when bne falls through).
        assert!((rows[0].instructions - 16.0 / 3.0).abs() < 1e-12);
        let text = trace.listings();
        let headers: Vec<&str> = text.lines().filter(|l| l.starts_with("listing")).collect();
        assert_eq!(
            headers,
            [
                "listing thumbv7em-none-eabihf shape_f32 δ = 1: 5 instructions, 2 of 3 calls",
                "listing thumbv7em-none-eabihf shape_f32 δ = 1: 6 instructions, 1 of 3 calls",
            ]
        );
        let body: Vec<&str> = text.lines().filter(|l| l.starts_with("  ")).collect();
        assert_eq!(body.len(), 5 + 6);
        assert!(body[0].contains("(caller)") && body[0].contains("bl"));
        assert!(body[1].contains("bench_shape_f32") && body[1].contains("movs"));
        // Without listings nothing is kept.
        let mut plain = Trace::new(qemu::TARGETS[0], &only, false);
        for line in log() {
            plain.feed(&line).unwrap();
        }
        assert!(plain.listings().is_empty());
    }
}
