//! The whole Q16.16 compensation loop as a small Cortex-M0 firmware would
//! link it, to measure its flash and RAM: a `Model<Q16>` built in place,
//! the presliding `Feedforward` on encoder counts, the
//! `DisturbanceObserver`, the `LevelAdaptation` and a `PwmForce` output,
//! run for 2 000 periods on a synthetic encoder trajectory (integer
//! arithmetic only). No formatting machinery is linked: the result goes
//! out as raw semihosting writes, and a panic only exits.
//!
//! Output: `stack <bytes>` (the deepest the stack reached below its top,
//! from painting the free RAM at entry), `duty <sum>` (the sum of the
//! duties written, which `cargo xtask` compares with the same loop run on
//! the host), `done`. `cargo xtask qemu compensation_fixed` adds .data,
//! .bss and the stack for the RAM, and the sections in flash from the ELF.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // stack painting; cortex-m-rt's handlers

use cortex_m_rt::entry;

#[path = "common/compensation_loop.rs"]
mod compensation_loop;
#[path = "common/footprint.rs"]
mod footprint;
#[path = "../../tests/support/mod.rs"]
mod support;

#[entry]
fn main() -> ! {
    footprint::measure(|| Some([(b"duty".as_slice(), compensation_loop::control()?)]))
}
