//! The fixed-point model (Q16.16, `breakaway::fixed_point`) on an MCU
//! without an FPU: the presliding trajectory of `presliding_loop` and the
//! break-away table of `breakaway_table`, in per-unit numbers.
//!
//! Output: `s <per z_max> <count> <v raw> <F raw>` per sample, for encoders
//! of 10, 10³, 10⁵ and 10⁷ counts per z_max (v in units of V, F in units of
//! Fs, raw = value·2¹⁶), then `ba <variant> <k raw> <v_b raw> <F_ba raw>
//! <t_ba raw>` (k in Fs/s), then `done`. `cargo xtask test` runs it on the
//! Cortex-M0 (QEMU microbit) and compares every value with the f64
//! reference (friction 1e-3·Fs; F_ba, v_b, t_ba 1e-3 relative).
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/mod.rs"]
mod common;

use breakaway::{BreakAwayPredictor, Presliding, Variant, DEFAULT_BOUNDARY, Q16};
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;

/// Metres per step of the reversal trajectory (z_max/1000).
const STEP: f32 = 1e-8;
/// Encoder resolutions: counts per z_max.
const RESOLUTIONS: [i64; 4] = [10, 1_000, 100_000, 10_000_000];
/// Sample period [s].
const DT: f32 = 1e-3;
const SAMPLES: i32 = 600;

#[entry]
fn main() -> ! {
    let model = common::model::<Q16>(common::FIG5);
    // Velocity in units of V per trajectory step per sample, converted once.
    let Some(per_step) = model.velocity(STEP / DT) else {
        common::exit_failure("velocity scale out of range");
    };
    for per_z_max in RESOLUTIONS {
        let count = common::FIG5.z_max / per_z_max as f32;
        let Some(scale) = model.position_scale::<i32>(count) else {
            common::exit_failure("encoder scale out of range");
        };
        let Ok(mut axis) = Presliding::<i32, Q16>::new(0, scale) else {
            common::exit_failure("invalid scale");
        };
        let mut last = 0;
        for n in 0..SAMPLES {
            let step = common::reversal_trajectory(n);
            let v = Q16::saturating_from_int(step - last) * per_step;
            last = step;
            // The trajectory read by this encoder: |count| ≤ 1.9·10⁷.
            let count = (i64::from(step) * per_z_max / 1000) as i32;
            match axis.update(&model, count, v) {
                Ok(f) => hprintln!("s {} {} {} {}", per_z_max, count, v.to_bits(), f.to_bits()),
                Err(_) => common::exit_failure("sample rejected"),
            }
        }
    }
    let Ok(predictor) = BreakAwayPredictor::new(&model, DEFAULT_BOUNDARY) else {
        common::exit_failure("invalid boundary");
    };
    // k = 0.01, 1, 5, 10, 30 N/s in units of Fs/s (Fs = 1.5 N).
    for k in [0.01f32, 1.0, 5.0, 10.0, 30.0] {
        let Some(k) = Q16::from_f32(k / common::FIG5.fs) else {
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
