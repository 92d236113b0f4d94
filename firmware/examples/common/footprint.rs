//! What the footprint firmwares (`compensation_fixed`, `velocity_loop_fixed`)
//! share: painting the free RAM to measure the stack, and raw semihosting
//! output (no formatting machinery linked, so that the flash figure is the
//! loop's). `cargo xtask qemu NAME` adds .data, .bss and the stack for the
//! RAM, and the sections in flash from the ELF.

use core::ptr::addr_of;

use cortex_m_rt::{exception, ExceptionFrame};
use cortex_m_semihosting::{debug, hio};

#[path = "stack.rs"]
mod stack;

extern "C" {
    /// cortex-m-rt: the initial stack pointer.
    static _stack_start: u32;
}

/// Runs `work` with the free RAM below the caller's frame painted, writes
/// `stack <bytes>` (the deepest the stack reached below its top) and each
/// `(label, number)` that `work` returns, then `done`, and exits; `fail`s
/// when `work` returns `None` or the stack reached the end of the free RAM.
pub fn measure<const N: usize>(work: impl FnOnce() -> Option<[(&'static [u8], u32); N]>) -> ! {
    // All the free RAM.
    let painted = stack::paint(usize::MAX);
    let Some(figures) = work() else { fail() };
    let Some(low) = painted.lowest(usize::MAX) else {
        fail()
    };
    let stack_top = addr_of!(_stack_start) as usize;
    write_number(b"stack", (stack_top - low) as u32);
    for (label, n) in figures {
        write_number(label, n);
    }
    write(b"done\n");
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
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

/// Writes `error` and exits with failure (the panic and fault handlers too).
pub fn fail() -> ! {
    write(b"error\n");
    debug::exit(debug::EXIT_FAILURE);
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
