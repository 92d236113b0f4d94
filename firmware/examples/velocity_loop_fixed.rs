//! The Q16.16 velocity-loop recipe of the `compensation` module's
//! documentation, as it stands there (`src/compensation/velocity_loop_q16.rs`,
//! included), linked into a Cortex-M0 firmware to measure its flash and
//! RAM against a small part (16 KiB of flash, 4 KiB of RAM): the loop runs
//! on the recipe's encoder counts, read through a volatile so that the
//! compiler cannot fold the loop away, and writes to a stand-in PWM
//! channel.
//!
//! Output: `stack <bytes>` (as in `compensation_fixed`), `feedforward
//! <f32 bits>` (the function's result), `duty <last duty>`, `done`; `cargo
//! xtask qemu velocity_loop_fixed` compares the two with the same function
//! run on the host and adds the sections in flash and the static RAM from
//! the ELF.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // the volatile read; cortex-m-rt's handlers

use core::ptr::{addr_of, read_volatile};

use cortex_m_rt::entry;

#[path = "common/footprint.rs"]
mod footprint;
#[path = "../../tests/support/pwm.rs"]
mod pwm;
#[path = "../../tests/support/mod.rs"]
mod support;
/// The recipe, as the documentation shows it.
mod recipe {
    include!("../../src/compensation/velocity_loop_q16.rs");
}

/// The recipe's encoder counts, in RAM (read through a volatile).
static ENCODER: [i32; 11] = support::RECIPE_COUNTS;

#[entry]
fn main() -> ! {
    footprint::measure(|| {
        // SAFETY: a read of a static array.
        let encoder = unsafe { read_volatile(addr_of!(ENCODER)) };
        let mut timer = pwm::Timer { duty: 0 };
        let newtons = recipe::velocity_loop(&mut timer, encoder).ok()?;
        Some([
            (b"feedforward".as_slice(), newtons.to_bits()),
            (b"duty".as_slice(), u32::from(timer.duty)),
        ])
    })
}
