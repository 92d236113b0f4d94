//! 10⁶ samples of random motion on the MCU (hardening): strokes of up to
//! 3·z_max with random speeds and rests, through the reference-rule and the
//! closing state machines.
//!
//! Output: every 10 000th sample `s <n> <count> <v> <F>`, the last sample,
//! then `stat <max |H| closing> <memory_len>` and `done`. `cargo xtask test`
//! replays the same generator on the host through the f64 reference and
//! compares every printed sample (1e-5·Fs), so agreement at the end is
//! checked as at the start.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/mod.rs"]
mod common;

use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;

const SAMPLES: u32 = 1_000_000;
const COUNT: f32 = 1e-8;

#[entry]
fn main() -> ! {
    let model = common::model::<f32>(common::LONG_RUN);
    let (mut single, mut closing) = common::presliding_pair(COUNT);
    let mut max_h = 0.0f32;
    // The motion of the host's hardening test, replayed by `cargo xtask`.
    for (n, (x, v)) in (0..SAMPLES).zip(common::Strokes::new(COUNT)) {
        let (Ok(f), Ok(g)) = (single.update(&model, x, v), closing.update(&model, x, v)) else {
            common::exit_failure("sample rejected");
        };
        if !(f.is_finite() && g.is_finite()) {
            common::exit_failure("non-finite friction");
        }
        max_h = max_h.max(libm::fabsf(closing.dry()));
        if n % 10_000 == 0 || n == SAMPLES - 1 {
            hprintln!("s {} {} {} {}", n, x, v, f);
        }
    }
    hprintln!("stat {} {}", max_h, closing.memory_len());
    hprintln!("done");
    common::exit_success()
}
