//! Cycle counting on hardware (feature `cortex-m`, ARMv7-M and later): times
//! a closure with the DWT cycle counter.
//!
//! Under QEMU the DWT cycle counter is not modelled and reads 0: a measurement
//! then comes back as [`Cycles::NotCounting`] rather than as a figure of 0. The
//! repository's
//! [`cargo xtask profile`](https://github.com/breakaway-rs/breakaway/blob/main/docs/cycle-budget.md)
//! counts instructions under QEMU instead.

use cortex_m::peripheral::{DCB, DWT};

/// The outcome of a measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Cycles {
    /// Core clock cycles between the two reads of the counter, including
    /// the closure call and about two cycles of read overhead.
    Counted(u32),
    /// The counter did not advance: it is absent, disabled, or not modelled
    /// (QEMU).
    NotCounting,
}

/// The DWT cycle counter, enabled.
#[derive(Debug)]
pub struct CycleCounter {
    _private: (),
}

impl CycleCounter {
    /// Enables tracing and the cycle counter. Returns `None` when the core
    /// has no cycle counter.
    pub fn new(dcb: &mut DCB, dwt: &mut DWT) -> Option<Self> {
        if !DWT::has_cycle_counter() {
            return None;
        }
        dcb.enable_trace();
        dwt.enable_cycle_counter();
        Some(Self { _private: () })
    }

    /// Runs `f` and returns its result with the cycles it took.
    #[inline(always)]
    pub fn measure<R>(&self, f: impl FnOnce() -> R) -> (R, Cycles) {
        let start = DWT::cycle_count();
        let result = f();
        let end = DWT::cycle_count();
        let cycles = if start == 0 && end == 0 {
            Cycles::NotCounting
        } else {
            Cycles::Counted(end.wrapping_sub(start))
        };
        (result, cycles)
    }
}
