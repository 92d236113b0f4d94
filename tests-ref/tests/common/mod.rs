//! Shared pieces of the tests that judge the library against the f64
//! reference: the library's test support (`tests/support`: parameter sets,
//! generator, stroke motion), the parameters in the reference's terms,
//! randomized parameter sets and trajectories, a deterministic proptest
//! runner, and a plant on the reference friction.
#![allow(dead_code)] // each test file uses its own subset

use std::ops::Range;
use std::sync::Mutex;

use breakaway::Params;
use breakaway_reference as reference;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseResult, TestRng, TestRunner};

#[path = "../../../tests/support/mod.rs"]
mod support;
#[allow(unused_imports)] // each test file uses its own subset
pub use support::{worse, Rng, Strokes, FIG5, LONG_RUN};

/// The library's parameters as a reference model (m = 1 kg, no effects).
pub fn reference_model(p: &Params) -> reference::Model {
    reference::Model {
        mass: 1.0,
        fc: p.fc as f64,
        fs: p.fs as f64,
        v_stribeck: p.v_stribeck as f64,
        delta: p.delta as f64,
        sigma: p.sigma as f64,
        z_max: p.z_max as f64,
        epsilon: p.epsilon as f64,
        effects: reference::Effects::default(),
    }
}

/// The reference's break-away of `model` for the library's `variant` under
/// the force ramp k [N/s] with the boundary w_b (every valid input has one).
pub fn reference_break_away(
    model: &reference::Model,
    variant: breakaway::Variant,
    k: f64,
    w_b: f64,
) -> reference::BreakAway {
    let variant = reference::Variant::parse(variant.name()).unwrap();
    reference::predict_break_away(model, variant, k, w_b).unwrap()
}

/// Parameter sets over the ranges a motion axis meets: Fc 0.1 … 100 N,
/// Fs up to 3·Fc, V 0.1 … 100 mm/s, δ from `delta` or the usual 0.5, 1, 2,
/// σ up to Fc/V, z_max 1 µm … 1 mm, ε 0 or a half-count multiple of
/// z_max/1000 (so that no deadband comparison ties).
pub fn params(delta: Range<f32>) -> impl Strategy<Value = Params> {
    (
        -1.0f32..2.0,                                           // log10 Fc [N]
        0.0f32..2.0,                                            // Fs/Fc − 1
        -4.0f32..-1.0,                                          // log10 V [m/s]
        prop_oneof![Just(0.5f32), Just(1.0), Just(2.0), delta], // δ
        prop_oneof![Just(0.0f32), 0.0f32..1.0],                 // σ·V/Fc
        -6.0f32..-3.0,                                          // log10 z_max [m]
        prop_oneof![Just(0u32), 0u32..40],                      // ε in counts (+½)
    )
        .prop_map(|(fc, rise, v, delta, sigma, z_max, eps)| {
            let fc = 10f32.powf(fc);
            let v_stribeck = 10f32.powf(v);
            let z_max = 10f32.powf(z_max);
            let count = z_max / 1000.0;
            Params {
                fc,
                fs: fc * (1.0 + rise),
                v_stribeck,
                delta,
                sigma: sigma * fc / v_stribeck,
                z_max,
                epsilon: if eps == 0 {
                    0.0
                } else {
                    (eps as f32 + 0.5) * count
                },
            }
        })
}

/// One segment of motion: travel in counts (z_max = 1000 counts), counts
/// per sample, velocity estimate in units of V.
pub type Segment = (i64, i64, f32);

/// Trajectories of 4 to 40 segments within, near and beyond z_max, with
/// speeds up to `max_speed`·V.
pub fn trajectory(max_speed: f32) -> impl Strategy<Value = Vec<Segment>> {
    let segment = (
        prop_oneof![1i64..300, 300i64..1500, 1500i64..6000],
        any::<bool>(),
        prop_oneof![Just(1i64), 1i64..8, 8i64..80],
        prop_oneof![Just(0.0f32), 0.0f32..0.3, 0.3f32..5.0, 5.0f32..max_speed],
    )
        .prop_map(|(len, up, step, v)| (if up { len } else { -len }, step, v));
    prop::collection::vec(segment, 4..40)
}

/// The samples of a trajectory: a rest sample (the same position again)
/// before each segment, then steps to its end.
pub fn samples(segments: &[Segment]) -> Vec<(i64, f32)> {
    let mut out = Vec::new();
    let mut x = 0i64;
    for &(travel, step, v) in segments {
        let target = x + travel;
        let dir = travel.signum();
        let v = dir as f32 * v;
        out.push((x, v));
        while x != target {
            x = if dir > 0 {
                (x + step).min(target)
            } else {
                (x - step).max(target)
            };
            out.push((x, v));
        }
    }
    out
}

/// A runner with a fixed seed: the same cases on every run and machine.
pub fn runner(cases: u32) -> TestRunner {
    TestRunner::new_with_rng(
        Config {
            cases,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    )
}

/// The presliding boundary w_b of the break-away tests: the usual 0.95, or
/// any in [0.5, 0.99).
pub fn boundary() -> impl Strategy<Value = f32> {
    prop_oneof![Just(0.95f32), 0.5f32..0.99]
}

/// Runs `cases` cases of `strategy` through `test` on the deterministic
/// runner; panics with the failing case (shrunk).
pub fn check<S: Strategy>(cases: u32, strategy: &S, test: impl Fn(S::Value) -> TestCaseResult) {
    if let Err(e) = runner(cases).run(strategy, test) {
        panic!("{e}");
    }
}

/// The worst error of a randomized test and the case that gave it.
pub struct Worst(Mutex<(f64, String)>);

impl Worst {
    pub const fn new() -> Self {
        Worst(Mutex::new((0.0, String::new())))
    }

    /// Keeps `error` when it is the worst so far, with its case (described
    /// only then); a NaN is the worst of all and stays.
    pub fn record(&self, error: f64, case: impl FnOnce() -> String) {
        let mut worst = self.0.lock().unwrap();
        // Compared by bits: `worse` returns `worst.0` itself unless `error`
        // is worse, a NaN included.
        if worse(worst.0, error).to_bits() != worst.0.to_bits() {
            *worst = (error, case());
        }
    }

    /// Records `error` for `case` and fails the case where `error`
    /// exceeds `bound`.
    pub fn within(&self, error: f64, bound: f64, case: impl Fn() -> String) -> TestCaseResult {
        self.record(error, &case);
        prop_assert!(error <= bound, "error {error:e} > {bound:e} for {}", case());
        Ok(())
    }

    /// Prints `what = <worst><unit> (<case>)`.
    pub fn print(&self, what: &str, unit: &str) {
        let worst = self.0.lock().unwrap();
        println!("{what} = {:.3e}{unit} ({})", worst.0, worst.1);
    }
}

/// m·ẍ = u − F with F from the reference `Friction`, integrated by
/// semi-implicit Euler with sub-steps far below the presliding period.
pub struct Plant {
    pub model: reference::Model,
    pub friction: reference::Friction,
    pub t: f64,
    pub x: f64,
    pub v: f64,
    /// Mean friction over the last period [N].
    pub mean_friction: f64,
}

impl Plant {
    pub const SUBSTEPS: usize = 200;

    pub fn new(model: reference::Model) -> Self {
        let friction = reference::Friction::new(&model, 0.0, 0.0, 0.0);
        Self {
            model,
            friction,
            t: 0.0,
            x: 0.0,
            v: 0.0,
            mean_friction: 0.0,
        }
    }

    /// Holds `u` [N] for `period` [s].
    pub fn step(&mut self, u: f64, period: f64) {
        let h = period / Self::SUBSTEPS as f64;
        let mut sum = 0.0;
        for _ in 0..Self::SUBSTEPS {
            let f = self.friction.update(&self.model, self.t, self.x, self.v);
            sum += f;
            self.v += h * (u - f) / self.model.mass;
            self.x += h * self.v;
            self.t += h;
        }
        self.mean_friction = sum / Self::SUBSTEPS as f64;
    }
}
