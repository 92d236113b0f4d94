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

use breakaway::{Model, Params, Presliding};
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;

const SAMPLES: u32 = 1_000_000;
const COUNT: f32 = 1e-8;

/// The same parameters as the host's hardening test.
const PARAMS: Params = Params {
    fc: 1.0,
    fs: 1.5,
    v_stribeck: 1e-3,
    delta: 1.3,
    sigma: 0.2,
    z_max: 1e-5,
    epsilon: 0.0,
};

/// xorshift64* (the host replays it in xtask/src/checks.rs).
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) % n
    }
}

#[entry]
fn main() -> ! {
    let Ok(model) = Model::<f32>::new(PARAMS) else {
        common::exit_failure("invalid parameters");
    };
    let (Ok(mut single), Ok(mut closing)) = (
        Presliding::<i64>::new(0, COUNT),
        Presliding::<i64, f32, 8>::new(0, COUNT),
    ) else {
        common::exit_failure("invalid scale");
    };
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut x, mut target, mut step, mut v) = (0i64, 0i64, 1i64, 0.0f32);
    let mut max_h = 0.0f32;
    for n in 0..SAMPLES {
        if x == target {
            let len = 1 + rng.below(3000) as i64;
            target = if rng.below(2) == 0 { x + len } else { x - len };
            step = 1 + rng.below(64) as i64;
            v = (target - x).signum() as f32 * step as f32 * COUNT / 1e-3;
        } else if target > x {
            x = (x + step).min(target);
        } else {
            x = (x - step).max(target);
        }
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
