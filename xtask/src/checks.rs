//! On-target checks: the firmware examples' results under QEMU against the
//! host f64 reference (`breakaway-reference`), within the library's f32
//! bounds (friction 1e-5·Fs, break-away 1e-4 relative).

use breakaway_reference as reference;

use crate::qemu::{self, Target};
use crate::root;

/// Relative bound on v_b, F_ba, t_ba (the core issue's f32 bound).
const BREAKAWAY_BOUND: f64 = 1e-4;
/// Bound on friction, in units of Fs.
const FRICTION_BOUND: f64 = 1e-5;

fn fig5() -> Result<reference::Model, String> {
    let path = root().join("lab/models/fig5.toml");
    reference::Model::load(&path).map_err(|e| e.to_string())
}

fn field(fields: &[&str], i: usize, line: &str) -> Result<f64, String> {
    // `"NaN".parse()` is a NaN, which every `>` bound after it lets through:
    // a firmware figure must be finite.
    fields
        .get(i)
        .and_then(|s| s.parse::<f64>().ok())
        .filter(|x| x.is_finite())
        .ok_or_else(|| {
            format!("malformed firmware line `{line}` (field {i} missing or not finite)")
        })
}

/// The lines of `example`'s output that start with `tag` ([`records`]),
/// which must number `count`.
fn counted<'a>(
    output: &'a str,
    tag: &str,
    example: &str,
    count: usize,
) -> Result<Vec<(&'a str, Vec<&'a str>)>, String> {
    let rows = records(output, tag)?;
    if rows.len() != count {
        return Err(format!(
            "{example} printed {} `{tag}` rows, expected {count}",
            rows.len()
        ));
    }
    Ok(rows)
}

/// The reference's break-away (w_b = 0.95) at the force rate `k` [N/s] for
/// the variant named in column 1 of the `ba` row `fields` of `line`.
fn reference_break_away(
    model: &reference::Model,
    fields: &[&str],
    line: &str,
    k: f64,
) -> Result<reference::BreakAway, String> {
    let variant = fields
        .get(1)
        .and_then(|name| reference::Variant::parse(name))
        .ok_or_else(|| format!("unknown variant in `{line}`"))?;
    reference::predict_break_away(model, variant, k, 0.95).map_err(|e| format!("reference: {e}"))
}

/// The lines of an example's output that start with `tag`, after checking
/// that the run ended with `done`.
fn records<'a>(output: &'a str, tag: &str) -> Result<Vec<(&'a str, Vec<&'a str>)>, String> {
    if output.lines().last() != Some("done") {
        return Err("firmware output does not end with `done`".into());
    }
    Ok(output
        .lines()
        .filter_map(|line| {
            let fields: Vec<&str> = line.split_whitespace().collect();
            (fields.first() == Some(&tag)).then_some((line, fields))
        })
        .collect())
}

/// `no_panic`: its panic handler calls a symbol that exists nowhere, so the
/// release build links only if no panic path survives in the library
/// functions it calls; it must also run to a clean exit.
pub fn no_panic(target: Target) -> Result<String, String> {
    qemu::run_example("no_panic", target).map_err(|e| {
        format!(
            "no_panic on {} (an undefined breakaway_panic_path_survived means a panic path): {e}",
            target.core
        )
    })?;
    Ok(format!(
        "no_panic on {}: linked without a panic handler (no panic path in update, curves, \
         predictor, compensation) and ran",
        target.core
    ))
}

/// `breakaway_table`: every (variant, k) row against the reference.
pub fn breakaway_table(target: Target) -> Result<String, String> {
    let output = qemu::run_example("breakaway_table", target)?;
    let model = fig5()?;
    let rows = counted(
        &output,
        "ba",
        "breakaway_table",
        4 * support::BREAKAWAY_RATES.len(),
    )?;
    // Each row is judged at the rate it prints: the rows must be the grid,
    // every variant at every rate in order, not any rows that agree.
    let grid = reference::Variant::ALL
        .iter()
        .flat_map(|v| support::BREAKAWAY_RATES.map(|k| (v.name(), k)));
    for ((line, fields), (variant, k)) in rows.iter().zip(grid) {
        // The firmware prints the f32 rate; read back, it is that f32.
        if fields.get(1) != Some(&variant) || field(fields, 2, line)? as f32 != k {
            return Err(format!(
                "breakaway_table: `{line}` where the grid has {variant} at k = {k}"
            ));
        }
    }
    let mut worst = 0.0f64;
    for (line, fields) in &rows {
        let want = reference_break_away(&model, fields, line, field(fields, 2, line)?)?;
        for (i, expected) in [(3, want.v_b), (4, want.f_ba), (5, want.t_ba)] {
            let got = field(fields, i, line)?;
            let error = ((got - expected) / expected).abs();
            within(target, &mut worst, error, BREAKAWAY_BOUND, || {
                format!(
                    "`{line}` column {i} is {got}, reference {expected} (rel. error {error:.2e})"
                )
            })?;
        }
    }
    Ok(format!(
        "breakaway_table on {}: {} rows, worst relative error {worst:.2e} (bound {BREAKAWAY_BOUND:.0e})",
        target.core,
        rows.len()
    ))
}

/// Keeps the largest `error` in `worst`; fails with `message` after the
/// core's name when `error` is NaN or above `bound`.
fn within(
    target: Target,
    worst: &mut f64,
    error: f64,
    bound: f64,
    message: impl FnOnce() -> String,
) -> Result<(), String> {
    *worst = support::worse(*worst, error);
    if error.is_nan() || error > bound {
        Err(format!("{}: {}", target.core, message()))
    } else {
        Ok(())
    }
}

/// `presliding_loop`: the reference rule against the f64 reference, and the
/// closing variant against the same library built for the host.
pub fn presliding_loop(target: Target) -> Result<String, String> {
    let output = qemu::run_example("presliding_loop", target)?;
    let model = fig5()?;
    let rows = counted(&output, "s", "presliding_loop", 1200)?;
    let count = 1e-8f32;
    // The parameters the firmware runs (the f32 values of fig5.toml).
    let host_model = breakaway::Model::<f32>::new(support::FIG5).map_err(|e| e.to_string())?;
    let mut judge = reference::Presliding::new(0.0);
    let mut host =
        breakaway::Presliding::<i64, f32, 8>::new(0, count).map_err(|e| e.to_string())?;
    let (mut worst_ref, mut worst_host) = (0.0f64, 0.0f64);
    for (line, fields) in &rows {
        let position = fields
            .get(1)
            .and_then(|s| s.parse::<i64>().ok())
            .ok_or_else(|| format!("malformed firmware line `{line}`"))?;
        let v = field(fields, 2, line)? as f32;
        let single = field(fields, 3, line)?;
        let closing = field(fields, 4, line)?;
        let want = judge.update(&model, position as f64 * count as f64, v as f64);
        let error = (single - want).abs() / model.fs;
        within(target, &mut worst_ref, error, FRICTION_BOUND, || {
            format!("`{line}`: F = {single}, reference {want} ({error:.2e}·Fs)")
        })?;
        let host_f = host
            .update(&host_model, position, v)
            .map_err(|e| e.to_string())?;
        let error = (closing - host_f as f64).abs() / model.fs;
        within(target, &mut worst_host, error, FRICTION_BOUND, || {
            format!("`{line}`: closing F = {closing}, host build {host_f}")
        })?;
    }
    Ok(format!(
        "presliding_loop on {}: {} samples, reference rule vs f64 reference worst {worst_ref:.2e}·Fs, \
         closing memory vs host build worst {worst_host:.2e}·Fs (bound {FRICTION_BOUND:.0e}·Fs)",
        target.core,
        rows.len()
    ))
}

/// Every on-target check on every target, or those whose name contains one
/// of `only` (all when `only` is empty); a name in `only` that matches no
/// check is an error, not an empty run that passes.
pub fn all(only: &[String]) -> Result<Vec<String>, String> {
    type Check = fn(Target) -> Result<String, String>;
    let per_target: [(&str, Check); 4] = [
        ("no_panic", no_panic),
        ("breakaway_table", breakaway_table),
        ("presliding_loop", presliding_loop),
        ("fixed_point", fixed_point),
    ];
    // Cortex-M4F only (the closed loop simulates 40 s of plant in 5 µs steps).
    let m4f_only: [(&str, Check); 2] = [("long_run", long_run), ("closed_loop", closed_loop)];
    // Cortex-M0 only: the Q16 compensators.
    let m0_only: [(&str, Check); 3] = [
        ("closed_loop_fixed", closed_loop_fixed),
        ("compensation_fixed", compensation_fixed),
        ("velocity_loop_fixed", velocity_loop_fixed),
    ];
    let names = || {
        per_target
            .iter()
            .chain(&m4f_only)
            .chain(&m0_only)
            .map(|(name, _)| *name)
    };
    if let Some(unknown) = only
        .iter()
        .find(|o| !names().any(|n| n.contains(o.as_str())))
    {
        return Err(format!(
            "no on-target check is named like `{unknown}`; the checks: {}",
            names().collect::<Vec<_>>().join(", ")
        ));
    }
    let wanted = |name: &str| only.is_empty() || only.iter().any(|o| name.contains(o.as_str()));
    let mut report = Vec::new();
    for target in qemu::TARGETS {
        for (name, check) in per_target {
            if wanted(name) {
                report.push(check(target)?);
            }
        }
    }
    for (name, check) in m4f_only {
        if wanted(name) {
            report.push(check(qemu::TARGETS[0])?);
        }
    }
    for (name, check) in m0_only {
        if wanted(name) {
            report.push(check(qemu::target("thumbv6m-none-eabi")?)?);
        }
    }
    Ok(report)
}

/// Bounds of the fixed-point model: friction in units of Fs, F_ba relative.
const FIXED_FRICTION_BOUND: f64 = 1e-3;
const FIXED_BREAKAWAY_BOUND: f64 = 1e-3;

/// Symbols of the soft-float `f64` routines (compiler-builtins' names and
/// the ARM EABI aliases): a firmware that uses only Q16 must link none.
fn soft_f64_symbols(elf: &std::path::Path) -> Result<Vec<String>, String> {
    use object::{Object, ObjectSymbol};
    let data = std::fs::read(elf).map_err(|e| format!("{}: {e}", elf.display()))?;
    let file = object::File::parse(&*data).map_err(|e| format!("{}: {e}", elf.display()))?;
    // Their C names, `__adddf3`, `__aeabi_dmul` …: a mangled Rust name can
    // hold such letters in its hash (`…9footprint4fail17hc1b2df38cc…E`).
    let f64_routine = |name: &str| {
        name.starts_with("__")
            && [
                "df3",
                "df2",
                "__aeabi_d",
                "__aeabi_f2d",
                "__aeabi_l2d",
                "__aeabi_i2d",
                "__aeabi_ui2d",
            ]
            .iter()
            .any(|pattern| name.contains(pattern))
    };
    let names: Vec<String> = file
        .symbols()
        .filter_map(|s| s.name().ok().map(str::to_string))
        .collect();
    // A stripped file would pass while checking nothing.
    if !names.iter().any(|name| name == "Reset") {
        return Err(format!(
            "{}: no symbol table (cortex-m-rt's `Reset` not found)",
            elf.display()
        ));
    }
    Ok(names.into_iter().filter(|name| f64_routine(name)).collect())
}

/// The test support the firmware examples share (`Strokes` of `long_run`,
/// the parameters of `compensation_loop`).
#[path = "../../tests/support/mod.rs"]
mod support;

/// The loop of the `compensation_fixed` firmware, run here on the host.
#[path = "../../firmware/examples/common/compensation_loop.rs"]
#[allow(dead_code)]
mod compensation_loop;

/// The stand-in PWM channel of the firmwares.
use compensation_loop::pwm;

/// The Q16 velocity-loop recipe of the `compensation` documentation, run
/// here on the host.
mod recipe {
    include!("../../src/compensation/velocity_loop_q16.rs");
}

/// A part's flash and RAM [bytes], for a firmware's footprint.
struct Part {
    flash: u64,
    ram: u64,
}

/// `compensation_fixed`: the Q16 compensation loop (model built in place,
/// presliding feedforward, observer, level adaptation, PWM output) as a
/// Cortex-M0 firmware, against 16 KiB of flash and 2 KiB of RAM; the duty
/// checksum against the same loop on the host (identical integer
/// arithmetic: equal).
pub fn compensation_fixed(target: Target) -> Result<String, String> {
    let host = compensation_loop::control().ok_or("compensation_fixed: the host run failed")?;
    let part = Part {
        flash: 16 * 1024,
        ram: 2 * 1024,
    };
    footprint(
        "compensation_fixed",
        target,
        &part,
        &[("duty", u64::from(host))],
    )
}

/// `velocity_loop_fixed`: the Q16 velocity-loop recipe of the
/// `compensation` documentation, as it stands there, as a Cortex-M0
/// firmware, against a small part (16 KiB of flash, 4 KiB of RAM); its
/// result and last duty against the same function on the host.
pub fn velocity_loop_fixed(target: Target) -> Result<String, String> {
    let encoder = support::RECIPE_COUNTS;
    let mut timer = pwm::Timer { duty: 0 };
    let newtons = recipe::velocity_loop(&mut timer, encoder)
        .map_err(|e| format!("velocity_loop_fixed: the host run failed: {e}"))?;
    let part = Part {
        flash: 16 * 1024,
        ram: 4 * 1024,
    };
    let expected = [
        ("feedforward", u64::from(newtons.to_bits())),
        ("duty", u64::from(timer.duty)),
    ];
    footprint("velocity_loop_fixed", target, &part, &expected)
}

/// A footprint firmware (`firmware/examples/common/footprint.rs`) run under QEMU:
/// its printed figures against the host's `expected` ones (equal: the same
/// integer arithmetic), no soft-float `f64` routine linked, flash from the
/// ELF's loaded sections and RAM as .data + .bss + the painted stack depth
/// within `part`.
fn footprint(
    name: &str,
    target: Target,
    part: &Part,
    expected: &[(&str, u64)],
) -> Result<String, String> {
    use object::{Object, ObjectSection};
    let elf = qemu::build(name, target)?;
    let output = qemu::run_example(name, target)?;
    let number = |tag: &str| -> Result<u64, String> {
        output
            .lines()
            .find_map(|line| {
                line.strip_prefix(tag)?
                    .strip_prefix(' ')?
                    .trim()
                    .parse()
                    .ok()
            })
            .ok_or_else(|| format!("{name} printed no `{tag}` figure"))
    };
    let stack = number("stack")?;
    for &(tag, host) in expected {
        let mcu = number(tag)?;
        if mcu != host {
            return Err(format!(
                "{name} on {}: {tag} {mcu}, the host run {host}",
                target.core
            ));
        }
    }
    let f64_symbols = soft_f64_symbols(&elf)?;
    if !f64_symbols.is_empty() {
        return Err(format!(
            "{name}: soft-float f64 routines linked: {}",
            f64_symbols.join(", ")
        ));
    }
    let data = std::fs::read(&elf).map_err(|e| format!("{}: {e}", elf.display()))?;
    let file = object::File::parse(&*data).map_err(|e| format!("{}: {e}", elf.display()))?;
    let size = |names: &[&str]| -> u64 {
        file.sections()
            .filter(|s| s.name().is_ok_and(|n| names.contains(&n)))
            .map(|s| s.size())
            .sum()
    };
    let flash = size(&[".vector_table", ".text", ".rodata", ".data"]);
    let statics = size(&[".data", ".bss", ".uninit"]);
    if flash == 0 {
        return Err(format!("{}: no .text section found", elf.display()));
    }
    // A stack depth of 0 is a painting that read nothing, not a loop that
    // needs no stack.
    if stack == 0 {
        return Err(format!("{name}: the painted stack reads 0 B"));
    }
    let ram = statics + stack;
    let figures = format!(
        "flash {flash} B (part: {} B), RAM {ram} B = {statics} B static + {stack} B stack (part: {} B)",
        part.flash, part.ram
    );
    if flash > part.flash || ram > part.ram {
        return Err(format!("{name} on {}: {figures}: too large", target.core));
    }
    let matched: Vec<String> = expected
        .iter()
        .map(|(tag, v)| format!("{tag} {v}"))
        .collect();
    Ok(format!(
        "{name} on {}: {figures}, within; no f64 routine linked; {} = host",
        target.core,
        matched.join(", ")
    ))
}

/// `fixed_point`: the Q16.16 model's friction and break-away against the f64
/// reference, at the quantized inputs the MCU used; on the Cortex-M0 the
/// firmware (Q16 only) must link no soft-float `f64` routine.
pub fn fixed_point(target: Target) -> Result<String, String> {
    let elf = qemu::build("fixed_point", target)?;
    let f64_symbols = soft_f64_symbols(&elf)?;
    if target.triple.starts_with("thumbv6m") && !f64_symbols.is_empty() {
        return Err(format!(
            "fixed_point on {}: soft-float f64 routines linked: {}",
            target.core,
            f64_symbols.join(", ")
        ));
    }
    let output = qemu::run_example("fixed_point", target)?;
    let model = fig5()?;
    let raw = |fields: &[&str], i: usize, line: &str| field(fields, i, line).map(|x| x / 65536.0);
    let samples = records(&output, "s")?;
    let resolutions = [10.0, 1e3, 1e5, 1e7];
    if samples.len() != 600 * resolutions.len() {
        return Err(format!(
            "fixed_point printed {} samples, expected {}",
            samples.len(),
            600 * resolutions.len()
        ));
    }
    let mut worst_f = 0.0f64;
    for (chunk, per_z_max) in samples.chunks(600).zip(resolutions) {
        let count = (model.z_max as f32 / per_z_max as f32) as f64;
        let mut judge = reference::Presliding::new(0.0);
        for (line, fields) in chunk {
            if field(fields, 1, line)? != per_z_max {
                return Err(format!(
                    "fixed_point: `{line}`: expected {per_z_max:e} counts per z_max"
                ));
            }
            let position = field(fields, 2, line)?;
            let v = raw(fields, 3, line)? * model.v_stribeck;
            let f = raw(fields, 4, line)? * model.fs;
            let want = judge.update(&model, position * count, v);
            let error = (f - want).abs() / model.fs;
            within(target, &mut worst_f, error, FIXED_FRICTION_BOUND, || {
                format!("`{line}`: F = {f}, reference {want} ({error:.2e}·Fs)")
            })?;
        }
    }
    let rows = counted(&output, "ba", "fixed_point", 20)?;
    let mut worst_ba = 0.0f64;
    for (line, fields) in &rows {
        let k = raw(fields, 2, line)? * model.fs;
        let want = reference_break_away(&model, fields, line, k)?;
        // (name, value, reference, unit of the printed raw value)
        let got = [
            ("v_b", raw(fields, 3, line)?, want.v_b, model.v_stribeck),
            ("F_ba", raw(fields, 4, line)?, want.f_ba, model.fs),
            ("t_ba", raw(fields, 5, line)?, want.t_ba, 1.0),
        ];
        for (name, value, reference, unit) in got {
            let value = value * unit;
            // 1e-3 relative, or within one unit of the Q16.16 resolution the
            // value is printed in (v_b below 0.015·V has fewer than 1000
            // raw units).
            let error = ((value - reference) / reference).abs();
            let resolution = unit / 65536.0;
            if (value - reference).abs() > resolution {
                worst_ba = worst_ba.max(error);
            }
            if error.is_nan()
                || (error > FIXED_BREAKAWAY_BOUND && (value - reference).abs() > resolution)
            {
                return Err(format!(
                    "{}: `{line}`: {name} = {value}, reference {reference} (rel. error {error:.2e})",
                    target.core
                ));
            }
        }
    }
    Ok(format!(
        "fixed_point on {}: {} f64 soft-float symbols; {} samples at 10 to 10^7 counts per z_max, worst |F − F_ref| {worst_f:.2e}·Fs \
         (bound {FIXED_FRICTION_BOUND:.0e}); {} break-away rows, worst v_b/F_ba/t_ba rel. error {worst_ba:.2e} \
         (bound {FIXED_BREAKAWAY_BOUND:.0e}, or one Q16 unit)",
        target.core,
        f64_symbols.len(),
        samples.len(),
        rows.len()
    ))
}

/// Bounds of the on-target closed loop against the host benchmark (f32 plant
/// and controller on the MCU, f64 reference plant on the host): relative, on
/// the RMS and peak reversal errors and on the RMS effort.
const CLOSED_LOOP_ERROR_BOUND: f64 = 0.05;
const CLOSED_LOOP_EFFORT_BOUND: f64 = 0.01;

/// `closed_loop`: the MCU's closed-loop figures on the MODEL.md plant against
/// `breakaway-lab closed-loop`'s (the same constants, checked from the `cfg`
/// line): the nine `f32` compensators measured ideally, three through the
/// 1 µm encoder.
pub fn closed_loop(target: Target) -> Result<String, String> {
    use breakaway_lab::closed_loop::{Compensator, COMPENSATORS, TARGET_ENCODER};
    let mut runs: Vec<(Compensator, f64)> = COMPENSATORS.iter().map(|&c| (c, 0.0)).collect();
    for c in [
        Compensator::COULOMB_OBSERVER,
        Compensator::PRESLIDING,
        Compensator::ADAPTIVE,
    ] {
        runs.push((c, TARGET_ENCODER));
    }
    compare_closed_loop("closed_loop", target, &runs)
}

/// `closed_loop_fixed`: the same benchmark on the Cortex-M0 with the
/// presliding compensators in Q16.16, against the host's f64 run of the
/// `f32` ones.
pub fn closed_loop_fixed(target: Target) -> Result<String, String> {
    use breakaway_lab::closed_loop::{Compensator, TARGET_ENCODER};
    compare_closed_loop(
        "closed_loop_fixed",
        target,
        &[
            (Compensator::PRESLIDING, 0.0),
            (Compensator::ADAPTIVE, 0.0),
            (Compensator::PRESLIDING, TARGET_ENCODER),
            (Compensator::ADAPTIVE, TARGET_ENCODER),
        ],
    )
}

/// Bounds of the on-target closed loop through the 1 µm encoder: the count
/// ⌊x/q⌋ flips at slightly different instants in the MCU's f32 plant than
/// in the host's f64 one, and the loop amplifies the difference. The
/// effort averages it out (relative bound). The errors of the adaptive row
/// do not: its RMS error is a few tenths of a count, so it moves with where
/// the counts fall (0.58 against 0.44 µm on the host after the f32
/// Stribeck table changed the MCU's arithmetic in the sixth digit, 12 %
/// before), and the peak reversal error of the observer rows moves by up
/// to 60 % between neighbouring velocity bandwidths on the host. Both are
/// held within a factor; the ideal runs carry the tight comparison.
const ENCODER_ERROR_FACTOR: f64 = 1.5;
const ENCODER_PEAK_FACTOR: f64 = 2.0;
const ENCODER_EFFORT_BOUND: f64 = 0.01;

fn compare_closed_loop(
    example: &str,
    target: Target,
    runs: &[(breakaway_lab::closed_loop::Compensator, f64)],
) -> Result<String, String> {
    use breakaway_lab::closed_loop as host;
    let output = qemu::run_example(example, target)?;
    let cfg = records(&output, "cfg")?;
    let (line, fields) = cfg
        .first()
        .ok_or_else(|| format!("{example} printed no `cfg` line"))?;
    let expected = [
        host::PERIOD,
        host::AMPLITUDE,
        host::FREQUENCY,
        (host::DURATION / host::PERIOD).round(),
        (host::WINDOW_START / host::PERIOD).round(),
        host::OMEGA,
        host::OBSERVER_BANDWIDTH,
        host::ADAPTATION_RATE,
        host::MODEL_SUBSTEPS as f64,
        host::VELOCITY_BANDWIDTH,
        host::REVERSAL_GAIN,
    ];
    for (i, want) in expected.iter().enumerate() {
        let got = field(fields, i + 1, line)?;
        let off = ((got - want) / want).abs();
        if off.is_nan() || off > 1e-6 {
            return Err(format!(
                "{example}: `{line}` field {} is {got}, the host benchmark uses {want}",
                i + 1
            ));
        }
    }
    let rows = counted(&output, "cl", example, runs.len())?;
    let (mut worst_error, mut worst_effort) = (0.0f64, 0.0f64);
    let mut worst_encoder_effort = 0.0f64;
    let (mut worst_error_factor, mut worst_peak_factor) = (1.0f64, 1.0f64);
    let mut summary = Vec::new();
    for ((line, fields), &(compensator, encoder)) in rows.iter().zip(runs) {
        let printed_encoder = field(fields, 2, line)?;
        let encoder_off = (printed_encoder - encoder).abs();
        if fields.get(1) != Some(&compensator.name())
            || encoder_off.is_nan()
            || encoder_off > 1e-3 * encoder.max(1e-9)
        {
            return Err(format!(
                "{example}: `{line}`, expected {} at encoder {encoder}",
                compensator.name()
            ));
        }
        let want = host::run(
            host::PlantKind::Model,
            compensator,
            host::Drift::None,
            &host::Setup::encoder(encoder),
        )?;
        let (error_bound, effort_bound) = if encoder > 0.0 {
            (f64::INFINITY, ENCODER_EFFORT_BOUND)
        } else {
            (CLOSED_LOOP_ERROR_BOUND, CLOSED_LOOP_EFFORT_BOUND)
        };
        if encoder > 0.0 {
            for (i, expected, bound, worst) in [
                (
                    3,
                    want.rms_error,
                    ENCODER_ERROR_FACTOR,
                    &mut worst_error_factor,
                ),
                (
                    4,
                    want.peak_reversal_error,
                    ENCODER_PEAK_FACTOR,
                    &mut worst_peak_factor,
                ),
            ] {
                let got = field(fields, i, line)?;
                let ratio = got / expected;
                *worst = worst.max(ratio.max(1.0 / ratio));
                if !(1.0 / bound..=bound).contains(&ratio) {
                    return Err(format!(
                        "{example} on {}: `{line}` column {i} is {got}, host {expected} (factor bound {bound})",
                        target.core
                    ));
                }
            }
        }
        let mut columns = vec![(5, want.rms_effort, effort_bound)];
        if encoder == 0.0 {
            columns.push((3, want.rms_error, error_bound));
            columns.push((4, want.peak_reversal_error, error_bound));
        }
        for (i, expected, bound) in columns {
            let got = field(fields, i, line)?;
            let error = ((got - expected) / expected).abs();
            let (worst_error, worst_effort) = if encoder == 0.0 {
                (&mut worst_error, &mut worst_effort)
            } else {
                (&mut worst_error, &mut worst_encoder_effort)
            };
            if i == 5 {
                *worst_effort = worst_effort.max(error);
            } else {
                *worst_error = worst_error.max(error);
            }
            if error.is_nan() || error > bound {
                return Err(format!(
                    "{example} on {}: `{line}` column {i} is {got}, host {expected} (rel. error {error:.2e}, bound {bound})",
                    target.core
                ));
            }
        }
        summary.push(format!(
            "{}{} {:.2} um",
            compensator.name(),
            if encoder > 0.0 { " (1 um encoder)" } else { "" },
            field(fields, 4, line)? * 1e6
        ));
    }
    Ok(format!(
        "{example} on {}: peak reversal errors {}; ideal runs vs host worst {worst_error:.2e} on errors \
         (bound {CLOSED_LOOP_ERROR_BOUND}), {worst_effort:.2e} on effort (bound {CLOSED_LOOP_EFFORT_BOUND}); \
         encoder runs: RMS error within a factor {worst_error_factor:.2} (bound {ENCODER_ERROR_FACTOR}), \
         {worst_encoder_effort:.2e} on effort (bound {ENCODER_EFFORT_BOUND}), peak within a factor \
         {worst_peak_factor:.2} (bound {ENCODER_PEAK_FACTOR})",
        target.core,
        summary.join(", ")
    ))
}

/// `long_run`: 10⁶ samples of random motion on the MCU. The host replays the
/// example's motion (`tests/support`'s `Strokes`, the same code) through the
/// f64 reference and compares every printed sample, the last one included.
pub fn long_run(target: Target) -> Result<String, String> {
    let output = qemu::run_example("long_run", target)?;
    let rows = counted(&output, "s", "long_run", 101)?;
    let mut model = fig5()?;
    (model.delta, model.sigma) = (1.3, 0.2);
    let count = 1e-8f32;
    let mut judge = reference::Presliding::new(0.0);
    let mut rows = rows.iter().peekable();
    let (mut worst, mut compared) = (0.0f64, 0usize);
    for (n, (x, v)) in (0..1_000_000u64).zip(support::Strokes::new(count)) {
        let want = judge.update(&model, x as f64 * count as f64, v as f64);
        if let Some((line, fields)) =
            rows.next_if(|(_, f)| f.get(1) == Some(&n.to_string().as_str()))
        {
            if field(fields, 2, line)? != x as f64 {
                return Err(format!(
                    "long_run: `{line}`: position differs from the replay ({x})"
                ));
            }
            let f = field(fields, 4, line)?;
            let error = (f - want).abs() / model.fs;
            compared += 1;
            within(target, &mut worst, error, FRICTION_BOUND, || {
                format!("long_run `{line}`: F = {f}, reference {want} ({error:.2e}·Fs)")
            })?;
        }
    }
    if let Some((line, _)) = rows.next() {
        return Err(format!(
            "long_run: `{line}` matches no sample of the replay"
        ));
    }
    if compared != 101 {
        return Err(format!(
            "long_run: {compared} samples compared, expected 101"
        ));
    }
    let stat = records(&output, "stat")?;
    let max_h = stat
        .first()
        .map(|(line, fields)| field(fields, 1, line))
        .transpose()?
        .unwrap_or(f64::NAN);
    if max_h.is_nan() || max_h > model.fs * (1.0 + 1e-6) {
        return Err(format!("long_run: |H| reached {max_h}, above Fs"));
    }
    Ok(format!(
        "long_run on {}: 10^6 samples, {compared} compared (last included), worst |ΔF| {worst:.2e}·Fs \
         (bound {FRICTION_BOUND:.0e}), closing |H| ≤ {max_h}",
        target.core
    ))
}
