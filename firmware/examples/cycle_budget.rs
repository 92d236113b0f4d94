//! The cycle-budget harness: each hot public function is called through a
//! `bench_*` wrapper (`#[no_mangle]`, never inlined) over a representative
//! input sequence. `cargo xtask profile` runs this under QEMU with one
//! instruction per translation block and counts, per call, the instructions
//! from the wrapper's entry to its return (the call and return included).
//!
//! The update trajectory spends half of its samples in presliding (a small
//! oscillation of ±0.4·z_max) and half in gross sliding (a 5 mm/s stroke).
//!
//! Each row is one *pass* (a function that calls its wrapper over the
//! row's inputs). The passes run in groups, one per shape exponent δ of
//! [`DELTAS`]: every pass with the Fig. 5 model (δ = 1), then the passes
//! whose cost depends on δ ([`DELTA_PASSES`]) with the same parameters at
//! δ = 0.7, 1.3 and 2, on the same trajectory. A group starts with a call
//! of its marker (`profile_delta_0_7` for δ = 0.7): the profile attributes
//! every call that follows to that δ. After the counted passes,
//! `stack_pass` runs every group's passes again with the free stack painted
//! and prints `stack <row> <δ> <bytes>`: the deepest the wrapper and
//! everything it called reached below the stack pointer of the call (the
//! instruction count stops at `stack_pass`).
//!
//! On hardware the example also times one update with the DWT cycle counter
//! (`breakaway::cycles`); under QEMU that counter reads 0 and the example
//! says so instead of printing a figure.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/mod.rs"]
mod common;

use core::hint::black_box;

use breakaway::{
    shape_f32, BreakAway, BreakAwayPredictor, CountScale, Model, Params, Presliding, Scalar,
    Variant, Q16,
};
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;

/// Metres per encoder count.
const COUNT: f32 = 1e-8;
/// Control period [s].
const DT: f32 = 1e-3;
/// Samples per half of the update trajectory.
const HALF: i32 = 200;

#[no_mangle]
#[inline(never)]
fn bench_update_f32(axis: &mut Presliding<i64>, model: &Model, count: i64, v: f32) -> f32 {
    axis.update(model, count, v).unwrap_or(0.0)
}

#[no_mangle]
#[inline(never)]
fn bench_stribeck_f32(model: &Model, v: f32) -> f32 {
    model.stribeck(v)
}

#[no_mangle]
#[inline(never)]
fn bench_shape_f32(w: f32) -> f32 {
    shape_f32(w)
}

#[no_mangle]
#[inline(never)]
fn bench_breakaway_f32(
    predictor: &BreakAwayPredictor<f32>,
    model: &Model,
    k: f32,
) -> Option<BreakAway<f32>> {
    predictor.predict(model, Variant::Consistent, k).ok()
}

#[no_mangle]
#[inline(never)]
fn bench_update_fixed(
    axis: &mut Presliding<i32, Q16>,
    model: &Model<Q16>,
    count: i32,
    v: Q16,
) -> Q16 {
    axis.update(model, count, v).unwrap_or(Q16::ZERO)
}

#[no_mangle]
#[inline(never)]
fn bench_breakaway_fixed(
    predictor: &BreakAwayPredictor<Q16>,
    model: &Model<Q16>,
    k: Q16,
) -> Option<BreakAway<Q16>> {
    predictor.predict(model, Variant::Consistent, k).ok()
}

#[no_mangle]
#[inline(never)]
fn bench_naive_libm_update(state: &mut naive::Naive, x: f32, v: f32) -> f32 {
    state.update(x, v)
}

/// The anchor: the same per-sample update written plainly, with
/// `libm::expf`, `libm::powf` and `libm::logf` on every call and absolute
/// `f32` positions.
mod naive {
    pub struct Naive {
        pub fc: f32,
        pub fs: f32,
        pub v: f32,
        pub delta: f32,
        pub sigma: f32,
        pub z_max: f32,
        pub d: f32,
        pub x_r: f32,
        pub x_ext: f32,
        pub h_r: f32,
        pub h_ext: f32,
    }

    impl Naive {
        pub fn update(&mut self, x: f32, v: f32) -> f32 {
            let s = self.fc
                + (self.fs - self.fc)
                    * libm::expf(-libm::powf(libm::fabsf(v) / self.v, self.delta));
            if self.d == 0.0 {
                if x == self.x_r {
                    return self.sigma * v;
                }
                self.d = if x > self.x_r { 1.0 } else { -1.0 };
            }
            if self.d * (x - self.x_ext) < 0.0 {
                self.d = -self.d;
                self.x_r = self.x_ext;
                self.h_r = self.h_ext;
            }
            self.x_ext = x;
            let w = libm::fminf(libm::fabsf(x - self.x_r) / self.z_max, 1.0);
            let g = if w > 0.0 {
                w * (1.0 - libm::logf(w))
            } else {
                0.0
            };
            let h = self.h_r + (self.d * s - self.h_r) * g;
            self.h_ext = h;
            h + self.sigma * v
        }
    }
}

/// Times one update with the DWT cycle counter where the core has one. Under
/// QEMU the counter reads 0, which is said, not printed as a figure.
#[cfg(not(breakaway_armv6m))]
fn dwt_note(axis: &mut Presliding<i64>, model: &Model) {
    use breakaway::cycles::{CycleCounter, Cycles};
    let Some(mut core) = cortex_m::Peripherals::take() else {
        return;
    };
    match CycleCounter::new(&mut core.DCB, &mut core.DWT) {
        None => hprintln!("dwt: this core has no cycle counter"),
        Some(counter) => match counter
            .measure(|| bench_update_f32(axis, model, 123, 1e-4))
            .1
        {
            Cycles::Counted(n) => hprintln!("dwt: update_f32 took {} cycles", n),
            // `NotCounting`, or what a later version may add.
            _ => {
                hprintln!(
                    "dwt: the cycle counter reads 0 (QEMU does not model it): no cycle figure"
                )
            }
        },
    }
}

#[cfg(breakaway_armv6m)]
fn dwt_note(_: &mut Presliding<i64>, _: &Model) {
    hprintln!("dwt: ARMv6-M has no cycle counter");
}

/// Position in counts at sample `n`: ±0.4·z_max oscillation, then a stroke.
fn trajectory(n: i32) -> i32 {
    if n < HALF {
        let phase = 2.0 * core::f32::consts::PI * n as f32 / 50.0;
        libm::roundf(400.0 * libm::sinf(phase)) as i32
    } else {
        (n - HALF) * 500 // 5 µm per sample: 5 mm/s
    }
}

#[no_mangle]
#[inline(never)]
fn bench_new_model_f32(params: Params) -> Option<Model> {
    Model::<f32>::new(params).ok()
}

/// Construction in place, the way for a small MCU: the model's storage is
/// the caller's, the S table is built where it lives.
#[no_mangle]
#[inline(never)]
fn bench_new_model_fixed(model: &mut Model<Q16>, params: Params) -> bool {
    *model = Model::UNIT_COULOMB;
    model.set_params(params).is_ok()
}

/// Samples of the update trajectory.
const SAMPLES: usize = 2 * HALF as usize;

/// What the passes of one δ share: the models and predictors of both
/// number types.
struct Bench<'a> {
    model: Model,
    predictor: BreakAwayPredictor<f32>,
    fixed: Model<Q16>,
    fixed_predictor: BreakAwayPredictor<Q16>,
    scale: CountScale,
    /// Model velocity units per count per sample.
    per_count: Q16,
    /// The update trajectory [counts], computed once for every δ (its
    /// `sinf` is not part of any row).
    counts: &'a [i32; SAMPLES],
}

/// The Fig. 5 parameters with the shape exponent `delta`, as models and
/// predictors of both number types.
fn bench(delta: f32, counts: &[i32; SAMPLES]) -> Bench<'_> {
    let p = Params {
        delta,
        ..common::FIG5
    };
    let mut fixed = Model::<Q16>::UNIT_COULOMB;
    let (Ok(model), Ok(())) = (Model::<f32>::new(p), fixed.set_params(p)) else {
        common::exit_failure("invalid parameters");
    };
    let (Ok(predictor), Ok(fixed_predictor), Some(scale), Some(per_count)) = (
        BreakAwayPredictor::new(&model, 0.95),
        BreakAwayPredictor::new(&fixed, 0.95),
        fixed.position_scale::<i32>(COUNT),
        fixed.velocity(COUNT / DT),
    ) else {
        common::exit_failure("invalid set-up");
    };
    Bench {
        model,
        predictor,
        fixed,
        fixed_predictor,
        scale,
        per_count,
        counts,
    }
}

/// The stack pointer in the caller's frame: the wrappers are called at it.
#[inline(always)]
fn sp() -> usize {
    cortex_m::register::msp::read() as usize
}

/// A pass calls one wrapper over its row's inputs and returns the stack
/// pointer it called it at, and a checksum.
type Pass = fn(&Bench) -> (usize, f32);

fn pass_update_f32(b: &Bench) -> (usize, f32) {
    let Ok(mut axis) = Presliding::<i64>::new(0, COUNT) else {
        common::exit_failure("invalid scale");
    };
    let (mut last, mut sum) = (0, 0.0);
    for n in 0..2 * HALF {
        let count = i64::from(b.counts[n as usize]);
        let v = (count - last) as f32 * COUNT / DT;
        last = count;
        sum += bench_update_f32(&mut axis, &b.model, black_box(count), black_box(v));
    }
    (sp(), sum)
}

fn pass_naive_libm_update(b: &Bench) -> (usize, f32) {
    let p = b.model.params();
    let mut plain = naive::Naive {
        fc: p.fc,
        fs: p.fs,
        v: p.v_stribeck,
        delta: p.delta,
        sigma: p.sigma,
        z_max: p.z_max,
        d: 0.0,
        x_r: 0.0,
        x_ext: 0.0,
        h_r: 0.0,
        h_ext: 0.0,
    };
    let (mut last, mut sum) = (0, 0.0);
    for n in 0..2 * HALF {
        let count = i64::from(b.counts[n as usize]);
        let v = (count - last) as f32 * COUNT / DT;
        last = count;
        sum += bench_naive_libm_update(&mut plain, black_box(count as f32 * COUNT), black_box(v));
    }
    (sp(), sum)
}

fn pass_update_fixed(b: &Bench) -> (usize, f32) {
    let Ok(mut axis) = Presliding::<i32, Q16>::new(0, b.scale) else {
        common::exit_failure("invalid scale");
    };
    let (mut last, mut sum) = (0, 0.0);
    for n in 0..2 * HALF {
        let count = i64::from(b.counts[n as usize]);
        let v = Q16::saturating_from_int((count - last) as i32) * b.per_count;
        last = count;
        let f = bench_update_fixed(&mut axis, &b.fixed, black_box(count as i32), black_box(v));
        sum += f.to_f32();
    }
    (sp(), sum)
}

fn pass_stribeck_f32(b: &Bench) -> (usize, f32) {
    let (mut last, mut sum) = (0, 0.0);
    for n in 0..2 * HALF {
        let count = i64::from(b.counts[n as usize]);
        let v = (count - last) as f32 * COUNT / DT;
        last = count;
        sum += bench_stribeck_f32(&b.model, black_box(v));
    }
    (sp(), sum)
}

fn pass_shape_f32(_: &Bench) -> (usize, f32) {
    let mut sum = 0.0;
    for n in 0..2 * HALF {
        sum += bench_shape_f32(black_box((n as f32 + 0.5) / (2 * HALF) as f32));
    }
    (sp(), sum)
}

/// k from 0.01 to 30 N/s, log-spaced.
fn rate(i: i32) -> f32 {
    0.01 * libm::powf(3000.0, i as f32 / 63.0)
}

fn pass_breakaway_f32(b: &Bench) -> (usize, f32) {
    let mut sum = 0.0;
    for i in 0..64 {
        if let Some(ba) = bench_breakaway_f32(&b.predictor, &b.model, black_box(rate(i))) {
            sum += ba.f_ba;
        }
    }
    (sp(), sum)
}

fn pass_breakaway_fixed(b: &Bench) -> (usize, f32) {
    let mut sum = 0.0;
    for i in 0..64 {
        if let Some(k) = Q16::from_f32(rate(i) / b.model.params().fs) {
            if let Some(ba) = bench_breakaway_fixed(&b.fixed_predictor, &b.fixed, black_box(k)) {
                sum += ba.f_ba.to_f32();
            }
        }
    }
    (sp(), sum)
}

fn pass_new_model_f32(b: &Bench) -> (usize, f32) {
    let model = bench_new_model_f32(black_box(*b.model.params()));
    (sp(), model.map_or(0.0, |m| m.stribeck(1e-3)))
}

fn pass_new_model_fixed(b: &Bench) -> (usize, f32) {
    let mut model = Model::<Q16>::UNIT_COULOMB;
    let built = bench_new_model_fixed(&mut model, black_box(*b.model.params()));
    (
        sp(),
        if built {
            model.stribeck(Q16::ONE).to_f32()
        } else {
            0.0
        },
    )
}

/// Every row's pass, by the name `cargo xtask profile` reports: the group
/// of the Fig. 5 model (δ = 1).
const PASSES: [(&str, Pass); 9] = [
    ("update_f32", pass_update_f32),
    ("stribeck_f32", pass_stribeck_f32),
    ("shape_f32", pass_shape_f32),
    ("breakaway_f32", pass_breakaway_f32),
    ("naive_libm_update", pass_naive_libm_update),
    ("update_fixed", pass_update_fixed),
    ("breakaway_fixed", pass_breakaway_fixed),
    ("new_model_f32", pass_new_model_f32),
    ("new_model_fixed", pass_new_model_fixed),
];

/// The passes whose cost depends on δ: the group of every other δ.
const DELTA_PASSES: [(&str, Pass); 3] = [
    ("update_f32", pass_update_f32),
    ("naive_libm_update", pass_naive_libm_update),
    ("update_fixed", pass_update_fixed),
];

// The markers of the δ groups. `cargo xtask profile` reads δ from the name
// of the function entered (`profile_delta_1_3`: δ = 1.3) and attributes the
// calls that follow to it. Each returns its δ through `black_box`, so that
// the call is kept and no two markers have the same body (identical
// functions could be folded into one symbol).
macro_rules! delta_markers {
    ($($marker:ident => $delta:literal),+ $(,)?) => {
        $(
            #[no_mangle]
            #[inline(never)]
            fn $marker() -> f32 {
                black_box($delta)
            }
        )+

        /// The δ groups in the order they run, by marker: the Fig. 5
        /// model's δ = 1 (every pass) first, then [`DELTA_PASSES`] at
        /// δ = 0.7, 1.3 and 2.
        const DELTAS: &[fn() -> f32] = &[$($marker),+];
    };
}

delta_markers! {
    profile_delta_1 => 1.0,
    profile_delta_0_7 => 0.7,
    profile_delta_1_3 => 1.3,
    profile_delta_2 => 2.0,
}

/// The passes of the δ group `group` (an index into [`DELTAS`]).
fn passes(group: usize) -> &'static [(&'static str, Pass)] {
    if group == 0 {
        &PASSES
    } else {
        &DELTA_PASSES
    }
}

/// The rows to run, comma-separated, when `cargo xtask profile --rows`
/// built the example (every row otherwise).
const ONLY: Option<&str> = option_env!("BREAKAWAY_PROFILE_ROWS");

/// Whether the pass of the row `name` runs.
fn selected(name: &str) -> bool {
    match ONLY {
        Some(only) if !only.is_empty() => only.split(',').any(|n| n == name),
        _ => true,
    }
}

#[path = "common/stack.rs"]
mod stack;

/// At most this much below the stack pointer is painted (the Cortex-M4F
/// machine has 4 MiB of RAM; the passes need far less).
const STACK_SPAN: usize = 32 * 1024;

/// Every group's passes again with the stack painted (not counted by the
/// profile). Each group's models are built again (one group at a time: an
/// `f32` model holds its Stribeck table, 1.3 KiB, and the Cortex-M0 has
/// 16 KiB of RAM).
#[no_mangle]
#[inline(never)]
fn stack_pass(counts: &[i32; SAMPLES]) {
    for (group, marker) in DELTAS.iter().enumerate() {
        let bench = bench(marker(), counts);
        let delta = bench.model.params().delta;
        for &(name, pass) in passes(group).iter().filter(|(n, _)| selected(n)) {
            let painted = stack::paint(STACK_SPAN);
            let (sp, _) = pass(&bench);
            match painted.lowest(sp) {
                Some(low) => hprintln!("stack {} {} {}", name, delta, sp - low),
                // Not a number: the profile fails, naming the row.
                None => hprintln!("stack {} {} beyond-the-painted-span", name, delta),
            }
        }
    }
}

/// The counted passes of the δ group `group` (an index into [`DELTAS`]).
/// A function of its own, as are [`stack_pass`] and [`timed`]: each
/// builds its models in its own frame, so that only one group's models are
/// on the stack at a time.
#[inline(never)]
fn counted_group(group: usize, counts: &[i32; SAMPLES]) {
    // The marker first: the profile attributes what follows to its δ.
    let bench = bench(DELTAS[group](), counts);
    let (mut library, mut anchor) = (0.0, 0.0);
    for &(name, pass) in passes(group).iter().filter(|(n, _)| selected(n)) {
        let sum = black_box(pass(&bench).1);
        match name {
            "update_f32" => library = sum,
            "naive_libm_update" => anchor = sum,
            _ => {}
        }
    }
    // The anchor and the library agree (same model, same samples).
    hprintln!(
        "anchor mismatch sum at delta {}: {}",
        bench.model.params().delta,
        library - anchor
    );
}

/// One update timed by the DWT cycle counter, with the Fig. 5 model.
#[inline(never)]
fn timed(counts: &[i32; SAMPLES]) {
    let bench = bench(1.0, counts);
    let mut axis =
        Presliding::<i64>::new(0, COUNT).unwrap_or_else(|_| common::exit_failure("invalid scale"));
    dwt_note(&mut axis, &bench.model);
}

#[entry]
fn main() -> ! {
    // The trajectory's `sinf` runs before the first marker.
    let counts: [i32; SAMPLES] = core::array::from_fn(|n| trajectory(n as i32));
    for group in 0..DELTAS.len() {
        counted_group(group, &counts);
    }
    stack_pass(&counts);
    timed(&counts);
    hprintln!("done");
    common::exit_success()
}
