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

use core::ptr::{addr_of, read_volatile, write_volatile};

use cortex_m_rt::{entry, exception, ExceptionFrame};
use cortex_m_semihosting::{debug, hio};

#[path = "common/compensation_loop.rs"]
mod compensation_loop;
#[path = "../tests/support/mod.rs"]
mod support;

const PATTERN: u32 = 0xA5C3_5A3C;

extern "C" {
    /// cortex-m-rt: the first free word after the static data, and the
    /// initial stack pointer.
    static __sheap: u32;
    static _stack_start: u32;
}

fn write(bytes: &[u8]) {
    if let Ok(mut out) = hio::hstdout() {
        let _ = out.write_all(bytes);
    }
}

/// Writes `label n\n` with `n` in decimal.
fn write_number(label: &[u8], mut n: u32) {
    let mut digits = [0u8; 10];
    let mut at = digits.len();
    loop {
        at -= 1;
        digits[at] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    write(label);
    write(b" ");
    write(&digits[at..]);
    write(b"\n");
}

fn fail() -> ! {
    write(b"error\n");
    debug::exit(debug::EXIT_FAILURE);
    #[allow(clippy::empty_loop)]
    loop {}
}

#[entry]
fn main() -> ! {
    // Paint the free RAM below this frame; every frame below is the loop's.
    let heap = addr_of!(__sheap) as usize;
    let top = cortex_m::register::msp::read() as usize - 64;
    let mut at = heap;
    while at < top {
        // SAFETY: [heap, top) is free RAM below every live frame.
        unsafe { write_volatile(at as *mut u32, PATTERN) };
        at += 4;
    }
    let Some(sum) = compensation_loop::control() else {
        fail()
    };
    let mut low = heap;
    // SAFETY: reads of the painted RAM.
    while low < top && unsafe { read_volatile(low as *const u32) } == PATTERN {
        low += 4;
    }
    if low == heap {
        fail();
    }
    let stack_top = addr_of!(_stack_start) as usize;
    write_number(b"stack", (stack_top - low) as u32);
    write_number(b"duty", sum);
    write(b"done\n");
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    fail()
}

#[exception]
unsafe fn HardFault(_: &ExceptionFrame) -> ! {
    fail()
}
