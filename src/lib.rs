#![doc = include_str!("../README.md")]
#![no_std]
// docs.rs builds with `--cfg docsrs` (Cargo.toml): feature-gated items show
// the feature they need.
#![cfg_attr(docsrs, feature(doc_cfg))]
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
#[cfg_attr(docsrs, doc(cfg(feature = "cortex-m")))]
pub mod cycles;
mod error;
pub mod fastmath;
pub mod fixed_point;
#[cfg(feature = "hal")]
#[cfg_attr(docsrs, doc(cfg(feature = "hal")))]
pub mod hal;
pub mod model;
pub mod model_overview;
pub mod params;
pub mod position;
pub mod predictor;
pub mod presliding;
pub mod scalar;

// The settings' error beside the other error types, as users look for it.
pub use crate::compensation::ConfigError;
pub use crate::curves::{shape_f32, Curves, CurvesF32, DefaultCurves};
pub use crate::error::{Error, SampleError};
pub use crate::fixed_point::{CountScale, TableCurves, Q16};
pub use crate::model::Model;
pub use crate::params::{Param, ParamError, Params};
pub use crate::position::Position;
pub use crate::predictor::{
    BreakAway, BreakAwayPredictor, PredictError, Variant, DEFAULT_BOUNDARY,
};
pub use crate::presliding::{Presliding, ScaleError, TurningPoint};
pub use crate::scalar::{Scalar, Units};
