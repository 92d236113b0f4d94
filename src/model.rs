//! A validated parameter set ready for the per-sample path
//! ([parameters](crate::model_overview#parameters)).

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap. Integer arithmetic is written with explicit wrapping or checks.
#![allow(clippy::arithmetic_side_effects)]

use crate::curves::{Curves, DefaultCurves};
use crate::params::{Param, ParamError, Params};
use crate::position::Position;
use crate::scalar::{Scalar, Units};

/// A validated friction model in the number type `T`: the coefficients that
/// the [`Presliding`](crate::Presliding) state machine and the
/// [`BreakAwayPredictor`](crate::BreakAwayPredictor) read. It holds no state;
/// one model can serve many axes.
///
/// `C` evaluates S(v) and g(w) and fixes the units; by default the number
/// type's own ([`DefaultCurves`]): [`CurvesF32`](crate::CurvesF32) for
/// `f32`, [`TableCurves<16>`](crate::TableCurves) for [`Q16`](crate::Q16)
/// (`Model<Q16, TableCurves<64>>` for a finer table). Quantities on the
/// per-sample path are in the model's [`Units`]: SI for `f32`, per-unit for
/// fixed point (force in units of Fs, velocity in units of V, see
/// [`fixed_point`](crate::fixed_point)).
#[derive(Clone, Debug)]
pub struct Model<T: Scalar = f32, C: Curves<T> = <T as DefaultCurves>::Curves> {
    params: Params,
    units: Units,
    pub(crate) curves: C,
    pub(crate) fc: T,
    pub(crate) fs: T,
    pub(crate) sigma: T,
    /// 1/z_max [1/m].
    pub(crate) inv_z_max: T,
    pub(crate) epsilon: T,
}

impl<T: Scalar, C: Curves<T>> Model<T, C> {
    /// Validates `params` against the rules of the
    /// [model](crate::model_overview#parameters) and prepares the model.
    ///
    /// ```
    /// use breakaway::{Model, Params, ParamError};
    /// let mut p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                      sigma: 0.0, z_max: 1e-5, epsilon: 0.0 };
    /// assert!(Model::<f32>::new(p).is_ok());
    /// p.fs = 0.5;
    /// assert_eq!(Model::<f32>::new(p).unwrap_err(), ParamError::StictionBelowCoulomb);
    /// ```
    pub fn new(params: Params) -> Result<Self, ParamError> {
        let [fc, fs, sigma, inv_z_max, epsilon] = Self::coefficients(&params)?;
        // Everything fallible is done: the curves are built straight into
        // the result.
        Ok(Self {
            curves: C::build(&params),
            fc,
            fs,
            sigma,
            inv_z_max,
            epsilon,
            units: C::units(&params),
            params,
        })
    }

    /// Re-parameterizes the model in place (validated as by
    /// [`new`](Self::new)); on error the model is left unchanged. For fixed
    /// point this rebuilds the S table where the model lives: the way to
    /// build a model on an MCU whose stack cannot hold a copy of it (start
    /// from [`Model::UNIT_COULOMB`](crate::Model::UNIT_COULOMB)).
    ///
    /// ```
    /// use breakaway::{Model, Params, Q16};
    /// let p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                  sigma: 0.0, z_max: 1e-5, epsilon: 0.0 };
    /// let mut model = Model::<Q16>::UNIT_COULOMB;
    /// model.set_params(p).unwrap();
    /// assert_eq!(model.params(), &p);
    /// // A rejected set leaves the model as it was.
    /// assert!(model.set_params(Params { fs: 0.5, ..p }).is_err());
    /// assert_eq!(model.params().fs, 1.5);
    /// ```
    pub fn set_params(&mut self, params: Params) -> Result<(), ParamError> {
        let [fc, fs, sigma, inv_z_max, epsilon] = Self::coefficients(&params)?;
        self.curves.rebuild(&params);
        (self.fc, self.fs, self.sigma) = (fc, fs, sigma);
        (self.inv_z_max, self.epsilon) = (inv_z_max, epsilon);
        self.units = C::units(&params);
        self.params = params;
        Ok(())
    }

    /// A model from its parts (for `const` models).
    pub(crate) const fn from_parts(
        params: Params,
        units: Units,
        curves: C,
        [fc, fs, sigma, inv_z_max, epsilon]: [T; 5],
    ) -> Self {
        Self {
            params,
            units,
            curves,
            fc,
            fs,
            sigma,
            inv_z_max,
            epsilon,
        }
    }

    /// Validates `params` and converts Fc, Fs, σ, 1/z_max and ε to model
    /// units; every check of [`new`](Self::new) happens here or in
    /// [`Curves::check`].
    fn coefficients(params: &Params) -> Result<[T; 5], ParamError> {
        params.validate()?;
        let units = C::units(params);
        // A positive parameter must stay positive once scaled.
        let convert = |param: Param, x: f32, positive: bool| {
            T::from_f32(x)
                .filter(|t| !positive || *t > T::ZERO)
                .ok_or(ParamError::OutOfRange(param))
        };
        let inv_z_max = units.length / params.z_max;
        if !inv_z_max.is_finite() {
            return Err(ParamError::OutOfRange(Param::ZMax));
        }
        let coefficients = [
            convert(Param::Fc, params.fc / units.force, true)?,
            convert(Param::Fs, params.fs / units.force, true)?,
            convert(
                Param::Sigma,
                params.sigma * units.velocity / units.force,
                false,
            )?,
            convert(Param::ZMax, inv_z_max, true)?,
            convert(Param::Epsilon, params.epsilon / units.length, false)?,
        ];
        C::check(params)?;
        Ok(coefficients)
    }

    /// The units of the model's numbers (SI for `f32`). With
    /// [`velocity`](Self::velocity) and
    /// [`position_scale`](Self::position_scale), the boundary between SI
    /// samples and a fixed-point model:
    ///
    /// ```
    /// use breakaway::{Model, Params, Presliding, Units, Q16};
    /// let p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                  sigma: 0.0, z_max: 1e-5, epsilon: 0.0 };
    /// assert_eq!(Model::<f32>::new(p).unwrap().units(), Units::SI);
    /// let model = Model::<Q16>::new(p).unwrap();
    /// let units = model.units(); // forces in Fc, velocities in V
    /// let v = model.velocity(2e-3).unwrap(); // 2 mm/s = 2·V
    /// assert!((v.to_f32() - 2.0).abs() < 1e-4);
    /// // 10 nm encoder counts as the position type of presliding.
    /// let scale = model.position_scale::<i32>(1e-8).unwrap();
    /// let mut axis = Presliding::<i32, Q16>::new(0, scale).unwrap();
    /// let force = axis.update(&model, 500, v).unwrap(); // 5 µm = z_max/2
    /// assert!(force.to_f32() * units.force > 0.5);
    /// ```
    pub fn units(&self) -> Units {
        self.units
    }

    /// A velocity [m/s] in model units, `None` when out of range.
    pub fn velocity(&self, v: f32) -> Option<T> {
        T::from_f32(v / self.units.velocity)
    }

    /// The position scale for [`Presliding::new`](crate::Presliding::new):
    /// model length units per position unit of type `P`, for positions in
    /// units of `metres_per_unit` metres (an encoder count, or 1 for metres).
    /// `None` when the scale is not finite and positive or outside the range
    /// the number type admits (for [`Q16`](crate::Q16), see
    /// [`CountScale`](crate::CountScale)).
    pub fn position_scale<P: Position<T>>(&self, metres_per_unit: f32) -> Option<P::Scale> {
        P::scale(metres_per_unit / self.units.length)
    }

    /// The parameters the model was built from.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Stribeck magnitude S(v) [N] at velocity `v` [m/s] ([Stribeck
    /// curve](crate::model_overview#stribeck-curve)).
    ///
    /// ```
    /// # use breakaway::{Model, Params};
    /// let p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                  sigma: 0.2, z_max: 1e-5, epsilon: 0.0 };
    /// let model = Model::<f32>::new(p).unwrap();
    /// assert!((model.stribeck(0.0) - 1.5).abs() < 1e-5); // Fs at rest
    /// assert!((model.stribeck(-1.0) - 1.0).abs() < 1e-5); // Fc far out, either way
    /// ```
    #[inline]
    pub fn stribeck(&self, v: T) -> T {
        self.curves.stribeck(v)
    }

    /// Steady-state friction F_ss(v) = sgn(v)·S(v) + σ·v [N] ([Stribeck
    /// curve](crate::model_overview#stribeck-curve)); F_ss(0) = 0.
    ///
    /// ```
    /// # use breakaway::{Model, Params};
    /// let p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                  sigma: 0.2, z_max: 1e-5, epsilon: 0.0 };
    /// let model = Model::<f32>::new(p).unwrap();
    /// assert_eq!(model.steady_state(0.0), 0.0);
    /// assert!((model.steady_state(1.0) - 1.2).abs() < 1e-5); // Fc + σ·v
    /// assert!((model.steady_state(-1.0) + 1.2).abs() < 1e-5);
    /// ```
    #[inline]
    pub fn steady_state(&self, v: T) -> T {
        let viscous = (self.sigma * v).saturate();
        if v > T::ZERO {
            (self.curves.stribeck(v) + viscous).saturate()
        } else if v < T::ZERO {
            (viscous - self.curves.stribeck(v)).saturate()
        } else {
            T::ZERO
        }
    }

    /// Presliding shape g(w) = w·(1 − ln w), clamped to [0, 1]
    /// ([presliding](crate::model_overview#presliding)).
    ///
    /// ```
    /// # use breakaway::{Model, Params};
    /// let p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                  sigma: 0.2, z_max: 1e-5, epsilon: 0.0 };
    /// let model = Model::<f32>::new(p).unwrap();
    /// assert_eq!(model.shape(0.0), 0.0);
    /// assert!((model.shape(1.0) - 1.0).abs() < 1e-6);
    /// assert!((model.shape(0.5) - 0.8466).abs() < 1e-4); // 0.5·(1 + ln 2)
    /// ```
    #[inline]
    pub fn shape(&self, w: T) -> T {
        self.curves.shape(w)
    }
}
