//! # breakaway
//!
//! Friction for motion control, after M. Ruderman, "On break-away forces in
//! actuated motion systems with nonlinear friction" (Mechatronics): a Stribeck
//! steady-state curve, a rate-independent presliding state machine with the
//! hysteresis shape g(w) = w·(1 − ln w) after each turning point, and a
//! predictor of the break-away force as a function of the force rate.
//!
//! `#![no_std]`, no allocation, no panic on any input. The equations, names
//! and units are those of [`model_overview`]; each module cites the section
//! it implements.
//!
//! ```
//! use breakaway::{BreakAwayPredictor, Model, Params, Presliding, Variant};
//!
//! let model = Model::<f32>::new(Params {
//!     fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
//!     sigma: 0.0, z_max: 1e-5, epsilon: 0.0,
//! })?;
//!
//! // Positions as encoder counts of 0.1 µm: exact at any distance.
//! let mut axis = Presliding::<i64>::new(0, 1e-7).unwrap();
//! let f = axis.update(&model, 50, 1e-4).unwrap(); // 5 µm into presliding
//! assert!(f > 0.0 && f < 1.5);
//!
//! let predictor = BreakAwayPredictor::new(&model, 0.95).unwrap();
//! let ba = predictor.predict(&model, Variant::Consistent, 1.0).unwrap();
//! assert!(ba.f_ba > 1.0 && ba.f_ba < 1.5);
//! # Ok::<(), breakaway::ParamError>(())
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Units are written in brackets in the docs ([N], [s], [m/s]), which rustdoc
// would otherwise try to resolve as links.
#![allow(rustdoc::broken_intra_doc_links)]
// No panic path on any input: no unwrap/expect/panic, no indexing that can
// go out of bounds, no integer arithmetic that can overflow unchecked.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::arithmetic_side_effects
    )
)]

pub mod compensation;
pub mod curves;
#[cfg(all(feature = "cortex-m", not(breakaway_armv6m)))]
pub mod cycles;
pub mod fastmath;
pub mod fixed_point;
#[cfg(feature = "hal")]
pub mod hal;
pub mod model;
pub mod model_overview;
pub mod params;
pub mod position;
pub mod predictor;
pub mod presliding;
pub mod scalar;

pub use crate::curves::{shape_f32, CurvesF32};
pub use crate::fixed_point::{CountScale, TableCurves, Q16};
pub use crate::model::Model;
pub use crate::params::{Param, ParamError, Params};
pub use crate::position::Position;
pub use crate::predictor::{
    BreakAway, BreakAwayPredictor, PredictError, Variant, DEFAULT_BOUNDARY,
};
pub use crate::presliding::{Presliding, SampleError, ScaleError, TurningPoint};
pub use crate::scalar::{Curves, Scalar, Units};

/// The README's code blocks, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
