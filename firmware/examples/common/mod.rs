//! Shared firmware plumbing of the examples: exit through semihosting with
//! status 0 on success and 1 from the panic and HardFault handlers, so that
//! QEMU's exit status is the example's verdict.

// Links cortex-m, whose single-core critical section semihosting uses.
use cortex_m as _;
use cortex_m_rt::{exception, ExceptionFrame};
use cortex_m_semihosting::{debug, hprintln};

// The parameter sets and the stroke motion of the tests (`tests/support`),
// so that the firmware runs what the host checks.
#[path = "../../../tests/support/mod.rs"]
mod support;
#[allow(unused_imports)]
pub use support::{Strokes, BREAKAWAY_RATES, CLOSED_LOOP_PLANT, FIG5, LONG_RUN};

use breakaway::{DefaultCurves, Model, Params, Presliding};

/// The model of `params`, or the end of the run.
#[allow(dead_code)]
pub fn model<T: DefaultCurves>(params: Params) -> Model<T> {
    Model::new(params).unwrap_or_else(|_| exit_failure("invalid parameters"))
}

/// Two axes read in `i64` counts of `count` metres from count 0: one with a
/// single turning point and one that closes up to eight minor loops; or the
/// end of the run.
#[allow(dead_code)]
pub fn presliding_pair(count: f32) -> (Presliding<i64>, Presliding<i64, f32, 8>) {
    match (Presliding::new(0, count), Presliding::new(0, count)) {
        (Ok(single), Ok(closing)) => (single, closing),
        _ => exit_failure("invalid scale"),
    }
}

/// Position in encoder counts at sample `n` (1 ms period) of the reversal
/// trajectory of `presliding_loop` and `fixed_point`: a 1.6·z_max stroke
/// (z_max = 1000 counts of 10 nm) with 0.3·z_max ripples at 7.3 times the
/// frequency, so that minor loops form inside presliding.
#[allow(dead_code)]
pub fn reversal_trajectory(n: i32) -> i32 {
    let t = n as f32 * 1e-3;
    let x = 1600.0 * sin_turns(0.8 * t) + 300.0 * sin_turns(5.84 * t);
    libm::roundf(x) as i32
}

/// sin(2π·p) in `f32` arithmetic only (`libm::sinf` reduces its argument in
/// `f64`, which would link soft-float `f64` code into an M0 firmware that
/// is meant to have none): p folded into [−¼, ¼] turn, then the Taylor
/// series to x¹¹ (error below 6e-8).
#[allow(dead_code)]
pub fn sin_turns(p: f32) -> f32 {
    let mut p = p - libm::roundf(p);
    if p > 0.25 {
        p = 0.5 - p;
    } else if p < -0.25 {
        p = -0.5 - p;
    }
    let x = 2.0 * core::f32::consts::PI * p;
    let x2 = x * x;
    let series = 1.0
        - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0 * (1.0 - x2 / 110.0))));
    x * series
}

/// Ends the run: QEMU exits with status 0.
pub fn exit_success() -> ! {
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
}

/// Ends the run with a message: QEMU exits with status 1.
pub fn exit_failure(message: &str) -> ! {
    hprintln!("error: {}", message);
    debug::exit(debug::EXIT_FAILURE);
    #[allow(clippy::empty_loop)]
    loop {}
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("panic: {}", info);
    debug::exit(debug::EXIT_FAILURE);
    #[allow(clippy::empty_loop)]
    loop {}
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    hprintln!("HardFault at pc = {:#010x}", frame.pc());
    debug::exit(debug::EXIT_FAILURE);
    #[allow(clippy::empty_loop)]
    loop {}
}
