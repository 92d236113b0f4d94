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

use embedded_hal::pwm::SetDutyCycle;

use crate::compensation::{positive, ConfigError, Setting};

/// How a signed force maps to an unsigned duty cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DutyMode {
    /// 50 % is 0 N; 0 % and 100 % are ∓F_full.
    Centered,
    /// The duty is |F|/F_full; [`Applied::reverse`] carries the sign.
    Magnitude,
}

/// What was written.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Applied {
    /// The duty written, 0 … `max_duty_cycle()`.
    pub duty: u16,
    /// The force [N] this duty represents (after saturation and rounding).
    pub force: f32,
    /// The requested force was beyond ±F_full.
    pub saturated: bool,
    /// The force is negative (for `Magnitude`: drive the direction pin).
    pub reverse: bool,
}

/// Why a force was not written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WriteError<E> {
    /// The force is NaN or infinite; the output was left unchanged.
    NonFiniteForce,
    /// The PWM driver failed.
    Pwm(E),
}

/// A PWM channel driven as a force output.
#[derive(Debug)]
pub struct PwmForce<P> {
    pwm: P,
    full_scale: f32,
    mode: DutyMode,
}

impl<P: SetDutyCycle> PwmForce<P> {
    /// Wraps `pwm`; `full_scale` F_full [N] is the force at full scale
    /// (finite, > 0). The output is not written until [`write`](Self::write).
    pub fn new(pwm: P, full_scale: f32, mode: DutyMode) -> Result<Self, ConfigError> {
        positive(full_scale, Setting::FullScale)?;
        Ok(Self {
            pwm,
            full_scale,
            mode,
        })
    }

    /// Writes the force `force` [N].
    pub fn write(&mut self, force: f32) -> Result<Applied, WriteError<P::Error>> {
        if !force.is_finite() {
            return Err(WriteError::NonFiniteForce);
        }
        let max = f32::from(self.pwm.max_duty_cycle());
        let ratio = force / self.full_scale;
        let saturated = !(-1.0..=1.0).contains(&ratio);
        let ratio = ratio.clamp(-1.0, 1.0);
        let fraction = match self.mode {
            DutyMode::Centered => 0.5 + 0.5 * ratio,
            DutyMode::Magnitude => libm::fabsf(ratio),
        };
        // In [0, max]: `as` saturates, never panics.
        let duty = libm::roundf(fraction * max) as u16;
        let written = if max > 0.0 {
            f32::from(duty) / max
        } else {
            0.0
        };
        let represented = match self.mode {
            DutyMode::Centered => (2.0 * written - 1.0) * self.full_scale,
            DutyMode::Magnitude if force < 0.0 => -written * self.full_scale,
            DutyMode::Magnitude => written * self.full_scale,
        };
        self.pwm.set_duty_cycle(duty).map_err(WriteError::Pwm)?;
        Ok(Applied {
            duty,
            force: represented,
            saturated,
            reverse: force < 0.0,
        })
    }

    /// The force at full scale F_full [N].
    pub fn full_scale(&self) -> f32 {
        self.full_scale
    }

    /// The wrapped PWM channel.
    pub fn inner(&self) -> &P {
        &self.pwm
    }

    /// Returns the wrapped PWM channel.
    pub fn release(self) -> P {
        self.pwm
    }
}
