//! The cycle-budget harness: each hot public function is called through a
//! `bench_*` wrapper (`#[no_mangle]`, never inlined) over a representative
//! input sequence. `cargo xtask profile` runs this under QEMU with one
//! instruction per translation block and counts, per call, the instructions
//! from the wrapper's entry to its return (the call and return included).
//!
//! The update trajectory spends half of its samples in presliding (a small
//! oscillation of ±0.4·z_max) and half in gross sliding (a 5 mm/s stroke).
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
    shape_f32, BreakAway, BreakAwayPredictor, Model, Presliding, Scalar, Variant, Q16,
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
            Cycles::NotCounting => {
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
fn trajectory(n: i32) -> i64 {
    if n < HALF {
        let phase = 2.0 * core::f32::consts::PI * n as f32 / 50.0;
        libm::roundf(400.0 * libm::sinf(phase)) as i64
    } else {
        (n - HALF) as i64 * 500 // 5 µm per sample: 5 mm/s
    }
}

#[entry]
fn main() -> ! {
    let Ok(model) = Model::<f32>::new(common::FIG5) else {
        common::exit_failure("invalid parameters");
    };
    let Ok(predictor) = BreakAwayPredictor::new(&model, 0.95) else {
        common::exit_failure("invalid boundary");
    };
    let Ok(mut axis) = Presliding::<i64>::new(0, COUNT) else {
        common::exit_failure("invalid scale");
    };
    let Ok(fixed) = Model::<Q16>::new(common::FIG5) else {
        common::exit_failure("invalid fixed-point model");
    };
    let Some(scale) = fixed.position_scale::<i32>(COUNT) else {
        common::exit_failure("encoder scale out of range");
    };
    let (Ok(mut fixed_axis), Ok(fixed_predictor), Some(per_count)) = (
        Presliding::<i32, Q16>::new(0, scale),
        BreakAwayPredictor::new(&fixed, 0.95),
        fixed.velocity(COUNT / DT),
    ) else {
        common::exit_failure("invalid fixed-point set-up");
    };
    let p = common::FIG5;
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
    let mut last = 0;
    let mut last_fixed = 0;
    let mut check = 0.0f32;
    for n in 0..2 * HALF {
        let count = trajectory(n);
        let v = (count - last) as f32 * COUNT / DT;
        last = count;
        let f = bench_update_f32(&mut axis, &model, black_box(count), black_box(v));
        let g = bench_naive_libm_update(&mut plain, black_box(count as f32 * COUNT), black_box(v));
        check += black_box(f) - black_box(g);
        let v_fixed = Q16::saturating_from_int((count - last_fixed) as i32) * per_count;
        last_fixed = count;
        black_box(bench_update_fixed(
            &mut fixed_axis,
            &fixed,
            black_box(count as i32),
            black_box(v_fixed),
        ));
        black_box(bench_stribeck_f32(&model, black_box(v)));
        black_box(bench_shape_f32(black_box(
            (n as f32 + 0.5) / (2 * HALF) as f32,
        )));
    }
    for i in 0..64 {
        // k from 0.01 to 30 N/s, log-spaced.
        let k = 0.01 * libm::powf(3000.0, i as f32 / 63.0);
        black_box(bench_breakaway_f32(&predictor, &model, black_box(k)));
        if let Some(k) = Q16::from_f32(k / p.fs) {
            black_box(bench_breakaway_fixed(
                &fixed_predictor,
                &fixed,
                black_box(k),
            ));
        }
    }
    // The anchor and the library agree (same model, same samples).
    hprintln!("anchor mismatch sum {}", check);
    dwt_note(&mut axis, &model);
    hprintln!("done");
    common::exit_success()
}
