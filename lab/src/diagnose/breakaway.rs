//! The break-away channel: the friction peak after each reversal, measured
//! against two models.
//!
//! The per-sample residual discounts the samples where an axis breaks away
//! (the presliding force at a quantised position is known only to
//! `|∂H/∂x|·q`, and the acceleration estimate smears the start of sliding),
//! so two models that differ only there fit a record about equally well:
//! `offset` and `asymmetry` shift the sliding force alike (`F0` against
//! `a·Fc`) and differ by `a·(Fs − Fc)` at the break-away only. The peak of
//! the friction after a reversal does not depend on when, sample by
//! sample, it is reached; compared peak against peak, the measurement says
//! which of the two models is right.
//!
//! For each departure `k` (a reversal of the measured motion, or its
//! start after a rest) the peak of the measured friction `d·(W*ū − m·â)`
//! in the window where the axis breaks away is `y_k`, the peaks of the two
//! models' friction (`W*F`, the same kernel, the same window) are `c_k`
//! (the current model) and `a_k` (its alternative). With means over the
//! departures of each direction,
//! `λ = (ȳ⁺ − c̄⁺ − ȳ⁻ + c̄⁻)/(ā⁺ − c̄⁺ − ā⁻ + c̄⁻)`: `λ ≈ 0` where the
//! current model is right, `λ ≈ 1` where the alternative is. The
//! difference between the directions is what tells `offset` from
//! `asymmetry`; what both directions share (the noise that raises every
//! measured peak, a drift of both levels) cancels in it.

use super::Model;
use crate::residual::Prepared;

/// Multiple of the Stribeck velocity `V` [m/s] at which a departure's
/// window closes: past it the dip has decayed (`exp(−3^δ)` ≤ 5 % at
/// δ ≥ 1) and the two models' sliding forces agree.
pub const WINDOW_SPEED: f64 = 3.0;

/// Fewest departures, in each direction, for the channel to judge.
pub const MIN_DEPARTURES: usize = 2;

/// Standard errors between `λ` and the midpoint `½` for the channel to
/// decide ([`Verdict::decided`]).
pub const DECISIVE_SE: f64 = 2.0;

/// Standard errors within which `λ` must lie of 0 or of 1 for the channel
/// to decide (version 8.5). Peaks that follow neither model say that the
/// break-aways are not MODEL.md's, not which of the two is right: on the
/// LuGre records 3700004 and 3700082 of the suite-like draw 3700000–
/// (asymmetry hidden) the channel read λ = 6.96 ± 0.45 and
/// 38 000 ± 10 400 and swapped `asymmetry` for `offset`. Over the verdicts
/// of the development records (every version's reports, 690 distinct
/// verdicts with `offset` or `asymmetry` hidden) the decisive verdicts for
/// the look-alike outside 3 standard errors of 0 and 1 were right 5 times
/// and wrong 9; at 2 standard errors, right 10 times and wrong 9.
pub const CONSISTENT_SE: f64 = 3.0;

/// One break-away window: samples `start..end` after a reversal or a rest,
/// towards `direction` (±1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Departure {
    /// First sample of the window (the turning point, or the rest's
    /// first sample).
    pub start: usize,
    /// One past the last sample.
    pub end: usize,
    /// Direction of the motion in the window (±1).
    pub direction: f64,
}

/// The departures of a record: from each turning point of the measured
/// motion (the direction of `v̂`, counted only where `|v̂|` exceeds the
/// rest threshold), and from each rest of at least
/// [`super::MIN_DWELL_REST`] after which the motion goes on the same way,
/// until `|v̂|` reaches `speed` [m/s] or the motion turns again; only
/// windows that reach `speed` count.
pub fn departures(p: &Prepared, speed: f64) -> Vec<Departure> {
    let valid = p.valid();
    let mut out = Vec::new();
    let mut direction = 0.0;
    // The last sample still moving the old way (or at rest): the turning
    // point, where the presliding branch starts.
    let mut turn = valid.start;
    let mut open: Option<Departure> = None;
    let min_rest = (super::MIN_DWELL_REST / p.dt).ceil() as usize;
    for i in valid.clone() {
        let v = p.v[i];
        let moving = !p.still[i] && v.abs() > p.v_rest;
        if moving && v.signum() == direction && i - turn > min_rest {
            open = Some(Departure {
                start: turn + 1,
                end: i,
                direction,
            });
        }
        if moving && v.signum() != direction {
            // A window that turns before reaching `speed` is dropped (a
            // dither, or a reversal that never broke away).
            // The first direction of the record has no reversal before it.
            if direction != 0.0 {
                open = Some(Departure {
                    start: turn,
                    end: i,
                    direction: v.signum(),
                });
            }
            direction = v.signum();
        }
        if moving && v.signum() == direction {
            turn = i;
        }
        if let Some(d) = open {
            if v.abs() >= speed {
                out.push(Departure { end: i + 1, ..d });
                open = None;
            }
        }
    }
    out
}

/// What the channel says of a current model against its alternative.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Verdict {
    /// Departures compared (both directions).
    pub departures: usize,
    /// Share of the models' peak difference the measured peaks follow:
    /// 0 the current model, 1 the alternative.
    pub lambda: f64,
    /// Standard error of `lambda`.
    pub se: f64,
}

impl Verdict {
    /// Whether the peaks follow one of the two models: `λ` within
    /// [`CONSISTENT_SE`] standard errors of 0 or of 1.
    pub fn consistent(&self) -> bool {
        self.lambda.abs().min((self.lambda - 1.0).abs()) <= CONSISTENT_SE * self.se
    }

    /// Whether the peaks decide: `λ` [`consistent`](Verdict::consistent)
    /// and more than [`DECISIVE_SE`] standard errors from ½. `Some(true)`
    /// for the alternative.
    pub fn decided(&self) -> Option<bool> {
        (self.consistent() && (self.lambda - 0.5).abs() >= DECISIVE_SE * self.se)
            .then_some(self.lambda > 0.5)
    }
}

/// The departures on which `current` can be judged (windows to
/// [`WINDOW_SPEED`] times its `V`), or `None` where fewer than
/// [`MIN_DEPARTURES`] go either way: checked before the look-alike is
/// fitted, which is the costly part.
pub fn judgeable(p: &Prepared, current: &Model) -> Option<Vec<Departure>> {
    let deps = departures(p, WINDOW_SPEED * current.v_stribeck);
    let per_direction = |s: f64| deps.iter().filter(|d| d.direction == s).count();
    (per_direction(1.0) >= MIN_DEPARTURES && per_direction(-1.0) >= MIN_DEPARTURES).then_some(deps)
}

/// Compares `current` with `alternative` at the departures `deps` (from
/// [`judgeable`]); `None` where the two models' peaks do not differ
/// between the directions.
pub fn compare(
    p: &Prepared,
    deps: &[Departure],
    current: &Model,
    alternative: &Model,
) -> Option<Verdict> {
    let measured = p.measured_friction(current.mass);
    let cur = p.filter_all(&p.friction(current));
    let alt = p.filter_all(&p.friction(alternative));
    let peak = |s: &[f64], d: &Departure| {
        s[d.start..d.end]
            .iter()
            .map(|f| d.direction * f)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // Per direction, the mean of `y_k − c_k` and of `a_k − c_k`, and the
    // variance of the first mean.
    let side = |s: f64| {
        let (mut n, mut gy, mut gx, mut gyy) = (0.0, 0.0, 0.0, 0.0);
        for d in deps.iter().filter(|d| d.direction == s) {
            let c = peak(&cur, d);
            let y = peak(&measured, d) - c;
            n += 1.0;
            gy += y;
            gyy += y * y;
            gx += peak(&alt, d) - c;
        }
        let (my, mx) = (gy / n, gx / n);
        let var = (gyy / n - my * my).max(0.0) * n / (n - 1.0);
        (my, mx, var / n)
    };
    let ((y_up, x_up, v_up), (y_down, x_down, v_down)) = (side(1.0), side(-1.0));
    // The difference between the directions: what a shift of one
    // direction against the other leaves, free of what both share (the
    // noise that raises every measured peak, a drift of both levels).
    let gap = x_up - x_down;
    if gap == 0.0 || !gap.is_finite() {
        return None;
    }
    Some(Verdict {
        departures: deps.len(),
        lambda: (y_up - y_down) / gap,
        se: (v_up + v_down).sqrt() / gap.abs(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::{Asymmetry, Effects, Offset};
    use crate::residual::{tests::record, Window};
    use std::f64::consts::PI;

    /// A sinusoid of 2 mm at 0.5 Hz over 10 s, quantised to 1 µm.
    fn position(t: f64) -> f64 {
        (2e-3 * (PI * t).sin() / 1e-6).round() * 1e-6
    }

    fn prepared(rec: &crate::data::Record) -> Prepared {
        Prepared::with_window(
            rec,
            Window {
                velocity: 4,
                force: 16,
            },
        )
    }

    /// A 1 kg axis with a Stribeck dip (Fs = 1.5·Fc) and, with `a`, an
    /// asymmetry of `a`; without, the offset of the same sliding shift.
    fn model(asymmetry: bool) -> Model {
        let a = 0.1;
        let fc = 2.0;
        Model {
            mass: 1.0,
            fc,
            fs: 3.0,
            v_stribeck: 1e-3,
            delta: 2.0,
            sigma: 0.0,
            z_max: 20e-6,
            epsilon: 0.0,
            effects: Effects {
                asymmetry: asymmetry.then_some(Asymmetry { a }),
                offset: (!asymmetry).then_some(Offset { f0: a * fc }),
                ..Effects::default()
            },
        }
    }

    /// A verdict decides only where the peaks follow one of the two
    /// models: λ far outside 0…1 in standard errors (the LuGre record
    /// 3700004's 6.96 ± 0.45) decides nothing, however far from ½.
    #[test]
    fn peaks_that_follow_neither_model_decide_nothing() {
        let verdict = |lambda, se| Verdict {
            departures: 18,
            lambda,
            se,
        };
        assert_eq!(verdict(1.02, 0.1).decided(), Some(true));
        assert_eq!(verdict(-0.05, 0.1).decided(), Some(false));
        assert_eq!(verdict(0.6, 0.1).decided(), None);
        let far = verdict(6.957, 0.4499);
        assert!(!far.consistent());
        assert_eq!(far.decided(), None);
        // Within three standard errors of 1: decided for the alternative.
        assert_eq!(verdict(1.25, 0.1).decided(), Some(true));
        assert_eq!(verdict(1.35, 0.1).decided(), None);
    }

    /// One window per reversal of the sinusoid, alternating in
    /// direction, each opening at a turning point of the quantised
    /// position.
    #[test]
    fn a_window_per_reversal() {
        let p = prepared(&record(10_000, 1e-3, position));
        let deps = departures(&p, 3e-3);
        // Turning points at t = 0.5, 1.5, …, 9.5 s; the motion before the
        // first one opens no window.
        assert_eq!(deps.len(), 10, "{deps:?}");
        for (k, d) in deps.iter().enumerate() {
            let turn = 0.5 + k as f64;
            assert!(
                (p.t[d.start] - turn).abs() < 0.05,
                "window {k} opens at {}",
                p.t[d.start]
            );
            assert!(d.end > d.start);
            assert_eq!(d.direction, if k % 2 == 0 { -1.0 } else { 1.0 });
        }
    }

    /// The force of the asymmetric axis along the sinusoid (the lab's own
    /// friction walk: an in-model check of the channel's arithmetic, not
    /// evidence of the workflow): its peaks follow the asymmetry (λ ≈ 1
    /// with `offset` as the current model, λ ≈ 0 the other way round), and
    /// the verdict is decisive both ways.
    #[test]
    fn the_peaks_follow_the_model_that_made_them() {
        let rec0 = record(10_000, 1e-3, position);
        let truth = model(true);
        let f = prepared(&rec0).friction(&truth);
        // u = F + m·ẍ, at the half-sample where `ū` sits (ẍ of the
        // unquantised sinusoid).
        let u: Vec<f64> = rec0
            .t
            .iter()
            .zip(&f)
            .map(|(&t, f)| f - truth.mass * 2e-3 * PI * PI * (PI * t).sin())
            .collect();
        let rec = crate::data::Record { u, ..rec0 };
        let p = prepared(&rec);
        let deps = judgeable(&p, &model(false)).expect("departures both ways");
        let v = compare(&p, &deps, &model(false), &truth).expect("a verdict");
        assert!((v.lambda - 1.0).abs() < 0.1, "{v:?}");
        assert_eq!(v.decided(), Some(true));
        let v = compare(&p, &deps, &truth, &model(false)).expect("a verdict");
        assert!(v.lambda.abs() < 0.1, "{v:?}");
        assert_eq!(v.decided(), Some(false));
    }
}
