//! A force command to a PWM output through `embedded_hal::pwm::SetDutyCycle`
//! (feature `hal`).
//!
//! The force-to-duty scale is linear with saturation, in one of two
//! [`DutyMode`]s, with F_full the force [N] at full scale:
//!
//! ```text
//! Centered:   duty/max = 1/2 + F/(2·F_full)   (0 % = −F_full, 50 % = 0 N, 100 % = +F_full)
//! Magnitude:  duty/max = |F|/F_full           (the sign goes to a direction pin)
//! ```
//!
//! `Centered` suits a half bridge or a complementary H-bridge PWM;
//! `Magnitude` a sign-magnitude driver. A force beyond ±F_full saturates at
//! full scale and is reported as such; the duty is rounded to the nearest
//! step of the timer. Quantisation therefore limits the force resolution to
//! F_full/max (Centered: 2·F_full/max), which sets the smallest presliding
//! force step the compensation can apply.

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap.
#![allow(clippy::arithmetic_side_effects)]

use embedded_hal::pwm::Error as _;
/// The output trait [`PwmForce`] writes to, re-exported so that a firmware
/// can name it (a function generic over its timer) without a dependency on
/// `embedded-hal` of its own.
pub use embedded_hal::pwm::SetDutyCycle;

use crate::compensation::{positive, ConfigError, Setting};
use crate::error::SampleError;
use crate::fixed_point::Q16;
use crate::scalar::{Scalar, Units};

/// The two conversions between a number and a timer's duty steps that a
/// [`PwmForce`] needs, for `f32` and [`Q16`] (integer arithmetic only).
pub trait Duty: Scalar {
    /// `self` clamped to [0, 1] times `steps`, rounded to nearest.
    fn of_steps(self, steps: u16) -> u16;
    /// `duty/steps` (0 for `steps` = 0).
    fn from_steps(duty: u16, steps: u16) -> Self;
}

impl Duty for f32 {
    fn of_steps(self, steps: u16) -> u16 {
        let fraction = if self > 1.0 {
            1.0
        } else if self > 0.0 {
            self
        } else {
            0.0
        };
        // In [0, steps]: `as` saturates, never panics.
        libm::roundf(fraction * f32::from(steps)) as u16
    }
    fn from_steps(duty: u16, steps: u16) -> Self {
        if steps == 0 {
            0.0
        } else {
            f32::from(duty) / f32::from(steps)
        }
    }
}

impl Duty for Q16 {
    fn of_steps(self, steps: u16) -> u16 {
        // raw ≤ 2¹⁶ and steps < 2¹⁶: the product and the rounding fit u32.
        let raw = self.to_bits().clamp(0, 1 << 16) as u32;
        (raw.wrapping_mul(u32::from(steps)).wrapping_add(1 << 15) >> 16) as u16
    }
    fn from_steps(duty: u16, steps: u16) -> Self {
        match (u32::from(duty) << 16).checked_div(u32::from(steps)) {
            // duty ≤ steps in use; a larger duty saturates at 32767.
            Some(raw) => Q16::from_bits(raw.min(i32::MAX as u32) as i32),
            None => Q16::ZERO,
        }
    }
}

/// How a signed force maps to an unsigned duty cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum DutyMode {
    /// 50 % is 0 N; 0 % and 100 % are ∓F_full.
    Centered,
    /// The duty is |F|/F_full; [`Applied::reverse`] carries the sign.
    Magnitude,
}

/// What was written.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Applied<T = f32> {
    /// The duty written, 0 … `max_duty_cycle()`.
    pub duty: u16,
    /// The force [N] (model units) this duty represents, after saturation
    /// and rounding.
    pub force: T,
    /// The requested force was beyond ±F_full.
    pub saturated: bool,
    /// The force is negative (for `Magnitude`: drive the direction pin).
    pub reverse: bool,
}

/// A PWM channel driven as a force output, in the number type `T` (`f32`
/// in N, or [`Q16`] in units of Fs).
#[derive(Debug)]
pub struct PwmForce<P, T = f32> {
    pwm: P,
    full_scale: T,
    mode: DutyMode,
}

impl<P: SetDutyCycle> PwmForce<P, f32> {
    /// Wraps `pwm`; `full_scale` F_full [N] is the force at full scale
    /// (finite, > 0). The output is not written until [`write`](Self::write).
    pub fn new(pwm: P, full_scale: f32, mode: DutyMode) -> Result<Self, ConfigError> {
        Self::with_units(pwm, full_scale, mode, Units::SI)
    }
}

impl<P: SetDutyCycle, T: Duty> PwmForce<P, T> {
    /// Wraps `pwm` for forces in the number type of a model with `units`
    /// ([`Model::units`](crate::Model::units)); `full_scale` F_full [N]
    /// (finite, > 0, representable in `T`).
    pub fn with_units(
        pwm: P,
        full_scale: f32,
        mode: DutyMode,
        units: Units,
    ) -> Result<Self, ConfigError> {
        positive(full_scale, Setting::FullScale)?;
        let full_scale = T::from_f32(full_scale / units.force)
            .filter(|f| *f > T::ZERO)
            .ok_or(ConfigError(Setting::FullScale))?;
        Ok(Self {
            pwm,
            full_scale,
            mode,
        })
    }

    /// Writes the force `force` [N] (model units).
    ///
    /// A non-finite force is rejected with [`SampleError::Force`] and leaves
    /// the output unchanged; a driver error comes back as
    /// [`SampleError::Pwm`] with the kind of
    /// the driver's error ([`embedded_hal::pwm::Error::kind`]).
    pub fn write(&mut self, force: T) -> Result<Applied<T>, SampleError> {
        if !force.is_finite() {
            return Err(SampleError::Force);
        }
        let steps = self.pwm.max_duty_cycle();
        let one = T::ONE;
        let half = T::from_steps(1, 2);
        let ratio = force / self.full_scale;
        let saturated = ratio > one || ratio < -one;
        let ratio = if ratio > one {
            one
        } else if ratio < -one {
            -one
        } else {
            ratio
        };
        let fraction = match self.mode {
            DutyMode::Centered => half + half * ratio,
            DutyMode::Magnitude => ratio.abs(),
        };
        let duty = fraction.of_steps(steps);
        let written = T::from_steps(duty, steps);
        let represented = match self.mode {
            DutyMode::Centered => (written + written - one) * self.full_scale,
            DutyMode::Magnitude if force < T::ZERO => -(written * self.full_scale),
            DutyMode::Magnitude => written * self.full_scale,
        };
        self.pwm
            .set_duty_cycle(duty)
            .map_err(|e| SampleError::Pwm(e.kind()))?;
        Ok(Applied {
            duty,
            force: represented,
            saturated,
            reverse: force < T::ZERO,
        })
    }

    /// The force at full scale F_full [N] (model units). With
    /// [`inner_mut`](Self::inner_mut) and [`release`](Self::release):
    ///
    /// ```
    /// use breakaway::hal::{DutyMode, PwmForce};
    /// use embedded_hal::pwm::{ErrorType, SetDutyCycle};
    ///
    /// /// A 1000-step timer channel that records the duty.
    /// struct Channel { duty: u16, enabled: bool }
    /// impl ErrorType for Channel { type Error = core::convert::Infallible; }
    /// impl SetDutyCycle for Channel {
    ///     fn max_duty_cycle(&self) -> u16 { 1000 }
    ///     fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {
    ///         self.duty = duty;
    ///         Ok(())
    ///     }
    /// }
    ///
    /// let channel = Channel { duty: 0, enabled: false };
    /// let mut out = PwmForce::new(channel, 2.0, DutyMode::Centered).unwrap();
    /// assert_eq!(out.full_scale(), 2.0);
    /// out.inner_mut().enabled = true;
    /// out.write(1.0).unwrap(); // +F_full/2: 75 %
    /// let channel = out.release();
    /// assert_eq!((channel.duty, channel.enabled), (750, true));
    /// ```
    pub fn full_scale(&self) -> T {
        self.full_scale
    }

    /// The wrapped PWM channel.
    pub fn inner(&self) -> &P {
        &self.pwm
    }

    /// The wrapped PWM channel, mutably (to enable it, change its period…).
    pub fn inner_mut(&mut self) -> &mut P {
        &mut self.pwm
    }

    /// Returns the wrapped PWM channel.
    pub fn release(self) -> P {
        self.pwm
    }
}
