//! Position samples that stay exact over long travel.
//!
//! Presliding reacts to travel of the order of z_max (micrometres), while an
//! axis may be metres or kilometres away from its origin: an `f32` absolute
//! position has a resolution of about 8 µm at 100 m. The state machine
//! therefore only ever uses *differences* of positions, taken in the type the
//! position arrives in, and scaled to metres afterwards:
//!
//! - integer encoder counts (`i32`, `i64`) — exact at any distance; the
//!   difference uses wrapping arithmetic, so an `i32` hardware counter that
//!   wraps is handled as long as two compared positions lie less than 2³¹
//!   counts apart (the state machine only compares positions within about
//!   z_max + ε + one sample's travel of each other);
//! - `f32` metres — convenient, exact only while |x| is small compared with
//!   z_max / 2⁻²³ (about 80 m for z_max = 10 µm to keep w within 1e-3):
//!   re-reference it, or use counts.

use crate::scalar::Scalar;

/// A position sample type: how to take the signed travel between two samples.
pub trait Position<T: Scalar>: Copy {
    /// `false` for a sample that must be rejected (a NaN or infinite float).
    fn is_valid(self) -> bool;
    /// The travel `self − origin` in metres, given the metres per unit of the
    /// sample type.
    fn travel_from(self, origin: Self, metres_per_unit: T) -> T;
}

impl Position<f32> for f32 {
    #[inline(always)]
    fn is_valid(self) -> bool {
        self.is_finite()
    }
    #[inline(always)]
    fn travel_from(self, origin: Self, metres_per_unit: f32) -> f32 {
        ((self - origin) * metres_per_unit).saturate()
    }
}

impl Position<f32> for i32 {
    #[inline(always)]
    fn is_valid(self) -> bool {
        true
    }
    #[inline(always)]
    fn travel_from(self, origin: Self, metres_per_unit: f32) -> f32 {
        self.wrapping_sub(origin) as f32 * metres_per_unit
    }
}

impl Position<f32> for i64 {
    #[inline(always)]
    fn is_valid(self) -> bool {
        true
    }
    #[inline(always)]
    fn travel_from(self, origin: Self, metres_per_unit: f32) -> f32 {
        (self.wrapping_sub(origin) as f32 * metres_per_unit).saturate()
    }
}
