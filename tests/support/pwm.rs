//! A PWM channel for tests and examples that have no timer: it keeps the
//! last duty written (a register write on hardware). Used by the README's
//! recipe (`tests/readme.rs`) and the Q16 compensation loop
//! (`firmware/examples/common/compensation_loop.rs`, through `#[path]`); needs
//! `embedded-hal`, so it is not part of `support/mod.rs`, which the crates
//! without it include.

use embedded_hal::pwm::{ErrorType, SetDutyCycle};

/// A 12-bit timer channel (duty 0 … 4095).
pub struct Timer {
    /// The last duty written.
    pub duty: u16,
}

impl ErrorType for Timer {
    type Error = core::convert::Infallible;
}

impl SetDutyCycle for Timer {
    fn max_duty_cycle(&self) -> u16 {
        4095
    }
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {
        self.duty = duty;
        Ok(())
    }
}
