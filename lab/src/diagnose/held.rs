//! The held force: the static level a still axis shows, against the
//! fitted model's `Fs`.
//!
//! At a still sample the force balance gives the friction itself
//! (`F = ū − m·â`, `â ≈ 0`), and without `dwell_stiction` MODEL.md §2–§5
//! bound it: `|H| ≤ S(0) = Fs·sc`, so the friction an axis holds is at most
//! `Fs·sc + F0 + A·sin(2π·x/λ + φ)` (`sc` the asymmetry and drift scale of
//! the direction it holds in). The residual gives still samples no weight
//! (they re-anchor the walk, [`Prepared::still`]) and discounts the
//! break-aways, so nothing in the fit sees that bound, and on records of
//! the independent generator the fitted `Fs` often lies below what the
//! axis was seen to hold. A model that lets the axis slip under a force it
//! held under-predicts every break-away; where the held force exceeds the
//! fitted level in both directions, [`pin`] writes `Fs` at the held level
//! and refits the rest of the model with it fixed.

use super::*;

/// Standard deviations of the force noise (`σ0`, that of the filtered
/// residual) between the largest held force and the level read from it:
/// the largest of some thousands of still samples carries about four of
/// them.
pub const HELD_MARGIN_SIGMAS: f64 = 5.0;

/// Least rise of `Fs`, as a share of the fitted one, for [`pin`] to refit.
pub const MIN_RAISE: f64 = 0.01;

/// What the still samples say of the model's static level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StaticLevel {
    /// The static level [N] each direction's held force shows (`+`, `−`):
    /// the largest held friction less the model's offset, ripple and dwell
    /// raise, over the direction's asymmetry and drift scale, less
    /// [`HELD_MARGIN_SIGMAS`]·`σ0`; `−∞` without still samples.
    pub held: [f64; 2],
    /// The fitted model's `Fs` [N].
    pub fitted: f64,
    /// The `Fs` written [N]: the fitted one, or the held level where
    /// [`pin`] raised it.
    pub written: f64,
    /// Whether the model had no Stribeck dip (`Fs = Fc`) and [`pin`]
    /// restored one with `Fs` at the held level.
    pub restored: bool,
}

impl StaticLevel {
    /// The level both directions hold [N] (the smaller of the two: an
    /// offset or asymmetry the model lacks raises one direction and lowers
    /// the other, so the smaller never overstates `Fs`).
    pub fn both(&self) -> f64 {
        self.held[0].min(self.held[1])
    }

    /// Whether `Fs` was raised to the held level.
    pub fn raised(&self) -> bool {
        self.written > self.fitted
    }
}

/// The ripple force [N] of `m` at sample `i` of `p`, `A·sin(2π·x/λ + φ)`
/// (0 without `position_ripple`).
pub fn ripple_at(p: &Prepared, m: &Model, i: usize) -> f64 {
    m.effects.position_ripple.map_or(0.0, |r| {
        r.amplitude * (2.0 * PI * p.x[i] / r.wavelength + r.phase).sin()
    })
}

/// The drift factor `1 + β·t` [-] of `m` at sample `i` of `p`, `t` from
/// the record's start, as the walk's `Friction` counts it (1 without
/// `drift`).
pub fn drift_at(p: &Prepared, m: &Model, i: usize) -> f64 {
    let beta = m.effects.drift.map_or(0.0, |d| d.beta);
    1.0 + beta * (p.t[i] - p.t[0])
}

/// The held levels of `m` on `p` (see [`StaticLevel::held`]).
pub fn held_levels(p: &Prepared, m: &Model) -> [f64; 2] {
    let measured = p.measured_friction(m.mass);
    let e = &m.effects;
    let f0 = e.offset.map_or(0.0, |o| o.f0);
    let a = e.asymmetry.map_or(0.0, |s| s.a);
    let dwell = e.dwell_stiction.map_or(0.0, |d| d.delta_fs);
    let margin = HELD_MARGIN_SIGMAS * p.sigma0;
    let mut held = [f64::NEG_INFINITY; 2];
    for i in p.valid().filter(|&i| p.still[i]) {
        let friction = measured[i] - f0 - ripple_at(p, m, i);
        let drift = drift_at(p, m, i);
        for (k, d) in [1.0, -1.0].into_iter().enumerate() {
            let sc = (1.0 + a * d) * drift;
            if sc > 0.0 {
                held[k] = held[k].max((d * friction - dwell - margin) / sc);
            }
        }
    }
    held
}

/// Presliding distances and Stribeck shapes [`pin`] refits from, as
/// factors on the model's `V` and `z_max` and the exponent `δ` (`None`:
/// the model's).
const PIN_STARTS: [(f64, Option<f64>, f64); 5] = [
    (1.0, None, 1.0),
    (0.5, None, 1.0),
    (2.0, None, 1.0),
    (1.0, Some(1.0), 1.0),
    (1.0, Some(2.0), 1.0),
];

/// What the still samples of `p` show of `m`'s static level, and `m` with
/// `Fs` at the level they hold in both directions,
/// the other parameters refitted with `Fs − Fc` fixed (from the starts of
/// `PIN_STARTS`, the best sound fit on the held-out blocks), where that
/// level exceeds the fitted `Fs` by [`MIN_RAISE`] (`None`: `m` stands).
/// A model without a Stribeck dip (`Fs = Fc`: the base fit found none, or
/// it was dropped as not identifiable or at a bound of its range) gets
/// one back where the dip with `Fs` at the held level, `V` and `δ`
/// refitted, is sound and the held-out model error is no higher than
/// without it: the axis was seen to hold more than `Fc`, which a model
/// with `Fs = Fc` contradicts, and the motion does not contradict the
/// dip. Where the motion does not resolve the dip, the written `V` and
/// `δ` are only the best of the starts; `Fs` is the held level.
/// (Version 10.10 asked the dip to lower the held-out error as a
/// candidate must, version 10.11 only not to raise it: on 31 development
/// records without a dip under a higher held level, 10.10 restored 4 and
/// 10.11 16, each moving the written `Fs` towards the truth's or, on
/// the two with `dwell_stiction`, to what the axis held.)
pub fn pin(p: &Prepared, m: &Model) -> (StaticLevel, Option<Model>) {
    let mut level = StaticLevel {
        held: held_levels(p, m),
        fitted: m.fs,
        written: m.fs,
        restored: false,
    };
    let target = level.both();
    if target <= m.fs * (1.0 + MIN_RAISE) {
        return (level, None);
    }
    let dip = fit::has_effect(m, Effect::Stribeck);
    // The parameters of the model with the dip (of `m` itself where it
    // has one), less its height, which the held level fixes.
    let params: Vec<Param> = fit::params_of(&Model {
        fs: target,
        ..m.clone()
    })
    .into_iter()
    .filter(|q| *q != Param::FsExcess)
    .collect();
    let sound = |c: &Model| {
        fit::effects_of(c)
            .into_iter()
            .all(|e| degenerate(p, c, e).is_none())
    };
    let best = PIN_STARTS
        .par_iter()
        .map(|&(v_factor, delta, z_factor)| {
            let mut s = m.clone();
            s.fs = target;
            s.v_stribeck *= v_factor;
            s.delta = delta.unwrap_or(s.delta);
            s.z_max *= z_factor;
            fit::fit(p, &s, &params, &FitOptions::default(), &mut |_| {}).model
        })
        .filter(sound)
        .map(|c| (held_rms(p, &c).0, c))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .filter(|(rms, _)| dip || *rms <= held_rms(p, m).0)
        .map(|(_, pinned)| pinned);
    if let Some(pinned) = &best {
        level.written = pinned.fs;
        level.restored = !dip;
    }
    (level, best)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::{Asymmetry, Offset};
    use crate::residual::{tests::record, Window};

    /// An axis held still (one count throughout) at +2 N for a second, then
    /// at −1.5 N: each direction's level is its held force less the
    /// model's offset and the margin, over its asymmetry scale (the
    /// arithmetic, on a hand-made record).
    #[test]
    fn held_levels_read_each_direction_through_offset_and_asymmetry() {
        let mut rec = record(2000, 1e-3, |_| 0.0);
        rec.u = rec
            .t
            .iter()
            .map(|&t| if t < 1.0 { 2.0 } else { -1.5 })
            .collect();
        let p = Prepared::with_window(
            &rec,
            Window {
                velocity: 4,
                force: 16,
            },
        );
        assert!(p.valid().all(|i| p.still[i]));
        let mut m = fig5_model();
        m.effects.offset = Some(Offset { f0: 0.25 });
        m.effects.asymmetry = Some(Asymmetry { a: 0.1 });
        let margin = HELD_MARGIN_SIGMAS * p.sigma0;
        let [up, down] = held_levels(&p, &m);
        assert!((up - (2.0 - 0.25 - margin) / 1.1).abs() < 1e-9, "+: {up}");
        assert!(
            (down - (1.5 + 0.25 - margin) / 0.9).abs() < 1e-9,
            "-: {down}"
        );
        let level = StaticLevel {
            held: [up, down],
            fitted: 1.0,
            written: 1.0,
            restored: false,
        };
        assert_eq!(level.both(), up.min(down));
        assert!(!level.raised());
        // Drift counts time from the record's start, as the walk does: the
        // same record ten seconds later reads the same levels.
        m.effects.drift = Some(crate::reference::Drift { beta: 0.02 });
        let drifted = held_levels(&p, &m);
        assert!(drifted[0] < up, "drift raises the scale: {drifted:?}");
        let mut later = rec.clone();
        later.t.iter_mut().for_each(|t| *t += 10.0);
        let q = Prepared::with_window(
            &later,
            Window {
                velocity: 4,
                force: 16,
            },
        );
        let shifted = held_levels(&q, &m);
        for k in 0..2 {
            assert!(
                (shifted[k] - drifted[k]).abs() < 1e-9,
                "{shifted:?} against {drifted:?}"
            );
        }
    }

    /// A reversing motion with half-second holds, each move of 2 mm (a
    /// half cosine over 1 s, then the hold), quantised to 1 µm, on the
    /// axis of `fig5_model` (Fs = 1.5·Fc): the force is the model's own
    /// along the motion (an in-model check of the arithmetic of [`pin`],
    /// not evidence of the workflow), held at 1.4 N towards the next move
    /// while the axis is still.
    fn held_record() -> (Prepared, Model) {
        let truth = fig5_model();
        let hold = 0.5;
        let period = 1.0 + hold;
        // Segment `k` of a time: a hold, then a move out (k even) or back.
        let segment = |t: f64| (t / period).floor() as i64;
        let towards = |t: f64| if segment(t) % 2 == 0 { 1.0 } else { -1.0 };
        let position = |t: f64| {
            let s = t - segment(t) as f64 * period;
            let from = if segment(t) % 2 == 0 { 0.0 } else { 2e-3 };
            let to = 2e-3 - from;
            let w = if s < hold {
                0.0
            } else {
                0.5 * (1.0 - (PI * (s - hold)).cos())
            };
            ((from + (to - from) * w) / 1e-6).round() * 1e-6
        };
        let mut rec = record((8.0 * period / 1e-3) as usize, 1e-3, position);
        // Held towards the move that follows the hold.
        rec.u = rec.t.iter().map(|&t| 1.4 * towards(t)).collect();
        let window = Window {
            velocity: 4,
            force: 16,
        };
        let p0 = Prepared::with_window(&rec, window);
        let f = p0.friction(&truth);
        // u = F + m·ẍ with ẍ from the unquantised half cosine.
        rec.u = rec
            .t
            .iter()
            .zip(&f)
            .map(|(&t, f)| {
                let s = t % period;
                let a = if s < hold {
                    0.0
                } else {
                    towards(t) * 2e-3 * 0.5 * PI * PI * (PI * (s - hold)).cos()
                };
                f + truth.mass * a
            })
            .collect();
        let mut p = Prepared::with_window(&rec, window);
        let r = p.residual(&truth);
        p.set_error_weights(&truth, &r);
        (p, truth)
    }

    /// Version 10.10: a model whose dip was dropped (`Fs = Fc`) gets it
    /// back with `Fs` at the level the still axis held (1.4 N, less the
    /// margin) where the held-out model error is no higher with that dip
    /// (here it is lower: 8.6 mN against 43 mN); where the axis held no
    /// more than `Fc`, nothing is restored.
    #[test]
    fn a_dropped_dip_is_restored_at_the_held_level() {
        let (p, truth) = held_record();
        let mut flat = truth.clone();
        flat.fs = flat.fc;
        let (level, pinned) = pin(&p, &flat);
        let margin = HELD_MARGIN_SIGMAS * p.sigma0;
        assert!(
            (level.both() - (1.4 - margin)).abs() < 0.02,
            "held {:?}, margin {margin}",
            level.held
        );
        let pinned = pinned.expect("a dip restored at the held level");
        assert!(level.restored && level.raised(), "{level:?}");
        assert!(fit::has_effect(&pinned, Effect::Stribeck));
        assert!(held_rms(&p, &pinned).0 < held_rms(&p, &flat).0);
        // Held at no more than the Coulomb level: no dip to restore.
        let mut strong = flat.clone();
        strong.fc = 1.5;
        strong.fs = 1.5;
        let (level, pinned) = pin(&p, &strong);
        assert!(pinned.is_none() && !level.restored, "{level:?}");
    }
}
