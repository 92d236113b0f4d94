//! The presliding state machine with ONE turning point, the reference rule of
//! MODEL.md §3.
//!
//! Positions are absolute `f64` [m]. Per sample `(x, v)`:
//!
//! * **idle** (`d = 0`, `H_r = 0`, `x_r` = start position; or anchored at a
//!   measured force by [`Presliding::anchor`]): `H = H_r` while
//!   `x == x_r`; the first sample with `x != x_r` sets `d = sgn(x − x_r)`
//!   (no deadband for this first motion) and starts the branch.
//! * **new extremum** (`d·(x − x_ext) > 0`): `x_ext ← x`, `H` on the current
//!   branch `H = H_r + (d·S(v) − H_r)·g(w)`, `w = min(1, |x − x_r|/z_max)`;
//!   the value is remembered as `H(x_ext)`.
//! * **at the extremum** (`x == x_ext`): `H` on the current branch with the
//!   current `v`, and `H(x_ext)` takes this latest value: H_r is "the dry
//!   friction H at x_ext" when the reversal starts, so H stays continuous
//!   through the reversal even when v changed while the axis stood there.
//! * **pending reversal** (`0 < d·(x_ext − x) <= ε`): `H = H(x_ext)` (held).
//! * **reversal** (`d·(x_ext − x) > ε`): `d ← −d`, `x_r ← x_ext`,
//!   `H_r ← H(x_ext)` (dry friction only), then `x` is the new extremum on the
//!   new branch (already `w = |x − x_r|/z_max` along it).
//!
//! With `z_max = 0` (a model without presliding) every branch is at `w = 1`:
//! `H = d·S(v)` at once.

use crate::curves::{shape, stribeck};
use crate::model::Model;

/// Presliding memory with one turning point (MODEL.md §3).
#[derive(Clone, Debug, PartialEq)]
pub struct Presliding {
    d: i8,
    x_r: f64,
    x_ext: f64,
    h_r: f64,
    h_ext: f64,
    h: f64,
}

impl Presliding {
    /// Idle state at position `x0` [m]: `d = 0`, `H_r = 0`, `x_r = x0`, `H = 0`.
    pub fn new(x0: f64) -> Self {
        Presliding::idle(x0, 0.0)
    }

    /// Idle at `x` [m] with `H_r = H = h` [N].
    fn idle(x: f64, h: f64) -> Self {
        Presliding {
            d: 0,
            x_r: x,
            x_ext: x,
            h_r: h,
            h_ext: h,
            h,
        }
    }

    /// Takes the sample at position `x` [m] with velocity `v` [m/s] and
    /// returns `F = H + σ·v` [N] (no effects). Updates the state.
    pub fn update(&mut self, m: &Model, x: f64, v: f64) -> f64 {
        let s = stribeck(m, v);
        let h = self.step(x, m.z_max, m.epsilon, |_| s);
        h + m.sigma * v
    }

    /// Idle at a measured dry friction: `d = 0`, `x_r = x` [m],
    /// `H_r = H = h` [N]. The next sample with a different position starts a
    /// branch from `(x, h)` as after a turning point.
    ///
    /// Not part of MODEL.md §3 (whose idle state has `H_r = 0`): a
    /// measurement-side re-anchoring. While an axis is held at rest the
    /// force balance gives its friction exactly (`F = u`), but the presliding
    /// state at a quantised position is not observable (sub-count
    /// reversals), so the discrepancy workflow re-anchors the memory at the
    /// measured force instead of guessing it.
    pub fn anchor(&mut self, x: f64, h: f64) {
        *self = Presliding::idle(x, h);
    }

    /// Dry (hysteretic) friction `H` [N] after the last update (0 when idle).
    pub fn dry(&self) -> f64 {
        self.h
    }

    /// Direction `d` of the current branch: −1, +1, or 0 while idle.
    pub fn direction(&self) -> i8 {
        self.d
    }

    /// Last turning point `x_r` [m] (the start position while idle and
    /// on the first branch).
    pub fn turning_point(&self) -> f64 {
        self.x_r
    }

    /// Dry friction at the last turning point `H_r` [N] (0 until the first
    /// reversal).
    pub fn dry_at_turning_point(&self) -> f64 {
        self.h_r
    }

    /// Extremum `x_ext` [m] reached in direction `d` on the current branch.
    pub fn extremum(&self) -> f64 {
        self.x_ext
    }

    /// Dry friction `H(x_ext)` [N] remembered at the extremum (the value held
    /// during a pending reversal and taken as `H_r` when it is confirmed).
    pub fn dry_at_extremum(&self) -> f64 {
        self.h_ext
    }

    /// Normalised travel `w = min(1, |x − x_r|/z_max)` [-] of position `x` [m]
    /// from the last turning point; 1 when `z_max = 0` (no presliding),
    /// 0 while idle.
    pub fn travel(&self, z_max: f64, x: f64) -> f64 {
        if self.d == 0 {
            0.0
        } else if z_max > 0.0 {
            ((x - self.x_r).abs() / z_max).min(1.0)
        } else {
            1.0
        }
    }

    /// H on the current branch at `x` with magnitude `s` for direction `d`.
    fn branch(&self, z_max: f64, x: f64, s: f64) -> f64 {
        let w = self.travel(z_max, x);
        self.h_r + (f64::from(self.d) * s - self.h_r) * shape(w)
    }

    /// The rule of the module doc. `s_of(d)` gives the Stribeck magnitude
    /// `S` [N] for the branch direction `d` (so effects such as asymmetry can
    /// depend on the new direction). Returns the dry friction `H` [N].
    pub(crate) fn step(&mut self, x: f64, z_max: f64, eps: f64, s_of: impl Fn(i8) -> f64) -> f64 {
        if self.d == 0 {
            let d = if x > self.x_r {
                1
            } else if x < self.x_r {
                -1
            } else {
                self.h = self.h_r;
                return self.h;
            };
            self.d = d;
            self.x_ext = x;
            self.h = self.branch(z_max, x, s_of(d));
            self.h_ext = self.h;
            return self.h;
        }
        let ahead = f64::from(self.d) * (x - self.x_ext);
        if ahead > 0.0 {
            self.x_ext = x;
            self.h = self.branch(z_max, x, s_of(self.d));
            self.h_ext = self.h;
        } else if ahead == 0.0 {
            // Still at the extremum: H follows the branch with the current
            // S, and H at x_ext is this latest value, so that a reversal
            // from here starts where H is (no jump).
            self.h = self.branch(z_max, x, s_of(self.d));
            self.h_ext = self.h;
        } else if -ahead > eps {
            self.d = -self.d;
            self.x_r = self.x_ext;
            self.h_r = self.h_ext;
            self.x_ext = x;
            self.h = self.branch(z_max, x, s_of(self.d));
            self.h_ext = self.h;
        } else {
            // Pending reversal (or a non-finite x): hold H(x_ext).
            self.h = self.h_ext;
        }
        self.h
    }
}
