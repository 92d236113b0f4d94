//! Stack depth by painting, for the firmwares that report it
//! (`cycle_budget` per pass, `compensation_fixed` and `velocity_loop_fixed`
//! for the whole loop): the free RAM below the painter's own frame is
//! filled with a pattern; after the work, the lowest word that no longer
//! holds it is the deepest the stack reached. (Under QEMU the cycle
//! counter reads 0; the painted depth is exact to the word.)

use core::ptr::{addr_of, read_volatile, write_volatile};

const PATTERN: u32 = 0xA5C3_5A3C;

extern "C" {
    /// cortex-m-rt: the first free word after the static data.
    static __sheap: u32;
}

/// A painted span of free RAM, `[bottom, top)` [addresses].
pub struct Painted {
    bottom: usize,
    top: usize,
}

/// Paints from `span` bytes below the caller's frame (or from the end of
/// the static data, where that is higher) up to just below that frame.
/// Inlined, as [`Painted::lowest`] is: a frame of their own, below the
/// caller's, would leave a gap unpainted (a pass that stayed within it
/// would read as deep as the gap) or overwrite the paint.
#[inline(always)]
pub fn paint(span: usize) -> Painted {
    let top = (cortex_m::register::msp::read() as usize).saturating_sub(8) & !3;
    // Only the address of the linker symbol is taken.
    let heap = addr_of!(__sheap) as usize;
    let bottom = heap.max(top.saturating_sub(span)) & !3;
    let mut at = bottom;
    while at < top {
        // SAFETY: [bottom, top) is free RAM below every live frame.
        unsafe { write_volatile(at as *mut u32, PATTERN) };
        at += 4;
    }
    Painted { bottom, top }
}

impl Painted {
    /// The lowest address the stack reached since [`paint`] (at most `below`,
    /// an address at or under the painter's caller's frame); `None` when it
    /// reached the bottom of the span, where the depth would be a bound only.
    #[inline(always)]
    pub fn lowest(&self, below: usize) -> Option<usize> {
        let end = below.min(self.top);
        let mut at = self.bottom;
        // SAFETY: reads of the painted RAM.
        while at < end && unsafe { read_volatile(at as *const u32) } == PATTERN {
            at += 4;
        }
        (at > self.bottom).then_some(at)
    }
}
