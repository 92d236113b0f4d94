//! Position samples that stay exact over long travel.
//!
//! Presliding reacts to travel of the order of z_max (micrometres), while an
//! axis may be metres or kilometres away from its origin: an `f32` absolute
//! position has a resolution of about 8 µm at 100 m. The state machine
//! therefore only ever uses *differences* of positions, taken in the type the
//! position arrives in, and scaled to metres afterwards:
//!
//! - integer encoder counts (`i32`, `i64`) — exact at any distance; the
//!   difference uses wrapping 32-bit arithmetic, so an `i32` hardware counter
//!   that wraps is handled, as long as consecutive samples differ by less
//!   than 2³¹ counts (the state machine only compares positions within about
//!   z_max + ε + one sample's travel of each other);
//! - `f32` metres — convenient, exact only while |x| is small compared with
//!   z_max / 2⁻²³ (about 80 m for z_max = 10 µm to keep w within 1e-3):
//!   re-reference it, or use counts.

use crate::scalar::Scalar;

/// A position sample type: how to take the signed travel between two samples.
pub trait Position<T: Scalar>: Copy {
    /// The scale from one position unit to the model's length unit (metres
    /// for `f32` models: an `f32`; for fixed point a
    /// [`CountScale`](crate::CountScale), which keeps its relative precision
    /// for any encoder resolution the type admits).
    type Scale: Copy + core::fmt::Debug + PartialEq;
    /// `false` for a sample that must be rejected (a NaN or infinite float).
    fn is_valid(self) -> bool;
    /// The scale for `units` model length units per position unit; `None`
    /// when `units` is not finite and positive or outside what the number
    /// type can represent.
    fn scale(units: f32) -> Option<Self::Scale>;
    /// `false` for a scale that [`scale`](Self::scale) would not have made
    /// (a user-built `f32` that is not finite and positive).
    fn is_valid_scale(scale: Self::Scale) -> bool;
    /// The travel `self − origin` in model length units, given the scale of
    /// the sample type.
    fn travel_from(self, origin: Self, scale: Self::Scale) -> T;
    /// `true` when d·[`travel_from`](Self::travel_from)`(origin, scale)`
    /// is certainly not negative for the direction d = `direction` (±1),
    /// whatever the scale; `false` when it may be (the travel is then
    /// computed). The state machine's test for a reversal; the default
    /// never rules one out.
    #[doc(hidden)]
    #[inline(always)]
    fn not_behind(self, origin: Self, direction: i8) -> bool {
        let _ = (origin, direction);
        false
    }
}

/// An encoder count type: two counts are compared by their wrapping
/// difference on the low 32 bits (see the module documentation).
pub(crate) trait Count: Copy {
    /// `self − origin` on the low 32 bits, wrapping.
    fn difference(self, origin: Self) -> i32;
}

impl Count for i32 {
    #[inline(always)]
    fn difference(self, origin: Self) -> i32 {
        self.wrapping_sub(origin)
    }
}

impl Count for i64 {
    #[inline(always)]
    fn difference(self, origin: Self) -> i32 {
        (self as i32).wrapping_sub(origin as i32)
    }
}

/// d·(a − b) ≥ 0 for counts whose wrapping difference a − b is `difference`
/// (the travel is the difference times a positive scale, rounded:
/// monotone, 0 at 0). The product wraps only for a difference of −2³¹
/// and d = −1, to −2³¹: then `false`, which is always allowed.
#[inline(always)]
pub(crate) fn counts_not_behind(difference: i32, direction: i8) -> bool {
    difference.wrapping_mul(i32::from(direction)) >= 0
}

/// A float scale [m per unit] is valid when finite and positive.
#[inline]
fn float_scale(units: f32) -> Option<f32> {
    (units.is_finite() && units > 0.0).then_some(units)
}

/// `Position<f32>` for a sample type with an `f32` scale [m per unit]:
/// `valid` tells a usable sample, `travel` the travel in metres from
/// `origin` to the sample given the scale `m`, and the optional
/// `not_behind` overrides [`Position::not_behind`] (count types).
macro_rules! position_f32 {
    (
        $(#[$doc:meta])* $ty:ty,
        valid: |$v:ident| $valid:expr,
        travel: |$x:ident, $origin:ident, $m:ident| $travel:expr
        $(, not_behind: |$nx:ident, $norigin:ident, $nd:ident| $not_behind:expr)? $(,)?
    ) => {
        $(#[$doc])*
        impl Position<f32> for $ty {
            type Scale = f32;
            #[inline(always)]
            fn is_valid(self) -> bool {
                let $v = self;
                $valid
            }
            fn scale(units: f32) -> Option<f32> {
                float_scale(units)
            }
            fn is_valid_scale(scale: f32) -> bool {
                float_scale(scale).is_some()
            }
            #[inline(always)]
            fn travel_from(self, $origin: Self, $m: f32) -> f32 {
                let $x = self;
                $travel
            }
            $(
                #[inline(always)]
                fn not_behind(self, $norigin: Self, $nd: i8) -> bool {
                    let $nx = self;
                    $not_behind
                }
            )?
        }
    };
}

position_f32!(
    f32,
    valid: |x| x.is_finite(),
    travel: |x, origin, m| ((x - origin) * m).saturate(),
);
position_f32!(
    i32,
    valid: |_x| true,
    travel: |x, origin, m| x.difference(origin) as f32 * m,
    not_behind: |x, origin, d| counts_not_behind(x.difference(origin), d),
);
position_f32!(
    /// As for `i32`, the difference is taken on the low 32 bits (wrapping), so
    /// two compared positions must lie less than 2³¹ counts apart (21 m at 10 nm
    /// per count). The state machine only compares a sample with the extremum
    /// and the turning points of a branch that has not reached gross sliding,
    /// all within z_max + ε plus one sample's travel: the requirement is that
    /// consecutive samples differ by less than 2³¹ counts. A 64-bit absolute
    /// count therefore stays exact over any travel at the cost of a 32-bit one.
    i64,
    valid: |_x| true,
    travel: |x, origin, m| x.difference(origin) as f32 * m,
    not_behind: |x, origin, d| counts_not_behind(x.difference(origin), d),
);
