//! The one error of the per-sample path, a sample that cannot be used, and
//! the one error that collects all of the library's.
//!
//! See [`SampleError`] and [`Error`].

use core::fmt;

/// Why a sample was rejected: the signal that is NaN or infinite, or (for
/// `hal::PwmForce`) the driver's failure.
///
/// Every `update` of the library ([`Presliding`](crate::Presliding), the
/// [`compensation`](crate::compensation) blocks) and
/// `hal::PwmForce::write` (feature `hal`) check their inputs for NaN and ±∞
/// and return this error, naming the signal at fault; the state (or the
/// output) is then left as it was, and the next finite sample proceeds
/// normally. Parameters are checked once, when the blocks are built
/// ([`ParamError`](crate::ParamError),
/// [`ConfigError`](crate::compensation::ConfigError)), so nothing else can go
/// wrong in a control period. One type for the whole loop lets a control
/// function use `?` on every block:
///
/// ```
/// use breakaway::compensation::{DisturbanceObserver, ObserverConfig};
/// use breakaway::{Model, Params, Presliding, SampleError};
///
/// fn period(
///     model: &Model<f32>,
///     axis: &mut Presliding<i64>,
///     observer: &mut DisturbanceObserver,
///     (count, v, u): (i64, f32, f32),
/// ) -> Result<f32, SampleError> {
///     let f = axis.update(model, count, v)?; // friction [N]
///     let r = observer.update(u, v, f)?; // what the model missed [N]
///     Ok(f + r)
/// }
///
/// let model = Model::<f32>::new(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3,
///     delta: 1.0, sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?;
/// let mut axis = Presliding::<i64>::new(0, 1e-8).unwrap();
/// let config = ObserverConfig { mass: 2.0, bandwidth: 100.0, period: 1e-3 };
/// let mut observer = DisturbanceObserver::new(config).unwrap();
/// assert!(period(&model, &mut axis, &mut observer, (100, 1e-4, 0.5)).is_ok());
/// let e = period(&model, &mut axis, &mut observer, (100, f32::NAN, 0.5));
/// assert_eq!(e, Err(SampleError::Velocity));
/// assert_eq!(e.unwrap_err().to_string(), "velocity sample is not finite");
/// # Ok::<(), breakaway::ParamError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SampleError {
    /// The position sample is NaN or infinite.
    Position,
    /// The velocity (sample or estimate) is NaN or infinite.
    Velocity,
    /// A force (from the model or the feedforward, or the force to write to
    /// the output) is NaN or infinite.
    Force,
    /// The force command u is NaN or infinite.
    Command,
    /// The PWM driver refused the duty cycle (feature `hal`), as the
    /// driver's [`embedded_hal::pwm::ErrorKind`]. The duty was computed; the
    /// output may not have changed.
    #[cfg(feature = "hal")]
    #[cfg_attr(docsrs, doc(cfg(feature = "hal")))]
    Pwm(embedded_hal::pwm::ErrorKind),
}

impl SampleError {
    /// What went wrong, in a few words (the [`Display`](fmt::Display) text
    /// without the driver's detail).
    ///
    /// ```
    /// use breakaway::{Model, Params, Presliding, SampleError};
    /// let p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                  sigma: 0.0, z_max: 1e-5, epsilon: 0.0 };
    /// let model = Model::<f32>::new(p).unwrap();
    /// let mut axis = Presliding::<f32>::new(0.0, 1.0).unwrap();
    /// let e = axis.update(&model, f32::NAN, 0.0).unwrap_err();
    /// assert_eq!(e, SampleError::Position);
    /// assert_eq!(e.message(), "position sample is not finite");
    /// ```
    pub const fn message(&self) -> &'static str {
        match self {
            SampleError::Position => "position sample is not finite",
            SampleError::Velocity => "velocity sample is not finite",
            SampleError::Force => "force is not finite",
            SampleError::Command => "force command is not finite",
            #[cfg(feature = "hal")]
            SampleError::Pwm(_) => "PWM driver error",
        }
    }
}

impl fmt::Display for SampleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        #[cfg(feature = "hal")]
        if let SampleError::Pwm(kind) = self {
            return write!(f, "{}: {kind}", self.message());
        }
        f.write_str(self.message())
    }
}

impl core::error::Error for SampleError {}

#[cfg(feature = "defmt")]
impl defmt::Format for SampleError {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "{=str}", self.message());
    }
}

/// Any error of the library, for a function that builds several blocks
/// and runs them with `?`, as firmware does (no allocator, so no
/// `Box<dyn Error>`): each of the library's error types converts into it.
///
/// The blocks keep their own error types (a setting is checked where it is
/// given, a sample where it enters); this one only collects them.
///
/// ```
/// use breakaway::compensation::{DisturbanceObserver, ObserverConfig};
/// use breakaway::{Error, Model, Params, Presliding, SampleError};
///
/// // Start-up and one period, as a firmware's `run()` would hold them.
/// fn run(v: f32) -> Result<f32, Error> {
///     let model = Model::<f32>::new(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3,
///         delta: 1.0, sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?; // ParamError
///     let mut axis = Presliding::<i64>::new(0, 1e-8)?; // ScaleError
///     let config = ObserverConfig { mass: 2.0, bandwidth: 100.0, period: 1e-3 };
///     let mut observer = DisturbanceObserver::new(config)?; // ConfigError
///     let f = axis.update(&model, 100, v)?; // SampleError
///     Ok(f + observer.update(0.5, v, f)?)
/// }
///
/// assert!(run(1e-4).is_ok());
/// assert_eq!(run(f32::NAN), Err(Error::Sample(SampleError::Velocity)));
/// assert_eq!(run(f32::NAN).unwrap_err().to_string(), "velocity sample is not finite");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Error {
    /// A model parameter out of its range ([`Model::new`](crate::Model::new)).
    Param(crate::ParamError),
    /// A setting of a compensation block out of its range.
    Config(crate::ConfigError),
    /// A position scale that is not finite and positive.
    Scale(crate::ScaleError),
    /// A break-away prediction that cannot be made.
    Predict(crate::PredictError),
    /// A sample that cannot be used (see [`SampleError`]).
    Sample(SampleError),
    /// A value outside the range of the number type, from a conversion that
    /// returned `None` (`Q16::from_f32`, `Model::velocity`,
    /// `Model::position_scale` and the like), with what it was: for
    /// `.ok_or(Error::Range("set-point"))?`.
    Range(&'static str),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Param(e) => e.fmt(f),
            Error::Config(e) => e.fmt(f),
            Error::Scale(e) => e.fmt(f),
            Error::Predict(e) => e.fmt(f),
            Error::Sample(e) => e.fmt(f),
            Error::Range(what) => write!(f, "{what} is outside the range of the number type"),
        }
    }
}

// Transparent: the message is the inner error's (`Display`), so the inner
// error is not also given as the source.
impl core::error::Error for Error {}

macro_rules! into_error {
    ($($variant:ident($from:ty)),*) => {
        $(impl From<$from> for Error {
            fn from(e: $from) -> Self {
                Error::$variant(e)
            }
        })*
    };
}

into_error!(
    Param(crate::ParamError),
    Config(crate::ConfigError),
    Scale(crate::ScaleError),
    Predict(crate::PredictError),
    Sample(SampleError)
);
