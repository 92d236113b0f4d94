//! The number types the model runs on.
//!
//! The friction model is written once, generic over [`Scalar`]. A number type
//! supplies plain arithmetic through the `core::ops` traits and, through its
//! associated [`Curves`] type, the two non-polynomial functions of the model:
//! the [Stribeck curve](crate::model_overview#stribeck-curve) S(v) and the
//! [presliding](crate::model_overview#presliding) shape g(w) = w·(1 − ln w).
//! For `f32` these are evaluated with the single-precision kernels of
//! [`fastmath`](crate::fastmath); the fixed-point type [`Q16`](crate::Q16)
//! supplies table-based curves and reuses the state machine and the predictor
//! unchanged.

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap. Integer arithmetic is written with explicit wrapping or checks.
#![allow(clippy::arithmetic_side_effects)]

use core::ops::{Add, Div, Mul, Neg, Sub};

use crate::params::{ParamError, Params};

/// A number type the friction model can run on.
///
/// Contract: the operators are total — they never panic and never wrap
/// (IEEE arithmetic for floats, saturation for fixed point, division by zero
/// included) — so the generic model code has no panic path.
pub trait Scalar:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// The largest finite value.
    const MAX: Self;
    /// Relative tolerance of iterative solvers (a few units in the last place).
    const TOLERANCE: Self;
    /// The curves S(v) and g(w) evaluated in this number type.
    type Curves: Curves<Self>;

    /// Converts a parameter or constant; `None` when it is not representable.
    fn from_f32(x: f32) -> Option<Self>;
    /// Converts back to `f32` (for reports; never used on the per-sample path).
    fn to_f32(self) -> f32;
    /// `false` for NaN and ±∞ (a fixed-point type is always finite).
    fn is_finite(self) -> bool;
    /// Clamps an overflowed result to the largest finite magnitude.
    fn saturate(self) -> Self;

    /// The units in which this number type carries forces, velocities and
    /// lengths for a parameter set: SI for `f32`; per-unit for fixed point
    /// (see [`fixed_point`](crate::fixed_point)).
    #[inline]
    fn units(_params: &Params) -> Units {
        Units::SI
    }

    /// |self|.
    #[inline(always)]
    fn abs(self) -> Self {
        negated_if(self, self < Self::ZERO)
    }

    /// `self`·`sign` for `sign` = ±1: −`self` for a negative `sign`.
    #[inline(always)]
    fn signed(self, sign: Self) -> Self {
        negated_if(self, sign < Self::ZERO)
    }

    /// `false` when |`self`| may reach half the largest finite value, or
    /// is NaN: a sum with a number of magnitude up to [`MAX`](Self::MAX)/4
    /// cannot overflow when `true`. A fixed-point type, whose operations
    /// saturate, may always return `true`.
    #[inline(always)]
    fn is_moderate(self) -> bool {
        self.is_finite()
    }

    /// `self`·`rhs` where the caller knows the exact product to be far
    /// inside the range (|self·rhs| ≤ 256 at most): a fixed-point type
    /// skips its saturation check. The model uses it where the bound holds
    /// by construction: a force difference (|ΔH| ≤ 2·Fs) times g ∈ [0, 1],
    /// and a saturated travel (≤ 128·z_max in fixed point) times 1/z_max.
    #[inline(always)]
    fn mul_in_range(self, rhs: Self) -> Self {
        self * rhs
    }

    /// `self`/`rhs` for `rhs` > 0 where a quotient to within a few parts
    /// in a million is enough (the break-away predictor's force rate and
    /// time): a fixed-point type replaces its exact 64-bit division by a
    /// reciprocal from a table (no divide instruction on ARMv6-M). Exact
    /// (IEEE) for `f32`; any `rhs` ≤ 0 takes the exact division.
    #[inline(always)]
    fn div_approx(self, rhs: Self) -> Self {
        self / rhs
    }

    /// The smaller of two numbers.
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        if other < self {
            other
        } else {
            self
        }
    }
}

/// The units of a model's numbers, in SI: a force of 1 in model units is
/// `force` newtons, and so on. Time is always in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Units {
    /// Newtons per model force unit.
    pub force: f32,
    /// Metres per second per model velocity unit.
    pub velocity: f32,
    /// Metres per model length unit.
    pub length: f32,
}

impl Units {
    /// Plain SI units (the `f32` model).
    pub const SI: Units = Units {
        force: 1.0,
        velocity: 1.0,
        length: 1.0,
    };
}

/// The non-polynomial functions of the model for one parameter set.
pub trait Curves<T>: Sized + Clone {
    /// Checks that the curves of a validated parameter set can be
    /// represented in `T`; `Err` names the parameter that cannot.
    fn check(params: &Params) -> Result<(), ParamError>;
    /// Builds the curves of a parameter set that passed
    /// [`check`](Self::check). Infallible, so that the result is written
    /// where the caller keeps it (a table is not copied through the stack).
    fn build(params: &Params) -> Self;
    /// Rebuilds the curves in place for a parameter set that passed
    /// [`check`](Self::check) (no copy of a table through the stack).
    fn rebuild(&mut self, params: &Params) {
        *self = Self::build(params);
    }
    /// Stribeck magnitude S(v) = Fc + (Fs − Fc)·exp(−(|v|/V)^δ) at the velocity
    /// `v` ([Stribeck curve](crate::model_overview#stribeck-curve)), in model
    /// units (N and m/s for `f32`).
    fn stribeck(&self, v: T) -> T;
    /// Presliding shape g(w) = w·(1 − ln w) for `w` in [0, 1]; 0 for `w ≤ 0`,
    /// 1 for `w ≥ 1` ([presliding](crate::model_overview#presliding)).
    fn shape(&self, w: T) -> T;
    /// S(v) as [`stribeck`](Self::stribeck) where it is evaluated without
    /// a call and `viscous` (σ·v) is [moderate](Scalar::is_moderate),
    /// `None` elsewhere: the state machine's straight path, which then
    /// leaves the sample to its general path. A table may skip the test of
    /// σ·v where |v| inside it bounds σ·v by construction.
    #[doc(hidden)]
    #[inline(always)]
    fn stribeck_fast(&self, v: T, viscous: T) -> Option<T>
    where
        T: Scalar,
    {
        if viscous.is_moderate() {
            Some(self.stribeck(v))
        } else {
            None
        }
    }
    /// The state machine's test for gross sliding and g in one (a table
    /// can test the range of `w` once for both): `Some(Some(g(w)))` for
    /// `w` < 1 (as [`shape`](Self::shape)), `Some(None)` for `w` ≥ 1 and
    /// NaN, `None` where g is not evaluated without a call (the straight
    /// path then leaves the sample to the general one).
    #[doc(hidden)]
    #[inline(always)]
    fn shape_fast(&self, w: T) -> Option<Option<T>>
    where
        T: Scalar,
    {
        if w < T::ONE {
            Some(Some(self.shape(w)))
        } else {
            Some(None)
        }
    }
    /// The smallest positive root v of v·S(v) = `c` for `c` ≥ 0 (the
    /// break-away velocity of [`Variant::Consistent`](crate::Variant)), and
    /// S(v); `None` when the solve does not converge.
    ///
    /// The default is the fixed-point iteration v ← c/S(v) from c/S(0)
    /// ([`predictor`](crate::predictor)); `f32` and [`Q16`](crate::Q16)
    /// replace it, where v·S(v) is monotone, by Newton's iteration on their
    /// tables (with this one as the fallback).
    fn consistent_root(&self, c: T) -> Option<(T, T)>
    where
        T: Scalar,
    {
        crate::predictor::fixed_point_root(self, c)
    }
}

impl Scalar for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const MAX: Self = f32::MAX;
    const TOLERANCE: Self = 4.0 * f32::EPSILON;
    type Curves = crate::curves::CurvesF32;

    #[inline(always)]
    fn from_f32(x: f32) -> Option<Self> {
        x.is_finite().then_some(x)
    }
    #[inline(always)]
    fn to_f32(self) -> f32 {
        self
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    /// One multiply, exact for ±1.
    #[inline(always)]
    fn signed(self, sign: Self) -> Self {
        self * sign
    }
    /// One test of the bits: |x| < 2¹²⁷ (NaN fails).
    #[inline(always)]
    fn is_moderate(self) -> bool {
        (self.to_bits() & 0x7fff_ffff) < 0x7f00_0000
    }
    #[inline(always)]
    fn saturate(self) -> Self {
        if f32::is_finite(self) {
            self
        } else {
            overflowed(self)
        }
    }
}

/// The rare path of `f32::saturate`: ±∞ → ±`f32::MAX`. NaN, which finite
/// inputs never produce, maps to 0.
#[cold]
#[inline(never)]
fn overflowed(x: f32) -> f32 {
    if x > 0.0 {
        f32::MAX
    } else if x < 0.0 {
        -f32::MAX
    } else {
        0.0
    }
}

/// −`x` when `negative`, else `x`: the one branch of [`Scalar::abs`] and
/// [`Scalar::signed`].
#[inline(always)]
fn negated_if<T: Scalar>(x: T, negative: bool) -> T {
    if negative {
        -x
    } else {
        x
    }
}
