//! The fixed-point model (Q16.16, `breakaway::fixed_point`) on an MCU
//! without an FPU: the presliding trajectory of `presliding_loop` and the
//! break-away table of `breakaway_table`, in per-unit numbers.
//!
//! Output: `s <count> <v raw> <F raw>` per sample (v in units of V, F in
//! units of Fs, raw = value·2¹⁶), then `ba <variant> <k raw> <v_b raw> <F_ba
//! raw> <t_ba raw>` (k in Fs/s), then `done`. `cargo xtask test` runs it on
//! the Cortex-M0 (QEMU microbit) and compares every line with the f64
//! reference (1e-3·Fs, 1e-3 relative).
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/mod.rs"]
mod common;

use breakaway::{BreakAwayPredictor, Model, Presliding, Scalar, Variant, DEFAULT_BOUNDARY, Q16};
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;

type Fx = Q16<16>;

/// Metres per encoder count.
const COUNT: f32 = 1e-8;
/// Sample period [s].
const DT: f32 = 1e-3;
const SAMPLES: i32 = 600;

#[entry]
fn main() -> ! {
    let Ok(model) = Model::<Fx>::new(common::FIG5) else {
        common::exit_failure("invalid parameters");
    };
    let Some(scale) = model.position_scale(COUNT) else {
        common::exit_failure("encoder scale out of range");
    };
    let Ok(mut axis) = Presliding::<i32, Fx>::new(0, scale) else {
        common::exit_failure("invalid scale");
    };
    // Velocity in units of V per count per sample, converted once.
    let Some(per_count) = model.velocity(COUNT / DT) else {
        common::exit_failure("velocity scale out of range");
    };
    let mut last = 0;
    for n in 0..SAMPLES {
        let count = common::reversal_trajectory(n);
        let v = Fx::saturating_from_int(count - last) * per_count;
        last = count;
        match axis.update(&model, count, v) {
            Ok(f) => hprintln!("s {} {} {}", count, v.to_bits(), f.to_bits()),
            Err(_) => common::exit_failure("sample rejected"),
        }
    }
    let Ok(predictor) = BreakAwayPredictor::new(&model, DEFAULT_BOUNDARY) else {
        common::exit_failure("invalid boundary");
    };
    // k = 0.01, 1, 5, 10, 30 N/s in units of Fs/s (Fs = 1.5 N).
    for k in [0.01f32, 1.0, 5.0, 10.0, 30.0] {
        let Some(k) = Fx::from_f32(k / common::FIG5.fs) else {
            common::exit_failure("rate out of range");
        };
        for variant in Variant::ALL {
            match predictor.predict(&model, variant, k) {
                Ok(ba) => hprintln!(
                    "ba {} {} {} {} {}",
                    variant.name(),
                    k.to_bits(),
                    ba.v_b.to_bits(),
                    ba.f_ba.to_bits(),
                    ba.t_ba.to_bits()
                ),
                Err(_) => common::exit_failure("prediction failed"),
            }
        }
    }
    hprintln!("done");
    common::exit_success()
}
