//! The discrepancy workflow on steady-state records (MODEL.md §6):
//! constant-velocity runs with one force reading per speed, such as the
//! Indy7 joint files. They carry no dynamics, so only the effects that
//! change the steady-state curve `F(v)` can be seen: `viscous`,
//! `nonlinear_viscous`, `offset`, `asymmetry` (and `stribeck`).
//!
//! The model is MODEL.md §2 and §5 in gross sliding (`w = 1`):
//!
//! ```text
//! F(v) = d·S'(v) + σ·v + σ_n·d·|v|^n + F0,   d = sgn(v)
//! S'   = Fc·(1 + a·d) + (Fs − Fc)·(1 + a·d)·exp(−(|v|/V)^δ)
//! ```
//!
//! Rotary axes use rad/s and N·m (the Indy7 files are read in deg/s and
//! converted). The residual is `r = F_measured − F(v)`, one per point;
//! every point with index 2, 5 or 8 modulo 10 (file order) is held out
//! for the report. The selection is that of [`crate::diagnose`]: each
//! missing candidate added and refitted
//! ([`crate::fit::levenberg_marquardt`]), accepted when its BIC is lower
//! and its RMS is lower by the candidate's required gain, and only while
//! the curve misses the data by more than [`NOISE_FACTOR`] times the
//! readings' noise; a fit at a bound of its range is not a finding. The
//! RMS that decides is cross-validated over all points
//! ([`SteadyRecord::cv_rms`]), not the report's held-out one: a record of
//! 30–40 speeds holds out 9–12 points, too few to tell an exponent or a
//! dip's shape. The gap the report gives is model error, as
//! on time records: `√(rms² − noise²)` of the held-out RMS over the
//! readings' noise ([`SteadyReport::gap`]), 0 where the curve fits within
//! the noise; the held-out RMS itself is given beside it.

use crate::diagnose::{self, required_gain};
use crate::fit::{self, FitOptions, Param, Residuals};
use crate::reference::{stribeck, Asymmetry, Effect, Effects, Model, NonlinearViscous, Offset};
use crate::residual::quantile;
use crate::static_curve::Point;
use crate::Error;
use std::path::Path;

/// A steady-state curve whose cross-validated RMS
/// ([`SteadyRecord::cv_rms`]) is below this many times the readings' noise
/// ([`SteadyRecord::noise`]) lacks nothing.
pub const NOISE_FACTOR: f64 = 1.5;

/// The largest `Fs/Fc` of a Stribeck dip that comes back with an effect on
/// a curve that had lost it (`with_effect`). Measured stiction levels lie
/// within about twice the Coulomb level; 3 leaves a margin and refuses a
/// "dip" that is really a second velocity curve.
pub const MAX_RESTORED_DIP: f64 = 3.0;

/// The effects a steady-state record can show, in the order tried.
pub const STEADY_CANDIDATES: [Effect; 4] = [
    Effect::Viscous,
    Effect::NonlinearViscous,
    Effect::Offset,
    Effect::Asymmetry,
];

/// The free parameters of `m`'s structure on a steady-state record: those
/// of the record fit ([`fit::params_of`]) without the mass and `z_max`,
/// which a steady state does not show.
fn params_of(m: &Model) -> Vec<Param> {
    fit::params_of(m)
        .into_iter()
        .filter(|p| !matches!(p, Param::Mass | Param::ZMax))
        .collect()
}

/// The steady-state friction `F(v)` [N] (N·m) of `m` at velocity `v`
/// (module doc).
pub fn steady_force(m: &Model, v: f64) -> f64 {
    let e = &m.effects;
    let d = if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    };
    let sc = 1.0 + e.asymmetry.map_or(0.0, |a| a.a) * d;
    let mut scaled = m.clone();
    scaled.fc = m.fc * sc;
    scaled.fs = m.fs * sc;
    let mut f = d * stribeck(&scaled, v) + m.sigma * v;
    if let Some(nv) = &e.nonlinear_viscous {
        f += nv.sigma_n * d * v.abs().powf(nv.n);
    }
    if let Some(o) = &e.offset {
        f += o.f0;
    }
    f
}

/// Least number of mirrored speed pairs for the noise estimate from the
/// sums `F(v) + F(−v)` ([`SteadyRecord::noise`]).
const MIN_MIRRORED_PAIRS: usize = 3;

/// Folds of the cross-validation that decides the steps
/// ([`SteadyRecord::cv_rms`]).
pub const CV_FOLDS: usize = 3;

/// The fold of each point for [`SteadyRecord::cv_rms`]: the points ranked
/// by speed (the negative direction first at equal speeds), rank `k` in
/// fold `k mod CV_FOLDS`, so that neighbouring speeds and the two
/// directions of one speed fall in different folds. In file order, a
/// record of 15 speeds a direction put both directions of each speed in one
/// fold, and a dip on three speeds lost its middle one.
fn folds(points: &[Point]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        let (pa, pb) = (&points[a], &points[b]);
        pa.v.abs()
            .total_cmp(&pb.v.abs())
            .then(pa.v.total_cmp(&pb.v))
    });
    let mut fold = vec![0; points.len()];
    for (k, &i) in order.iter().enumerate() {
        fold[i] = k % CV_FOLDS;
    }
    fold
}

/// The units of a steady-state file's numbers (MODEL.md §1: a rotary axis
/// reads rad, rad/s, N·m and kg·m² for m, m/s, N and kg).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    /// The Indy7 layout: a rotary joint, read in deg/s and N·m, the speeds
    /// converted to rad/s.
    Rotary,
    /// A `v, u` CSV: SI units of a linear (m/s, N) or a rotary axis (rad/s,
    /// N·m); the file does not say which.
    Si,
}

impl Units {
    /// The units in words, for the text report.
    pub fn text(self) -> &'static str {
        match self {
            Units::Rotary => "forces in N·m, speeds in rad/s (a rotary joint, Indy7 layout)",
            Units::Si => "forces in N, speeds in m/s (N·m and rad/s if the axis is rotary)",
        }
    }

    /// The units for the JSON report.
    pub fn json(self) -> &'static str {
        match self {
            Units::Rotary => "N*m, rad/s",
            Units::Si => "N, m/s (N*m, rad/s on a rotary axis)",
        }
    }

    /// A comment line for a model file written from the record, whose key
    /// comments name the linear units (MODEL.md §7).
    pub fn model_header(self) -> Option<&'static str> {
        match self {
            Units::Rotary => Some(
                "# rotary joint (Indy7 layout): read rad, rad/s, N·m and kg·m² for the m, m/s, N and kg below\n",
            ),
            Units::Si => None,
        }
    }
}

/// A steady-state record prepared for fitting.
#[derive(Clone, Debug)]
pub struct SteadyRecord {
    /// The points (velocity [m/s] or [rad/s], force [N] or [N·m]).
    pub points: Vec<Point>,
    /// Held-out flag per point.
    pub held_out: Vec<bool>,
    /// Fold of each point for [`SteadyRecord::cv_rms`] (see `folds`).
    fold: Vec<usize>,
    /// What the numbers are in (reported, not used by the fit).
    pub units: Units,
}

impl SteadyRecord {
    /// Splits `points` (file order), in SI units ([`Units::Si`]).
    pub fn new(points: Vec<Point>) -> SteadyRecord {
        SteadyRecord::with_units(points, Units::Si)
    }

    /// Splits `points` (file order), in `units`.
    pub fn with_units(points: Vec<Point>, units: Units) -> SteadyRecord {
        let held_out = (0..points.len())
            .map(|i| matches!(i % 10, 2 | 5 | 8))
            .collect();
        let fold = folds(&points);
        SteadyRecord {
            points,
            held_out,
            fold,
            units,
        }
    }

    /// RMS of `F_measured − F(v)` over the held-out (`true`) or training
    /// points.
    pub fn rms(&self, m: &Model, held_out: bool) -> f64 {
        let (s, n) = self.squares(m, &self.held_out, held_out);
        (s / n.max(1) as f64).sqrt()
    }

    /// Sum of the squared residuals of `m` over the points whose `mask`
    /// flag is `on`, and their number.
    fn squares(&self, m: &Model, mask: &[bool], on: bool) -> (f64, usize) {
        self.points
            .iter()
            .zip(mask)
            .filter(|(_, h)| **h == on)
            .fold((0.0, 0), |(s, n), (pt, _)| {
                let r = pt.tau - steady_force(m, pt.v);
                (s + r * r, n + 1)
            })
    }

    /// Noise of one reading [N] (N·m): the smallest of three spreads —
    /// `curvature_noise` and `mirrored_noise`, which the curve can only
    /// inflate (its curvature, an asymmetry), and `full_curve_noise`, the
    /// residual of the fullest curve with its degrees of freedom counted. On the 130 steady-state
    /// records of the development seeds the first alone is 1.8× the
    /// generator's noise at the median (up to 16×). The smaller of the first
    /// two (version 9.0 and before) read 1.68× the generator's noise at the
    /// 90th percentile of the 119 steady-state records of 4100000–,
    /// 4300000–, 4500000–, 4900000– and 5100000–, and more than 1.5× on
    /// 17 of them (a steep fall beside an asymmetry inflates both); with
    /// the third, 1.07× and on 1.
    pub fn noise(&self) -> f64 {
        self.noise_from(&base(self))
    }

    /// [`SteadyRecord::noise`] with the record's base curve ([`base`])
    /// given, as [`diagnose_steady`] has it already.
    fn noise_from(&self, base: &Model) -> f64 {
        let curvature = self.curvature_noise();
        let full = self.full_curve_noise(base).unwrap_or(f64::INFINITY);
        let pairs = self.mirrored_noise().unwrap_or(f64::INFINITY);
        curvature.min(pairs).min(full)
    }

    /// Second differences of the force over neighbouring speeds of one
    /// direction, `median|F_{i−1} − 2F_i + F_{i+1}|/(0.6745·√6)` [N]; the
    /// curve's own curvature adds to them where the Stribeck fall is steep
    /// against the speed spacing. 0 with fewer than three speeds a
    /// direction.
    fn curvature_noise(&self) -> f64 {
        let mut d = Vec::new();
        for dir in [1.0, -1.0] {
            let mut pts: Vec<Point> = self
                .points
                .iter()
                .copied()
                .filter(|p| p.v * dir > 0.0)
                .collect();
            pts.sort_by(|a, b| a.v.abs().total_cmp(&b.v.abs()));
            d.extend(
                pts.windows(3)
                    .map(|w| (w[0].tau - 2.0 * w[1].tau + w[2].tau).abs()),
            );
        }
        if d.is_empty() {
            0.0
        } else {
            quantile(&mut d, 0.5) / (0.6745 * 6f64.sqrt())
        }
    }

    /// Mirrored pairs, the same |v| in both directions:
    /// `s = F(v) + F(−v)` is `2·F0` plus an asymmetry term plus the two
    /// readings' noise, so `median|s − median s|/(0.6745·√2)` [N]; an
    /// asymmetry adds to it. `None` with fewer than [`MIN_MIRRORED_PAIRS`].
    fn mirrored_noise(&self) -> Option<f64> {
        let mut sums: Vec<f64> = self
            .points
            .iter()
            .filter(|p| p.v > 0.0)
            .filter_map(|p| {
                let mirror = self.points.iter().find(|q| q.v == -p.v)?;
                Some(p.tau + mirror.tau)
            })
            .collect();
        if sums.len() < MIN_MIRRORED_PAIRS {
            return None;
        }
        let centre = quantile(&mut sums, 0.5);
        let mut dev: Vec<f64> = sums.iter().map(|s| (s - centre).abs()).collect();
        Some(quantile(&mut dev, 0.5) / (0.6745 * 2f64.sqrt()))
    }

    /// Noise of one reading [N] from the curve with every effect a
    /// steady state can show (the base curve `base` with all of
    /// [`STEADY_CANDIDATES`], each added from its starts whatever its
    /// gain): `√(Σr²/(n − k))` over the `n` training points, `k` its free
    /// parameters; `None` with fewer than 3 degrees of freedom.
    fn full_curve_noise(&self, base: &Model) -> Option<f64> {
        let mut m = base.clone();
        for effect in STEADY_CANDIDATES {
            let best = with_effect(&m, effect, self)
                .iter()
                .map(|s| fit_steady(self, s))
                .min_by(|a, b| self.rms(a, false).total_cmp(&self.rms(b, false)));
            if let Some(b) = best.filter(|b| self.rms(b, false) <= self.rms(&m, false)) {
                m = b;
            }
        }
        let n = self.count(false) as f64;
        let dof = n - params_of(&m).len() as f64;
        let r = self.rms(&m, false);
        (dof >= 3.0 && r.is_finite()).then(|| r * (n / dof).sqrt())
    }

    /// Cross-validated RMS [N] (N·m) of the structure of `m`: each point
    /// predicted by that structure refitted from `m` without the point's
    /// fold ([`CV_FOLDS`]), over all points. It judges every step of the
    /// selection: a record of 30–40 readings holds only 9–12 of the
    /// report's held-out points, and a Stribeck dip that lives on two or
    /// three of them is then judged on one or none.
    pub fn cv_rms(&self, m: &Model) -> f64 {
        let (mut s, mut n) = (0.0, 0usize);
        for f in 0..CV_FOLDS {
            let out: Vec<bool> = self.fold.iter().map(|k| *k == f).collect();
            let (sf, nf) = self.squares(&fit_without(self, m, &out), &out, true);
            s += sf;
            n += nf;
        }
        (s / n.max(1) as f64).sqrt()
    }

    fn count(&self, held_out: bool) -> usize {
        self.held_out.iter().filter(|h| **h == held_out).count()
    }
}

struct SteadyProblem<'a> {
    rec: &'a SteadyRecord,
    /// The points left out of the fit.
    out: &'a [bool],
    m0: &'a Model,
    params: &'a [Param],
}

impl Residuals for SteadyProblem<'_> {
    fn residuals(&self, th: &[f64]) -> Vec<f64> {
        let m = fit::decode(self.m0, self.params, th, fit::Scales::UNIT);
        self.rec
            .points
            .iter()
            .zip(self.out)
            .filter(|(_, h)| !**h)
            .map(|(pt, _)| pt.tau - steady_force(&m, pt.v))
            .collect()
    }
}

/// Least-squares fit of the structure of `m0` on the training points.
pub fn fit_steady(rec: &SteadyRecord, m0: &Model) -> Model {
    fit_without(rec, m0, &rec.held_out)
}

/// Least-squares fit of the structure of `m0` on the points whose `out`
/// flag is false.
fn fit_without(rec: &SteadyRecord, m0: &Model, out: &[bool]) -> Model {
    let params = params_of(m0);
    let problem = SteadyProblem {
        rec,
        out,
        m0,
        params: &params,
    };
    let (th, _, _) = fit::levenberg_marquardt(
        &problem,
        fit::encode(m0, &params, fit::Scales::UNIT),
        &FitOptions::default(),
        &mut |_| {},
    );
    tidy(rec, fit::decode(m0, &params, &th, fit::Scales::UNIT))
}

/// Without a Stribeck dip (`Fs = Fc` up to 0.1 %) `V` and `δ` have no
/// effect; they are written as neutral, physical values (the median speed,
/// δ = 1), never as what the fit left.
fn tidy(rec: &SteadyRecord, m: Model) -> Model {
    if m.fs - m.fc <= 1e-3 * m.fc {
        without(rec, &m, Effect::Stribeck)
    } else {
        m
    }
}

/// `m` without `effect`; without `stribeck`, V is the median speed of the
/// record [m/s] (1 where that is 0).
fn without(rec: &SteadyRecord, m: &Model, effect: Effect) -> Model {
    diagnose::without_effect(m, effect, || median_speed(rec))
}

/// The median speed of the record [m/s] (1 where that is 0 or there are no
/// points).
fn median_speed(rec: &SteadyRecord) -> f64 {
    let mut speeds: Vec<f64> = rec.points.iter().map(|p| p.v.abs()).collect();
    speeds.sort_by(f64::total_cmp);
    speeds
        .get(speeds.len() / 2)
        .copied()
        .filter(|v| *v > 0.0)
        .unwrap_or(1.0)
}

/// The starts of a Stribeck dip, `(V [m/s], δ)`: `V` at 0.03, 0.3 and 3
/// times the record's median speed, δ at 0.7 and 1.5.
fn dip_starts(rec: &SteadyRecord) -> Vec<(f64, f64)> {
    let v_mid = median_speed(rec);
    [0.03, 0.3, 3.0]
        .into_iter()
        .flat_map(|f| [0.7, 1.5].map(|delta| (f * v_mid, delta)))
        .collect()
}

/// The base curve (Fc, Fs, V, δ; no effects), from a grid over `V` and
/// `δ` ([`dip_starts`]), each node fitted, the best kept.
fn base(rec: &SteadyRecord) -> Model {
    let mut levels: Vec<f64> = rec.points.iter().map(|p| p.tau.abs()).collect();
    levels.sort_by(f64::total_cmp);
    let fc = levels.first().copied().unwrap_or(1.0).max(1e-6);
    let mut best: Option<(f64, Model)> = None;
    for (v_stribeck, delta) in dip_starts(rec) {
        let m0 = Model {
            mass: 1.0,
            fc,
            fs: 1.5 * fc,
            v_stribeck,
            delta,
            sigma: 0.0,
            z_max: 0.0,
            epsilon: 0.0,
            effects: Effects::default(),
        };
        let m = fit_steady(rec, &m0);
        let c = rec.rms(&m, false);
        if c.is_finite() && best.as_ref().is_none_or(|(b, _)| c < *b) {
            best = Some((c, m));
        }
    }
    best.map_or_else(
        || Model {
            mass: 1.0,
            fc,
            fs: fc,
            v_stribeck: median_speed(rec),
            delta: 1.0,
            sigma: 0.0,
            z_max: 0.0,
            epsilon: 0.0,
            effects: Effects::default(),
        },
        |(_, m)| m,
    )
}

/// One accepted effect of a steady-state diagnosis.
#[derive(Clone, Debug)]
pub struct SteadyStep {
    /// The effect.
    pub effect: Effect,
    /// Held-out RMS before [N] (N·m).
    pub rms_before: f64,
    /// Held-out RMS after.
    pub rms_after: f64,
    /// BIC change (of the cross-validated RMS, over all points).
    pub score: f64,
    /// The model after the step.
    pub model: Model,
    /// Every candidate of the round: (effect, cross-validated RMS, BIC
    /// change).
    pub candidates: Vec<(Effect, f64, f64)>,
}

/// The result of [`diagnose_steady`].
#[derive(Clone, Debug)]
pub struct SteadyReport {
    /// Points.
    pub n: usize,
    /// The base curve and its held-out RMS.
    pub start: Model,
    /// Held-out RMS of the base curve [N] (N·m).
    pub rms_before: f64,
    /// Held-out RMS of the final model.
    pub rms_after: f64,
    /// Accepted steps.
    pub steps: Vec<SteadyStep>,
    /// The last round's candidates (none accepted).
    pub rejected: Vec<(Effect, f64, f64)>,
    /// Effects the backward pass dropped again.
    pub pruned: Vec<Effect>,
    /// Base parts dropped, with the reason.
    pub dropped: Vec<(Effect, String)>,
    /// The final model.
    pub model: Model,
    /// Noise of one reading [N] (N·m) ([`SteadyRecord::noise`]).
    pub noise: f64,
    /// The record's units.
    pub units: Units,
}

impl SteadyReport {
    /// Model error [N] (N·m) of a held-out RMS `rms`: the part of it that
    /// the readings' noise does not explain, `√(max(rms² − noise², 0))`,
    /// the steady-state counterpart of the gap of time records (before,
    /// after and every step are read against the same noise).
    pub fn gap(&self, rms: f64) -> f64 {
        (rms * rms - self.noise * self.noise).max(0.0).sqrt()
    }

    /// The named effect and its look-alike ([`diagnose::look_alike`]) where
    /// the final curve has no Stribeck dip: `offset` adds `F0`, `asymmetry`
    /// `a·Fc`, the same curve at every speed, so the record cannot tell
    /// them apart and which one is named is decided in the solver's last
    /// digits (on 10 of the 11 such records of the fresh steady-state draw
    /// 8700000– the two candidates' cross-validated rms agreed within
    /// 1.3e-8 of it). `None` where the dip (`a·(Fs − Fc)`) or both names
    /// separate them.
    pub fn same_curve(&self) -> Option<(Effect, Effect)> {
        if fit::has_effect(&self.model, Effect::Stribeck) {
            return None;
        }
        let named = |e: Effect| self.steps.iter().any(|s| s.effect == e);
        self.steps.iter().find_map(|s| {
            diagnose::look_alike(s.effect)
                .filter(|other| !named(*other))
                .map(|other| (s.effect, other))
        })
    }
}

/// Starting models for adding `effect` to `m` (none for an effect that a
/// steady-state curve does not show, see [`STEADY_CANDIDATES`]).
fn with_effect(m: &Model, effect: Effect, rec: &SteadyRecord) -> Vec<Model> {
    let v_max = rec.points.iter().fold(1e-12f64, |a, p| a.max(p.v.abs()));
    let mut out = Vec::new();
    let mut c = m.clone();
    match effect {
        Effect::Viscous => {
            c.sigma = 0.1 * m.fc / v_max;
            out.push(c);
        }
        Effect::NonlinearViscous => {
            for n in [0.3, 0.6, 1.5] {
                let mut c = m.clone();
                c.effects.nonlinear_viscous = Some(NonlinearViscous {
                    sigma_n: 0.1 * m.fc / v_max.powf(n),
                    n,
                });
                out.push(c);
            }
        }
        Effect::Offset => {
            // From zero and from the mean residual (the least-squares
            // offset with the rest held).
            let n = rec.points.len().max(1) as f64;
            let mean = rec
                .points
                .iter()
                .map(|p| p.tau - steady_force(m, p.v))
                .sum::<f64>()
                / n;
            for f0 in [0.0, mean] {
                let mut c = m.clone();
                c.effects.offset = Some(Offset { f0 });
                out.push(c);
            }
        }
        Effect::Asymmetry => {
            for a in [0.1, -0.1] {
                let mut c = m.clone();
                c.effects.asymmetry = Some(Asymmetry { a });
                out.push(c);
            }
        }
        Effect::PositionRipple
        | Effect::DwellStiction
        | Effect::FrictionalLag
        | Effect::Drift
        | Effect::Stribeck
        | Effect::Presliding => {}
    }
    // A base dip bent to a bound of δ while the effect was missing is
    // also restarted from δ = 2 (an offset fitted from δ = 4 stopped at
    // 3.5× the asymmetry's rms on a record with equal dips).
    if degenerate(m, Effect::Stribeck).is_some() {
        let again: Vec<Model> = out
            .iter()
            .map(|c| Model {
                delta: 2.0,
                ..c.clone()
            })
            .collect();
        out.extend(again);
    }
    // A base curve without a dip may have lost it to the missing effect
    // (a viscous term 2× Fc at the fastest point bends the whole curve,
    // and the dip was fitted away): each start is also tried with the dip
    // back, from the base grid's starts.
    if !fit::has_effect(m, Effect::Stribeck) {
        let again: Vec<Model> = out
            .iter()
            .flat_map(|c| {
                dip_starts(rec).into_iter().map(move |(v_s, delta)| Model {
                    fs: 1.5 * c.fc,
                    v_stribeck: v_s,
                    delta,
                    ..c.clone()
                })
            })
            .collect();
        out.extend(again);
    }
    out
}

/// Why `effect` in `m` is degenerate on this record, or `None`.
fn degenerate(m: &Model, effect: Effect) -> Option<String> {
    let near = |x: f64, b: f64| (x / b).ln().abs() < 0.02;
    match effect {
        Effect::NonlinearViscous => diagnose::nonlinear_viscous_degenerate(m),
        Effect::Stribeck => (fit::has_effect(m, effect)
            && (near(m.delta, fit::DELTA_RANGE.0) || near(m.delta, fit::DELTA_RANGE.1)))
        .then(|| format!("delta = {:.4} at a bound of its range", m.delta)),
        Effect::Viscous
        | Effect::Offset
        | Effect::Asymmetry
        | Effect::PositionRipple
        | Effect::DwellStiction
        | Effect::FrictionalLag
        | Effect::Drift
        | Effect::Presliding => None,
    }
}

/// Whether a Stribeck dip that came back with an effect ([`with_effect`]
/// on a curve without one) is one: not degenerate, and a stiction level at
/// most [`MAX_RESTORED_DIP`] times the Coulomb level. Otherwise the dip is
/// only a second curve bending the low-speed end (on the Indy7 joints it
/// came back with `Fs ≈ 11·Fc` and `V` of 1–110 deg/s beside
/// `nonlinear_viscous`).
fn restored_dip_is_a_dip(m: &Model) -> bool {
    !fit::has_effect(m, Effect::Stribeck)
        || (degenerate(m, Effect::Stribeck).is_none() && m.fs <= MAX_RESTORED_DIP * m.fc)
}

/// The model without its Stribeck dip (`Fs = Fc`), refitted.
fn without_stribeck(rec: &SteadyRecord, m: &Model) -> Model {
    let mut c = m.clone();
    c.fs = c.fc;
    fit_steady(rec, &tidy(rec, c))
}

/// One forward pass of the name → add → shrink loop from `model`, over the
/// `allowed` effects: the accepted steps, the last round's candidates and
/// the final model.
/// `noise` is the record's [`SteadyRecord::noise`].
fn select(rec: &SteadyRecord, mut model: Model, allowed: &[Effect], noise: f64) -> Selection {
    let bic = |rms: f64, k: usize| cv_bic(rec, rms, k);
    let mut rms = rec.cv_rms(&model);
    let mut steps = Vec::new();
    let mut rejected = Vec::new();
    for _ in 0..diagnose::MAX_ROUNDS {
        let bic_cur = bic(rms, params_of(&model).len());
        let mut cands: Vec<(Effect, f64, f64, Model)> = Vec::new();
        for &effect in allowed {
            if fit::has_effect(&model, effect) {
                continue;
            }
            let best = with_effect(&model, effect, rec)
                .iter()
                .map(|s| fit_steady(rec, s))
                .filter(|m| degenerate(m, effect).is_none())
                .filter(|m| fit::has_effect(&model, Effect::Stribeck) || restored_dip_is_a_dip(m))
                .min_by(|a, b| train_bic(rec, a).total_cmp(&train_bic(rec, b)));
            if let Some(m) = best {
                let r = rec.cv_rms(&m);
                let score = bic(r, params_of(&m).len()) - bic_cur;
                cands.push((effect, r, score, m));
            }
        }
        cands.sort_by(|a, b| a.2.total_cmp(&b.2));
        let summary: Vec<(Effect, f64, f64)> = cands.iter().map(|c| (c.0, c.1, c.2)).collect();
        match cands.into_iter().next() {
            // Nothing is missing where the curve already fits to the noise
            // of the readings (1.5 σ: a 5 % gain there is chance).
            Some((effect, r, score, m))
                if score < 0.0
                    && r <= (1.0 - required_gain(effect)) * rms
                    && rms > NOISE_FACTOR * noise =>
            {
                steps.push(SteadyStep {
                    effect,
                    rms_before: rec.rms(&model, true),
                    rms_after: rec.rms(&m, true),
                    score,
                    model: m.clone(),
                    candidates: summary,
                });
                model = m;
                rms = r;
            }
            _ => {
                rejected = summary;
                break;
            }
        }
    }
    // Backward pass (as on time records): an effect whose removal, refitted
    // from the final model, keeps the cross-validated rms within its required
    // gain is dropped again. A refit after the first effect can stop in a
    // local minimum that a second name then absorbs (a = −0.29 named, then
    // `offset` with F0 = −0.004·Fc taking 81 % of what was left).
    let mut pruned = Vec::new();
    let mut k = 0;
    while k < steps.len() {
        let effect = steps[k].effect;
        let refit = fit_steady(rec, &without(rec, &model, effect));
        let without = rec.cv_rms(&refit);
        if rms > (1.0 - required_gain(effect)) * without || without <= NOISE_FACTOR * noise {
            steps.remove(k);
            pruned.push(effect);
            model = refit;
            rms = without;
        } else {
            k += 1;
        }
    }
    Selection {
        steps,
        rejected,
        pruned,
        model,
    }
}

/// `BIC = n·ln(rms²) + k·ln(n)` over all `n` points of `rec`, for a
/// cross-validated rms [N] ([`SteadyRecord::cv_rms`]) and `k` parameters.
fn cv_bic(rec: &SteadyRecord, rms: f64, k: usize) -> f64 {
    fit::bic(rec.points.len(), rms, k)
}

/// `BIC = n·ln(rms²) + k·ln(n)` of `m` over the training points of `rec`:
/// which of an effect's starts ([`with_effect`]) becomes its candidate. The
/// lowest training rms took the most parameters: on a development record
/// without a dip (`nonlinear_viscous`, n = 1.42), `viscous` with a
/// restored "dip" at V = 0.27 m/s, the fastest speeds, was named.
fn train_bic(rec: &SteadyRecord, m: &Model) -> f64 {
    fit::bic(rec.count(false), rec.rms(m, false), params_of(m).len())
}

/// What one order of [`select`] ends with.
struct Selection {
    steps: Vec<SteadyStep>,
    rejected: Vec<(Effect, f64, f64)>,
    pruned: Vec<Effect>,
    model: Model,
}

/// The name → add → shrink loop on a steady-state record, over the
/// `candidates` of [`STEADY_CANDIDATES`] (all of them when empty).
///
/// When the base curve's Stribeck dip is degenerate (δ at a bound, say),
/// two orders are tried: dropping the dip first (a curve without one, as
/// on the Indy7 joints), and adding the effects first and dropping the dip
/// only if it is still degenerate then. A missing `asymmetry` makes the
/// symmetric dip degenerate by itself, and once the dip is gone
/// `asymmetry` is `offset` exactly (both a constant shift): on a
/// development record with a = −0.29 and Fs = 1.6·Fc the first order named
/// `offset` (gap 5.25 → 2.38 N). The order whose final model has the lower
/// BIC (over all points, of its cross-validated rms) is reported.
pub fn diagnose_steady(rec: &SteadyRecord, candidates: &[Effect]) -> SteadyReport {
    let allowed: Vec<Effect> = STEADY_CANDIDATES
        .into_iter()
        .filter(|e| candidates.is_empty() || candidates.contains(e))
        .collect();
    let full = base(rec);
    let noise = rec.noise_from(&full);
    let bic = |m: &Model| cv_bic(rec, rec.cv_rms(m), params_of(m).len());
    let (start, sel, dropped) = match degenerate(&full, Effect::Stribeck) {
        None => {
            let sel = select(rec, full.clone(), &allowed, noise);
            (full, sel, Vec::new())
        }
        Some(why) => {
            let first = without_stribeck(rec, &full);
            let a = select(rec, first.clone(), &allowed, noise);
            let mut b = select(rec, full.clone(), &allowed, noise);
            let mut dropped_b = Vec::new();
            if let Some(why_b) = degenerate(&b.model, Effect::Stribeck) {
                b.model = without_stribeck(rec, &b.model);
                dropped_b.push((Effect::Stribeck, why_b));
            }
            if !b.steps.is_empty() && bic(&b.model) < bic(&a.model) {
                (full, b, dropped_b)
            } else {
                (first, a, vec![(Effect::Stribeck, why)])
            }
        }
    };
    SteadyReport {
        n: rec.points.len(),
        rms_before: rec.rms(&start, true),
        rms_after: rec.rms(&sel.model, true),
        start,
        steps: sel.steps,
        rejected: sel.rejected,
        pruned: sel.pruned,
        dropped,
        model: sel.model,
        noise,
        units: rec.units,
    }
}

/// Reads a steady-state record: the Indy7 layout (`desired vel, real vel,
/// tau` in deg/s and N·m) or a CSV with columns `v` and `u` (SI units, any
/// order, `#` comments), with readings at
/// [`MIN_SPEEDS`](crate::static_curve::MIN_SPEEDS) distinct non-zero speeds
/// at least.
pub fn read(path: &Path) -> Result<SteadyRecord, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::Runtime(format!("{}: cannot read: {e}", path.display())))?;
    let (rec, units) = if text
        .lines()
        .any(|l| l.trim().to_ascii_lowercase().starts_with("desired vel"))
    {
        (crate::static_curve::read(path)?, Units::Rotary)
    } else {
        (crate::data::parse_steady_csv(&text, path)?, Units::Si)
    };
    let speeds = crate::static_curve::distinct_speeds(rec.iter().map(|p| p.v));
    if speeds < crate::static_curve::MIN_SPEEDS {
        return Err(Error::Runtime(format!(
            "{}: readings at {speeds} distinct non-zero speeds: a steady-state curve needs {} at least",
            path.display(),
            crate::static_curve::MIN_SPEEDS
        )));
    }
    Ok(SteadyRecord::with_units(rec, units))
}

/// True when `path` holds a steady-state record rather than a time series:
/// the Indy7 layout, or a CSV header with `v` and `u` but neither `t` nor
/// `x`.
pub fn is_steady(path: &Path) -> bool {
    let Ok(text) = std::fs::read_to_string(path) else {
        return false;
    };
    let Some((_, first)) = crate::data::rows(&text).next() else {
        return false;
    };
    if text
        .lines()
        .any(|l| l.trim().to_ascii_lowercase().starts_with("desired vel"))
    {
        return true;
    }
    // A header with `x` is a time record, its `t` missing or misnamed
    // (`time`): read as one, it gets the error that names the column.
    let cols = crate::data::trimmed(&first);
    cols.contains(&"v") && cols.contains(&"u") && !cols.contains(&"t") && !cols.contains(&"x")
}

/// The JSON report (the keys of [`crate::diagnose::report_json`] that
/// apply).
pub fn report_json(rep: &SteadyReport) -> String {
    use serde_json::json;
    let steps: Vec<_> = rep
        .steps
        .iter()
        .map(|s| {
            let scores = (rep.gap(s.rms_before), rep.gap(s.rms_after), s.score);
            diagnose::step_json(s.effect, &s.model, scores, s.candidates.iter().copied())
        })
        .collect();
    let v = json!({
        "version": diagnose::WORKFLOW_VERSION,
        "kind": "steady_state",
        "units": rep.units.json(),
        "effects_added": rep.steps.iter().map(|s| s.effect.name()).collect::<Vec<_>>(),
        "metric": "model error: sqrt(rms^2 - floor^2), rms the held-out RMS of F_measured - F(v) over the points with index 2, 5, 8 mod 10 (steady-state record: no dynamics; the steps are decided on the 3-fold cross-validated rms over all points, folds by speed rank, which is the rms of each step's and each rejected entry's candidates; floor = the readings' noise: the smallest of three spreads, second differences over neighbouring speeds, sums of mirrored speeds, and the residual of the curve with every steady-state effect over its degrees of freedom); mass and z_max are not identifiable from it",
        "rms_before": rep.gap(rep.rms_before),
        "rms_after": rep.gap(rep.rms_after),
        "rms_raw_before": rep.rms_before,
        "rms_raw_after": rep.rms_after,
        "floor": rep.noise,
        "steps": steps,
        "rejected": diagnose::candidates_json(rep.rejected.iter().copied()),
        "dropped": rep.dropped.iter().map(|(n, why)| json!({"part": n.name(), "reason": why})).collect::<Vec<_>>(),
        "pruned": rep.pruned.iter().map(|e| e.name()).collect::<Vec<_>>(),
        "same_curve": rep.same_curve().map(|(named, other)| json!({"named": named.name(), "same_curve_as": other.name(), "why": "no Stribeck dip: F0 and a*Fc shift the curve alike at every speed"})),
        "start_model": diagnose::model_json(&rep.start),
        "model": diagnose::model_json(&rep.model),
        "samples": rep.n,
    });
    let mut s = serde_json::to_string_pretty(&v).unwrap_or_else(|_| "{}".into());
    s.push('\n');
    s
}

/// The terminal text.
pub fn report_text(rep: &SteadyReport, source: &str) -> String {
    use crate::format::short;
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{source}: steady-state record, {} points (one force per speed; only F(v) effects are visible; \
         {}); mass and z_max are not identified by it (a model written from it holds m = 1 kg, \
         z_max = 0)",
        rep.n,
        rep.units.text()
    );
    for (part, why) in &rep.dropped {
        let _ = writeln!(s, "not identifiable here, dropped: `{part}` ({why})");
    }
    let _ = writeln!(
        s,
        "readings' noise {}; figures below are model error above it",
        short(rep.noise, 4)
    );
    let _ = writeln!(
        s,
        "start: Stribeck curve, held-out model error {} (rms {})",
        short(rep.gap(rep.rms_before), 4),
        short(rep.rms_before, 4)
    );
    for (k, st) in rep.steps.iter().enumerate() {
        let (before, after) = (rep.gap(st.rms_before), rep.gap(st.rms_after));
        let _ = writeln!(
            s,
            "step {}: missing effect `{}`; adding it shrinks the gap from {} to {} ({:.0} %), fitted {}",
            k + 1,
            st.effect,
            short(before, 4),
            short(after, 4),
            100.0 * (before - after) / before,
            diagnose::effect_params(&st.model, st.effect)
        );
    }
    for e in &rep.pruned {
        let _ = writeln!(
            s,
            "backward check: `{e}` dropped again (the model refitted without it is within its required gain)"
        );
    }
    let added: Vec<&str> = rep.steps.iter().map(|s| s.effect.name()).collect();
    let _ = writeln!(
        s,
        "effects added: [{}]; gap {} -> {} (held-out rms {} -> {})",
        added.join(", "),
        short(rep.gap(rep.rms_before), 4),
        short(rep.gap(rep.rms_after), 4),
        short(rep.rms_before, 4),
        short(rep.rms_after, 4)
    );
    if let Some((named, other)) = rep.same_curve() {
        let _ = writeln!(
            s,
            "`{named}` and `{other}` are the same curve here (no Stribeck dip: F0 and a·Fc shift it alike at every speed); the record cannot tell them apart, `{named}` is named"
        );
    }
    let _ = writeln!(s, "model: {}", diagnose::model_json(&rep.model));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Readings of `truth` at `n` speeds `v0·ratio^k` in both directions
    /// (positive first), each with Gaussian noise of `sigma` [N] from seed
    /// `seed`.
    fn readings(
        truth: &Model,
        (v0, ratio, n): (f64, f64, i32),
        sigma: f64,
        seed: u64,
    ) -> Vec<Point> {
        let mut rng = crate::synth::Rng::new(seed);
        let mut points = Vec::new();
        for k in 0..n {
            let speed = v0 * ratio.powi(k);
            for v in [speed, -speed] {
                let tau = steady_force(truth, v) + sigma * rng.normal();
                points.push(Point { v, tau });
            }
        }
        points
    }

    /// The noise estimate on a steep Stribeck fall sampled at ×2.2 speed
    /// steps (12 speeds per direction, as the generator's steady records):
    /// the second differences alone read the fall's curvature as noise;
    /// the mirrored pairs do not, and the estimate is the smaller.
    #[test]
    fn noise_is_not_the_curvature_of_a_steep_fall() {
        let mut truth = diagnose::fig5_model();
        (truth.fc, truth.fs, truth.v_stribeck, truth.delta) = (48.0, 81.4, 1.17e-3, 0.81);
        let sigma = 0.05;
        let mut points = readings(&truth, (2.49e-4, 2.18, 12), sigma, 5);
        let rec = SteadyRecord::new(points.clone());
        let noise = rec.noise();
        assert!((0.5 * sigma..2.0 * sigma).contains(&noise), "{noise}");
        // Without mirrored speeds only the second differences remain, and
        // they hold the curvature (about 3σ here).
        for p in points.iter_mut().filter(|p| p.v < 0.0) {
            p.v *= 1.1;
        }
        let curvature = SteadyRecord::new(points).noise();
        assert!(curvature > 2.0 * noise, "{curvature} vs {noise}");
    }

    /// The noise estimate where both robust spreads read the curve: a
    /// steep fall (the second differences) and an asymmetry beside an
    /// offset (the mirrored sums `2·F0 + 2a·S(v)` move with the dip), the
    /// development record 5100030's shape (Fs = 1.67·Fc, a = −0.006,
    /// F0 = −0.11·Fc; in-model readings, a check of the estimator's
    /// arithmetic). The curve with every steady-state effect leaves the
    /// noise: within 30 % of σ, where the two spreads alone read at least
    /// 1.5σ.
    #[test]
    fn noise_is_not_an_asymmetric_dip() {
        let mut truth = diagnose::fig5_model();
        (truth.fc, truth.fs, truth.v_stribeck, truth.delta) = (3.76, 6.27, 1.64e-3, 1.92);
        truth.effects.asymmetry = Some(Asymmetry { a: -0.006 });
        truth.effects.offset = Some(Offset { f0: -0.41 });
        let sigma = 0.0046;
        let points = readings(&truth, (6e-5, 1.6, 22), sigma, 7);
        let rec = SteadyRecord::new(points);
        let noise = rec.noise();
        assert!((0.7 * sigma..1.3 * sigma).contains(&noise), "{noise}");
        let full = rec.full_curve_noise(&base(&rec)).expect("enough points");
        assert_eq!(noise, full, "the smallest of the three spreads");
        let pairs = rec.mirrored_noise().expect("mirrored speeds");
        let curvature = rec.curvature_noise();
        assert!(pairs.min(curvature) > 1.5 * sigma, "{pairs} {curvature}");
    }

    /// A steady-state curve with a Stribeck dip and direction asymmetry
    /// (a = −0.29, Fs = 1.6·Fc): the symmetric base dip comes out
    /// degenerate, and with the dip dropped first `asymmetry` would be
    /// `offset` exactly. Both orders are tried, so `asymmetry` is named,
    /// alone, with `a` recovered.
    #[test]
    fn asymmetry_with_a_stribeck_dip_is_not_an_offset() {
        let mut truth = diagnose::fig5_model();
        (truth.fc, truth.fs, truth.v_stribeck, truth.delta) = (13.7, 22.2, 4e-3, 0.9);
        truth.effects.asymmetry = Some(Asymmetry { a: -0.29 });
        let points = readings(&truth, (1e-3, 1.35, 22), 0.05, 3);
        let rep = diagnose_steady(&SteadyRecord::new(points), &[]);
        let named: Vec<Effect> = rep.steps.iter().map(|s| s.effect).collect();
        assert_eq!(
            named,
            vec![Effect::Asymmetry],
            "{}",
            report_text(&rep, "test")
        );
        let a = rep.model.effects.asymmetry.map_or(0.0, |a| a.a);
        assert!((a + 0.29).abs() < 0.02, "a = {a}");
    }

    /// The folds of the cross-validation: in the generator's file order
    /// (13 speeds a direction, positives first) the two directions of a
    /// speed and neighbouring speeds fall in different folds, and the folds
    /// are equal in size.
    #[test]
    fn folds_split_the_directions_and_neighbouring_speeds() {
        let points: Vec<Point> = [1.0, -1.0]
            .into_iter()
            .flat_map(|d| {
                (0..13).map(move |k| Point {
                    v: d * 1e-4 * 2f64.powi(k),
                    tau: d,
                })
            })
            .collect();
        let folds = SteadyRecord::new(points).fold;
        for k in 0..13 {
            assert_ne!(folds[k], folds[13 + k], "speed {k}");
        }
        for k in 0..12 {
            assert_ne!(folds[k], folds[k + 1], "speeds {k}, {}", k + 1);
        }
        for f in 0..CV_FOLDS {
            let n = folds.iter().filter(|x| **x == f).count();
            assert!((8..=9).contains(&n), "fold {f}: {n} points");
        }
    }

    /// `offset` beside `asymmetry` on a dip that falls over three speeds
    /// (the development record 8600199's curve: Fs = 1.46·Fc, F0 = 0.27·Fc,
    /// a = 0.16; 13 speeds a direction at ×2 steps, positives first, noise
    /// 0.1 N; in-model readings). Judged on the held-out points the pair
    /// was refused (the point on the fall that the training fit misses
    /// outweighs the gain elsewhere); judged on all points it is named,
    /// with F0 and `a` recovered.
    #[test]
    fn an_offset_beside_an_asymmetry_is_judged_on_all_points() {
        let mut truth = diagnose::fig5_model();
        (truth.fc, truth.fs, truth.v_stribeck, truth.delta) = (22.5, 32.8, 1.39e-3, 2.09);
        truth.effects.offset = Some(Offset { f0: 5.98 });
        truth.effects.asymmetry = Some(Asymmetry { a: 0.162 });
        let mut points = readings(&truth, (4.12e-4, 2.0, 13), 0.1, 13);
        points.sort_by(|a, b| {
            b.v.signum()
                .total_cmp(&a.v.signum())
                .then(a.v.abs().total_cmp(&b.v.abs()))
        });
        let rep = diagnose_steady(&SteadyRecord::new(points), &[]);
        let text = report_text(&rep, "test");
        let mut named: Vec<Effect> = rep.steps.iter().map(|s| s.effect).collect();
        named.sort_by_key(|e| e.name());
        assert_eq!(named, vec![Effect::Asymmetry, Effect::Offset], "{text}");
        let e = &rep.model.effects;
        let (f0, a) = (
            e.offset.map_or(0.0, |o| o.f0),
            e.asymmetry.map_or(0.0, |a| a.a),
        );
        assert!(
            (f0 - 5.98).abs() < 0.3 && (a - 0.162).abs() < 0.015,
            "{text}"
        );
    }

    /// Without a Stribeck dip `asymmetry` and `offset` are one curve
    /// (in-model readings, Fs = Fc, a = 0.05): whichever is named, the
    /// report says the record cannot tell it from the other; with a dip
    /// (Fs = 1.5·Fc) it does not.
    #[test]
    fn without_a_dip_the_look_alikes_are_reported_as_one_curve() {
        let mut truth = diagnose::fig5_model();
        (truth.fc, truth.fs) = (4.0, 4.0);
        truth.effects.asymmetry = Some(Asymmetry { a: 0.05 });
        let points = readings(&truth, (1e-4, 1.6, 18), 0.01, 17);
        let rep = diagnose_steady(&SteadyRecord::new(points), &[]);
        let text = report_text(&rep, "test");
        let (named, other) = rep.same_curve().expect(&text);
        assert_eq!(Some(other), diagnose::look_alike(named), "{text}");
        assert!(text.contains("the same curve here"), "{text}");
        assert!(report_json(&rep).contains("\"same_curve_as\""), "{text}");
        let mut with_dip = truth.clone();
        with_dip.fs = 6.0;
        let points = readings(&with_dip, (1e-4, 1.6, 18), 0.01, 17);
        let rep = diagnose_steady(&SteadyRecord::new(points), &[]);
        assert_eq!(rep.same_curve(), None, "{}", report_text(&rep, "test"));
    }

    /// A viscous term that reaches 2× Fc at the fastest point (σ = 870
    /// N·s/m, Fs = 1.48·Fc, V = 0.47 mm/s, speeds 0.02–23 mm/s): the base
    /// curve without it has no room for the dip and fits it away
    /// (`Fs = Fc`); the dip comes back with `viscous`, which is named
    /// alone, with Fs and σ recovered (before, the curve without a dip
    /// named `nonlinear_viscous` at 25× the noise).
    #[test]
    fn a_dip_lost_to_a_strong_viscous_term_comes_back() {
        let mut truth = diagnose::fig5_model();
        (truth.fc, truth.fs, truth.v_stribeck, truth.delta) = (10.28, 15.24, 4.72e-4, 2.1);
        truth.sigma = 867.0;
        let points = readings(&truth, (2.2e-5, 1.35, 24), 0.06, 11);
        let rep = diagnose_steady(&SteadyRecord::new(points), &[]);
        let text = report_text(&rep, "test");
        assert!(!fit::has_effect(&rep.start, Effect::Stribeck), "{text}");
        let named: Vec<Effect> = rep.steps.iter().map(|s| s.effect).collect();
        assert_eq!(named, vec![Effect::Viscous], "{text}");
        let m = &rep.model;
        assert!((m.fs / truth.fs - 1.0).abs() < 0.02, "{text}");
        assert!((m.sigma / truth.sigma - 1.0).abs() < 0.02, "{text}");
        assert!(rep.rms_after < 2.0 * rep.noise, "{text}");
    }

    /// The gap is model error over the readings' noise, before and after
    /// alike: on Fig. 5 readings with `nonlinear_viscous` (n = 0.5, 12
    /// speeds per direction, noise 0.01 N) the held-out rms of the named
    /// model sits at the noise, and the gap it leaves is a small share of
    /// the first; the JSON's `rms_before`/`rms_after` are these gaps, with
    /// the held-out rms beside them.
    #[test]
    fn the_gap_is_model_error_above_the_noise() {
        let mut truth = diagnose::fig5_model();
        truth.effects.nonlinear_viscous = Some(NonlinearViscous {
            sigma_n: 2.0,
            n: 0.5,
        });
        let points = readings(&truth, (2e-4, 1.8, 12), 0.01, 5);
        let rep = diagnose_steady(&SteadyRecord::new(points), &[]);
        let text = report_text(&rep, "test");
        let named: Vec<Effect> = rep.steps.iter().map(|s| s.effect).collect();
        assert_eq!(named, vec![Effect::NonlinearViscous], "{text}");
        assert!(rep.noise > 0.005 && rep.noise < 0.015, "{text}");
        let (before, after) = (rep.gap(rep.rms_before), rep.gap(rep.rms_after));
        let direct = (rep.rms_before.powi(2) - rep.noise.powi(2)).sqrt();
        assert!((before - direct).abs() < 1e-12 * direct, "{text}");
        assert!(after < 0.1 * before && after <= rep.rms_after, "{text}");
        let json: serde_json::Value = serde_json::from_str(&report_json(&rep)).expect("JSON");
        assert_eq!(json["rms_before"].as_f64(), Some(before));
        assert_eq!(json["rms_after"].as_f64(), Some(after));
        assert_eq!(json["rms_raw_after"].as_f64(), Some(rep.rms_after));
    }
}
