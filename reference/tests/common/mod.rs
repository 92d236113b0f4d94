//! Shared fixtures of the reference's tests.
#![allow(dead_code)] // each test file uses its own subset

use breakaway_reference::{Effects, Model};

/// The paper's Fig. 5 setting (MODEL.md §4): Fc = 1 N, Fs = 1.5 N, σ = 0,
/// m = 1 kg, z_max = 10 µm, with V = 1 mm/s and δ = 1.
pub fn paper() -> Model {
    Model {
        mass: 1.0,
        fc: 1.0,
        fs: 1.5,
        v_stribeck: 1e-3,
        delta: 1.0,
        sigma: 0.0,
        z_max: 1e-5,
        epsilon: 0.0,
        effects: Effects::default(),
    }
}
