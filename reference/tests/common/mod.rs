//! Shared fixtures of the reference's tests.
#![allow(dead_code)] // each test file uses its own subset

use breakaway_reference::Model;

/// The paper's Fig. 5 setting (MODEL.md §4): Fc = 1 N, Fs = 1.5 N, σ = 0,
/// m = 1 kg, z_max = 10 µm, with V = 1 mm/s and δ = 1, as the repository's
/// model file `lab/models/fig5.toml` gives it.
pub fn paper() -> Model {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../lab/models/fig5.toml");
    Model::load(std::path::Path::new(path)).expect("lab/models/fig5.toml")
}
