//! Independent `f64` reference of the `breakaway` friction model and a
//! full-dynamics simulator, written from the contract `MODEL.md` alone.
//!
//! It is the judge the firmware library is tested against; it does not depend
//! on it. Sections of MODEL.md:
//!
//! * [`model`] — parameters, validation, TOML model files (§2, §3, §5, §7);
//! * [`effect`] — the names of the effect catalogue (§5);
//! * [`curves`] — Stribeck curve `S`, `F_ss` and presliding shape `g` (§2, §3);
//! * [`presliding`] — the one-turning-point presliding state machine (§3);
//! * [`friction`] — friction with the effect catalogue composed (§5);
//! * [`predict`] — the quasi-static break-away predictor (§4);
//! * [`sim`] — full dynamics `m·ẍ = u − F` (§1, §4, §8).
//!
//! Units are SI: m, m/s, N, N/s, kg, s, written in brackets after a
//! quantity (`x` \[m\]).

// Units in brackets (`[m]`, `[N]`) are not intra-doc links.
#![allow(rustdoc::broken_intra_doc_links)]

pub mod curves;
pub mod effect;
pub mod friction;
pub mod model;
pub mod predict;
pub mod presliding;
pub mod sim;

pub use curves::{decay_of_power, shape, steady_state, stribeck, stribeck_decay};
pub use effect::{Effect, UnknownEffect};
pub use friction::{Friction, LagFilter, SampleTerms};
pub use model::{
    ArgumentError, Asymmetry, Drift, DwellStiction, Effects, FrictionalLag, Model, ModelError,
    NonlinearViscous, Offset, PositionRipple,
};
pub use predict::{
    consistent_root, phase_velocity, predict_break_away, BreakAway, PredictError, Variant,
};
pub use presliding::Presliding;
pub use sim::{
    simulate, simulate_break_away, simulate_break_away_with, DynamicBreakAway, Sample, SimError,
    SimOptions,
};
