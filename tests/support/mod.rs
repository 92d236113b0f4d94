//! The one place of test support: the paper's parameter sets, a seeded
//! generator and the random stroke motion of the long runs.
//!
//! Used by the library's tests (`mod support;`) and, through `#[path]`, by
//! the tests against the reference (`tests-ref/tests/common`), the firmware
//! examples (`firmware/examples/common`), `cargo xtask` and the lab's closed-loop
//! benchmark, so that the MCU, the host test and the host replay draw the
//! same motion with the same parameters. `core` only: the firmware
//! examples are `no_std`.
#![allow(dead_code)] // each user takes its own subset

use breakaway::Params;

/// The paper's Fig. 5 setting (`lab/models/fig5.toml`): Fc = 1 N,
/// Fs = 1.5 N, σ = 0, z_max = 10 µm, with V = 1 mm/s and δ = 1.
pub const FIG5: Params = Params {
    fc: 1.0,
    fs: 1.5,
    v_stribeck: 1e-3,
    delta: 1.0,
    sigma: 0.0,
    z_max: 1e-5,
    epsilon: 0.0,
};

/// The encoder counts of the velocity-loop recipes (README, `compensation`
/// docs): an axis that starts from rest and slides at 5 mm/s, one 10 nm
/// count per ms. The README's test, the `velocity_loop_fixed` firmware and
/// its host run in `cargo xtask` take them from here.
pub const RECIPE_COUNTS: [i32; 11] = [0, 0, 40, 160, 400, 800, 1300, 1800, 2300, 2800, 3300];

/// The force rates k [N/s] of the break-away table (`breakaway_table`
/// firmware, checked row by row by `cargo xtask test`): the paper's grid,
/// k = 0.01, then 1 … 29 in steps of 2, and 30 N/s.
pub const BREAKAWAY_RATES: [f32; 17] = [
    0.01, 1.0, 3.0, 5.0, 7.0, 9.0, 11.0, 13.0, 15.0, 17.0, 19.0, 21.0, 23.0, 25.0, 27.0, 29.0, 30.0,
];

/// The long runs' setting: Fig. 5 with a shape exponent off the usual ones
/// (δ = 1.3) and viscous friction (σ = 0.2 N·s/m).
pub const LONG_RUN: Params = Params {
    delta: 1.3,
    sigma: 0.2,
    ..FIG5
};

/// The plant of the closed-loop benchmark (`breakaway-lab closed-loop` and
/// the firmware example `closed_loop`): Fc +25 %, Fs +20 %, V +30 % and
/// z_max +30 % against the compensator's [`FIG5`].
pub const CLOSED_LOOP_PLANT: Params = Params {
    fc: 1.25,
    fs: 1.8,
    v_stribeck: 1.3e-3,
    z_max: 1.3e-5,
    ..FIG5
};

/// xorshift64*: a small seeded generator, the same on the host and the MCU.
#[derive(Clone, Debug)]
pub struct Rng(pub u64);

impl Rng {
    /// The seed of the long runs.
    pub const SEED: u64 = 0x9e37_79b9_7f4a_7c15;

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [0, n) (n > 0).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

/// Random motion in encoder counts, one sample per 1 ms period: strokes of
/// 1 count to 3·z_max (3000 counts of z_max/1000) either way at 1 to 64
/// counts per sample, each started by a rest sample (the same position
/// again) that carries the stroke's velocity [m/s]. About half the samples
/// lie in presliding.
#[derive(Clone, Debug)]
pub struct Strokes {
    rng: Rng,
    count: f32,
    x: i64,
    target: i64,
    step: i64,
    v: f32,
}

impl Strokes {
    /// From position 0, with `count` metres per count, seeded with
    /// [`Rng::SEED`].
    pub fn new(count: f32) -> Self {
        Self {
            rng: Rng(Rng::SEED),
            count,
            x: 0,
            target: 0,
            step: 1,
            v: 0.0,
        }
    }
}

impl Iterator for Strokes {
    /// Position [counts] and velocity estimate [m/s].
    type Item = (i64, f32);

    fn next(&mut self) -> Option<(i64, f32)> {
        if self.x == self.target {
            let len = 1 + self.rng.below(3000) as i64;
            self.target = if self.rng.below(2) == 0 {
                self.x + len
            } else {
                self.x - len
            };
            self.step = 1 + self.rng.below(64) as i64;
            self.v = (self.target - self.x).signum() as f32 * self.step as f32 * self.count / 1e-3;
        } else if self.target > self.x {
            self.x = (self.x + self.step).min(self.target);
        } else {
            self.x = (self.x - self.step).max(self.target);
        }
        Some((self.x, self.v))
    }
}

/// The larger of `worst` and `error`, a NaN kept: `f64::max` drops a NaN,
/// so an error fold written with it reads a comparison that produced NaN
/// as no error at all, and the bound checked after it passes having
/// compared nothing. Once NaN, the fold stays NaN and fails any `<=` bound.
pub fn worse(worst: f64, error: f64) -> f64 {
    if worst.is_nan() || error <= worst {
        worst
    } else {
        error
    }
}
