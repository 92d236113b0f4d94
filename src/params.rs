//! Model parameters and their validation
//! ([parameters](crate::model_overview#parameters)).
//!
//! [`Params`] is the parameter set in SI units as a user writes it down.
//! [`Model::new`](crate::Model::new) checks it once against every rule of the
//! contract; the per-sample path then never checks again.

use core::fmt;

/// The parameters of the friction model, in SI units
/// ([parameters](crate::model_overview#parameters)).
///
/// Rotary axes read rad, N·m and rad/s for m, N and m/s.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Params {
    /// Coulomb level Fc [N], > 0.
    pub fc: f32,
    /// Stiction level Fs [N], ≥ Fc.
    pub fs: f32,
    /// Stribeck velocity V [m/s], > 0.
    pub v_stribeck: f32,
    /// Shape exponent δ of the Stribeck curve, > 0 (typically 0.5 … 2).
    pub delta: f32,
    /// Viscous coefficient σ [N·s/m], ≥ 0.
    pub sigma: f32,
    /// Presliding distance z_max [m], > 0: the travel after a turning point
    /// over which friction reaches the steady-state curve.
    pub z_max: f32,
    /// Turning-point deadband ε [m], ≥ 0 (0 for clean position data).
    pub epsilon: f32,
}

impl Params {
    /// Checks every rule of the [model](crate::model_overview#parameters) and
    /// returns the first violation, in the order of the fields; the error
    /// names the parameter and its key in a model file.
    ///
    /// ```
    /// use breakaway::{Param, ParamError, Params};
    /// let p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                  sigma: 0.0, z_max: 1e-5, epsilon: 0.0 };
    /// assert_eq!(p.validate(), Ok(()));
    /// let e = Params { sigma: -0.1, delta: f32::NAN, ..p }.validate().unwrap_err();
    /// assert_eq!(e, ParamError::NotFinite(Param::Delta)); // δ comes before σ
    /// assert_eq!(e.param(), Param::Delta);
    /// assert_eq!(e.param().key(), "delta");
    /// ```
    pub fn validate(&self) -> Result<(), ParamError> {
        let fields = [
            (Param::Fc, self.fc),
            (Param::Fs, self.fs),
            (Param::VStribeck, self.v_stribeck),
            (Param::Delta, self.delta),
            (Param::Sigma, self.sigma),
            (Param::ZMax, self.z_max),
            (Param::Epsilon, self.epsilon),
        ];
        for (param, value) in fields {
            if !value.is_finite() {
                return Err(ParamError::NotFinite(param));
            }
        }
        if self.fc <= 0.0 {
            return Err(ParamError::CoulombNotPositive);
        }
        if self.fs < self.fc {
            return Err(ParamError::StictionBelowCoulomb);
        }
        if self.v_stribeck <= 0.0 {
            return Err(ParamError::StribeckVelocityNotPositive);
        }
        if self.delta <= 0.0 {
            return Err(ParamError::ShapeExponentNotPositive);
        }
        if self.sigma < 0.0 {
            return Err(ParamError::ViscousNegative);
        }
        if self.z_max <= 0.0 {
            return Err(ParamError::PreslidingDistanceNotPositive);
        }
        if self.epsilon < 0.0 {
            return Err(ParamError::DeadbandNegative);
        }
        Ok(())
    }
}

/// Names a parameter of [`Params`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Param {
    /// Fc.
    Fc,
    /// Fs.
    Fs,
    /// V.
    VStribeck,
    /// δ.
    Delta,
    /// σ.
    Sigma,
    /// z_max.
    ZMax,
    /// ε.
    Epsilon,
}

impl Param {
    /// The parameter's key in a model file
    /// ([parameters](crate::model_overview#parameters)).
    pub const fn key(self) -> &'static str {
        match self {
            Param::Fc => "fc",
            Param::Fs => "fs",
            Param::VStribeck => "v_stribeck",
            Param::Delta => "delta",
            Param::Sigma => "sigma",
            Param::ZMax => "z_max",
            Param::Epsilon => "epsilon",
        }
    }
}

/// A parameter set that breaks a rule of the
/// [model](crate::model_overview#parameters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ParamError {
    /// The parameter is NaN or infinite.
    NotFinite(Param),
    /// Fc ≤ 0.
    CoulombNotPositive,
    /// Fs < Fc.
    StictionBelowCoulomb,
    /// V ≤ 0.
    StribeckVelocityNotPositive,
    /// δ ≤ 0.
    ShapeExponentNotPositive,
    /// σ < 0.
    ViscousNegative,
    /// z_max ≤ 0.
    PreslidingDistanceNotPositive,
    /// ε < 0.
    DeadbandNegative,
    /// The value is valid but the number type cannot represent a quantity
    /// derived from it (for instance 1/V overflows `f32` for V < 3e-39).
    OutOfRange(Param),
}

impl ParamError {
    /// The parameter at fault.
    pub const fn param(&self) -> Param {
        match *self {
            ParamError::NotFinite(p) | ParamError::OutOfRange(p) => p,
            ParamError::CoulombNotPositive => Param::Fc,
            ParamError::StictionBelowCoulomb => Param::Fs,
            ParamError::StribeckVelocityNotPositive => Param::VStribeck,
            ParamError::ShapeExponentNotPositive => Param::Delta,
            ParamError::ViscousNegative => Param::Sigma,
            ParamError::PreslidingDistanceNotPositive => Param::ZMax,
            ParamError::DeadbandNegative => Param::Epsilon,
        }
    }
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let key = self.param().key();
        match self {
            ParamError::NotFinite(_) => write!(f, "parameter `{key}` must be finite"),
            ParamError::CoulombNotPositive => write!(f, "parameter `fc` must be > 0"),
            ParamError::StictionBelowCoulomb => write!(f, "parameter `fs` must be >= fc"),
            ParamError::StribeckVelocityNotPositive => {
                write!(f, "parameter `v_stribeck` must be > 0")
            }
            ParamError::ShapeExponentNotPositive => write!(f, "parameter `delta` must be > 0"),
            ParamError::ViscousNegative => write!(f, "parameter `sigma` must be >= 0"),
            ParamError::PreslidingDistanceNotPositive => {
                write!(f, "parameter `z_max` must be > 0")
            }
            ParamError::DeadbandNegative => write!(f, "parameter `epsilon` must be >= 0"),
            ParamError::OutOfRange(_) => {
                write!(f, "parameter `{key}` is out of the number type's range")
            }
        }
    }
}

impl core::error::Error for ParamError {}
