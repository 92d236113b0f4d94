//! The number types the model runs on.
//!
//! The friction model is written once, generic over [`Scalar`]: plain
//! arithmetic through the `core::ops` traits, total (never a panic, never a
//! wrap), and the conversions at the boundary. What a number type does not
//! say is how the model's two non-polynomial functions are evaluated, the
//! [Stribeck curve](crate::model_overview#stribeck-curve) S(v) and the
//! [presliding](crate::model_overview#presliding) shape g(w) = w·(1 − ln w),
//! nor in which units: that is the [`Curves`](crate::curves::Curves) a
//! [`Model`](crate::Model) is built with (for `f32` the single-precision
//! kernels of [`fastmath`](crate::fastmath), SI units; for
//! [`Q16`](crate::Q16) tables, per-unit).

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap. Integer arithmetic is written with explicit wrapping or checks.
#![allow(clippy::arithmetic_side_effects)]

use core::ops::{Add, Div, Mul, Neg, Sub};

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

    /// Converts a parameter or constant; `None` when it is not representable.
    fn from_f32(x: f32) -> Option<Self>;
    /// Converts back to `f32` (for reports; never used on the per-sample path).
    fn to_f32(self) -> f32;
    /// `false` for NaN and ±∞ (a fixed-point type is always finite).
    fn is_finite(self) -> bool;
    /// Clamps an overflowed result to the largest finite magnitude.
    fn saturate(self) -> Self;

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

impl Scalar for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const MAX: Self = f32::MAX;

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
