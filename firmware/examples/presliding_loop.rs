//! A position trajectory with reversals and minor loops, run through the
//! presliding state machine on the MCU (MODEL.md §3).
//!
//! The axis follows two superposed sinusoids in encoder counts of 10 nm
//! (z_max = 1000 counts): large strokes into gross sliding with small
//! back-and-forth loops inside presliding. Output, one line per sample:
//! `s <count> <v> <F reference rule> <F closing, 8 turning points>`, then
//! `done`. `cargo xtask test` re-runs the printed inputs through the f64
//! reference and compares.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/mod.rs"]
mod common;

use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;

/// Metres per encoder count.
const COUNT: f32 = 1e-8;
/// Sample period [s].
const DT: f32 = 1e-3;
const SAMPLES: i32 = 1200;

#[entry]
fn main() -> ! {
    let model = common::model::<f32>(common::FIG5);
    let (mut single, mut closing) = common::presliding_pair(COUNT);
    let mut last = 0;
    for n in 0..SAMPLES {
        let count = i64::from(common::reversal_trajectory(n));
        let v = (count - last) as f32 * COUNT / DT;
        last = count;
        match (
            single.update(&model, count, v),
            closing.update(&model, count, v),
        ) {
            (Ok(f), Ok(g)) => hprintln!("s {} {} {} {}", count, v, f, g),
            _ => common::exit_failure("sample rejected"),
        }
    }
    hprintln!("done");
    common::exit_success()
}
