//! The discrepancy workflow (`breakaway-lab diagnose`): where the model and
//! the measurement disagree, which effect of MODEL.md §5 is missing, and how
//! much adding it shrinks the gap.
//!
//! 1. **Residual.** The force residual along the measured motion of
//!    [`crate::fit`] (local by construction, MODEL.md §8), for the current
//!    model refitted on the training blocks.
//! 2. **Localise.** Every sample gets a regime (rest, presliding after a
//!    turning point, break-away after a rest, low speed, sliding by speed
//!    band; each direction); the report lists where the residual
//!    concentrates (regimes and time windows) and how much of it each signal
//!    explains (binned means against velocity, direction, position — the
//!    best line of a spatial periodogram —, time, time since the last turning
//!    point, rest time before motion).
//! 3. **Name.** Each catalogue effect the model lacks is added in turn,
//!    refitted (Levenberg–Marquardt from a few starting points) and scored on
//!    the held-out blocks by `BIC = n·ln(mse) + p·ln(n)`. The best candidate
//!    is accepted only if its BIC is lower **and** it lowers the held-out RMS
//!    by at least [`ACCEPT_GAIN`] above the floor (see there for why both)
//!    **and** removes [`MIN_GAP_SHARE`] of the gap.
//! 4. Repeat until no candidate is accepted; 5. report.

use crate::data::Record;
use crate::fit::{self, FitOptions, Param, Prepared};
use crate::progress::Progress;
use crate::reference::{
    Asymmetry, Drift, DwellStiction, Effect, Effects, Friction, FrictionalLag, Model,
    NonlinearViscous, Offset, PositionRipple,
};
use std::f64::consts::PI;

/// Least relative reduction of the held-out RMS for a candidate to be
/// accepted.
///
/// The held-out residual samples are not independent: the differentiator
/// window (11 samples), the control loop and the smoothing of the force
/// kernel correlate them over tens of samples, so the `ln(n)` penalty of BIC
/// per parameter is too weak by about that factor and BIC alone would accept
/// parameters that fit the correlated floor (differentiation and
/// discretisation errors at break-away). Requiring a 5 % lower held-out RMS
/// on top is a margin above what an effect-free record gives: on the
/// effect-free records of the test matrix no candidate reached 1.5 % (while
/// BIC alone accepted some), and the hidden effects give 11–95 % (see
/// lab/README.md).
pub const ACCEPT_GAIN: f64 = 0.05;

/// Least size of a named effect: the RMS of the force it adds along the
/// measured motion (moving samples), in units of the per-sample force
/// noise ([`visibility`]). The smallest effects the workflow is asked to
/// find are 3× the noise; a candidate below 2× only absorbs the rest of a
/// model error (on effect-free development records, a `frictional_lag` of
/// τ = 1.2 ms and an `asymmetry` of 6e-5 were named that way).
pub const MIN_VISIBILITY: f64 = 2.0;

/// RMS [N] of the force that `effect` adds to `m` along the measured
/// motion (moving samples), over the per-sample force noise the floor
/// assumes (`σ0/‖W‖`, [`Prepared::sigma0`]).
pub fn visibility(p: &Prepared, m: &Model, effect: Effect) -> f64 {
    let with = p.friction(m);
    let without = p.friction(&remove_effect(m, effect, p));
    let (mut s, mut n) = (0.0, 0usize);
    for i in p.valid().filter(|&i| !p.still[i]) {
        s += (with[i] - without[i]).powi(2);
        n += 1;
    }
    let noise = p.sigma0 / p.kernel_norm();
    if n == 0 || noise.is_nan() || noise <= 0.0 {
        return f64::INFINITY;
    }
    (s / n as f64).sqrt() / noise
}

/// Least relative reduction per added parameter (a candidate with `p` new
/// parameters needs `max(ACCEPT_GAIN, p·ACCEPT_GAIN_PER_PARAM)`;
/// `dwell_stiction` counts its grid-chosen `v_rest`). A periodic term with
/// free wavelength and phase finds some line in any structured residual:
/// in the test matrix, spurious `position_ripple` lines reached 12 % after
/// the real effect had been added.
pub const ACCEPT_GAIN_PER_PARAM: f64 = 0.045;

/// The relative reduction of the held-out rms from `before` to `after`
/// that lies above the measurement `floor`: `(before − max(after,
/// floor))/before`, 0 when `before` is at or below the floor. What a
/// candidate removes below the floor is noise and resolution, however
/// much BIC likes it: a record already at its floor is missing nothing.
pub fn gain_above_floor(before: f64, after: f64, floor: f64) -> f64 {
    if before > floor && before > 0.0 {
        (before - after.max(floor)) / before
    } else {
        0.0
    }
}

/// Least share of the gap (model error above the floor, [`fit::model_error`])
/// that a named effect must remove, on top of [`required_gain`].
///
/// The floor counts force noise and encoder resolution, but not all that a
/// quantised, servo-driven record leaves unresolved (the last counts
/// before a stop, chatter within a count), so a record with no missing
/// effect still shows a gap, and some candidate always absorbs a part of
/// it. On 260 development records of the independent generator (seeds
/// 9000–9039, 9200–9229, 9500–9529 and 400000–400159, the last scored as
/// a fresh sweep before this rule), the steps that named a hidden effect
/// removed less than 25 % of the gap in 12 of 177 cases, the steps that
/// named an effect that was not there in 33 of 71.
pub const MIN_GAP_SHARE: f64 = 0.25;

/// The share of the gap that goes from `before` to `after` (held-out
/// rms [N]) removes: `1 − e(after)/e(before)` with `e` the model error
/// above `floor`; 0 when there is no gap.
pub fn gap_share(before: f64, after: f64, floor: f64) -> f64 {
    let e0 = fit::model_error(before, floor);
    if e0 > 0.0 {
        1.0 - fit::model_error(after, floor) / e0
    } else {
        0.0
    }
}

/// Whether moving the held-out rms from `before` to `after` [N] is enough
/// to name `effect`: [`required_gain`] of the rms above the floor and
/// [`MIN_GAP_SHARE`] of the gap.
pub fn enough_gain(effect: Effect, before: f64, after: f64, floor: f64) -> bool {
    gain_above_floor(before, after, floor) >= required_gain(effect)
        && gap_share(before, after, floor) >= MIN_GAP_SHARE
}

/// The gain a candidate must reach.
pub fn required_gain(effect: Effect) -> f64 {
    let p = match effect {
        Effect::PositionRipple | Effect::DwellStiction | Effect::Stribeck => 3.0,
        Effect::NonlinearViscous => 2.0,
        Effect::Viscous
        | Effect::Offset
        | Effect::Asymmetry
        | Effect::FrictionalLag
        | Effect::Drift
        | Effect::Presliding => 1.0,
    };
    ACCEPT_GAIN.max(p * ACCEPT_GAIN_PER_PARAM)
}

/// Most effects added.
pub const MAX_ROUNDS: usize = 4;

/// Options of the workflow.
#[derive(Clone, Debug)]
pub struct Options {
    /// Savitzky–Golay half-widths.
    pub window: fit::Window,
    /// Candidate effects considered; all when empty.
    pub candidates: Vec<Effect>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            window: fit::Window::both(fit::DEFAULT_HALF_WIDTH),
            candidates: Vec::new(),
        }
    }
}

/// A candidate tried in one round.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The effect.
    pub effect: Effect,
    /// Weighted held-out RMS after adding and refitting [N] (noise and
    /// resolution included; the same weights for every candidate).
    pub rms: f64,
    /// BIC change on the held-out blocks (negative is better).
    pub score: f64,
    /// The fitted model.
    pub model: Model,
}

/// One accepted effect.
#[derive(Clone, Debug)]
pub struct Step {
    /// The effect.
    pub effect: Effect,
    /// Model error before [N] (held-out, above the floor).
    pub rms_before: f64,
    /// Model error after [N].
    pub rms_after: f64,
    /// BIC change (negative).
    pub score: f64,
    /// The model after the step.
    pub model: Model,
    /// The signal that localises this effect, and the fraction of the
    /// residual (before the step) it explains.
    pub signal: (String, f64),
    /// Every candidate of the round, best first.
    pub candidates: Vec<Candidate>,
    /// The round's candidates whose fit ran the Stribeck dip to its bound
    /// (not a finding; still runner-ups for the swap pass, from the base
    /// without this step's effect), best first.
    pub held_back: Vec<Candidate>,
    /// Residual before the step (all samples).
    pub residual_before: Vec<f64>,
}

/// The catalogue effect that shifts the force like `effect` in gross
/// sliding, if any: `offset` adds `F0` in both directions, `asymmetry` adds
/// `a·S(v)`, the same shift wherever `S = Fc`. They differ only by
/// `a·(Fs − Fc)` in the Stribeck dip and at break-away.
pub fn look_alike(effect: Effect) -> Option<Effect> {
    match effect {
        Effect::Offset => Some(Effect::Asymmetry),
        Effect::Asymmetry => Some(Effect::Offset),
        Effect::Viscous
        | Effect::NonlinearViscous
        | Effect::PositionRipple
        | Effect::DwellStiction
        | Effect::FrictionalLag
        | Effect::Drift
        | Effect::Stribeck
        | Effect::Presliding => None,
    }
}

/// Share of a step's gap within which the named effect and its
/// [`look_alike`] count as fitting equally well.
pub const TIE_SHARE: f64 = 0.005;

/// The look-alike of a step's effect when it fitted as well in that step's
/// round (model errors above `floor` within [`TIE_SHARE`] of the gap
/// before the step): the record does not tell the two apart, and the report
/// says so. On the development records the choice between such a tied pair
/// went either way (23 ties: 10 with `offset` hidden, 13 with `asymmetry`).
pub fn tied_look_alike(step: &Step, floor: f64) -> Option<(Effect, f64, f64)> {
    let other = look_alike(step.effect)?;
    let err = |e: Effect| {
        step.candidates
            .iter()
            .find(|c| c.effect == e)
            .map(|c| fit::model_error(c.rms, floor))
    };
    let (mine, theirs) = (err(step.effect)?, err(other)?);
    ((mine - theirs).abs() <= TIE_SHARE * step.rms_before).then_some((other, mine, theirs))
}

/// A stretch where the residual concentrates.
#[derive(Clone, Debug)]
pub struct Region {
    /// Regime label.
    pub regime: String,
    /// Start [s].
    pub t_start: f64,
    /// End [s].
    pub t_end: f64,
    /// RMS of the residual there [N].
    pub rms: f64,
}

/// Per-regime statistics.
#[derive(Clone, Debug)]
pub struct RegimeStat {
    /// Regime label.
    pub regime: String,
    /// Samples.
    pub n: usize,
    /// RMS of the residual [N].
    pub rms: f64,
}

/// The result of [`diagnose`].
#[derive(Clone, Debug)]
pub struct Report {
    /// Samples, interval, resolution.
    pub n: usize,
    /// Half-width of the force kernel (samples).
    pub half_width: usize,
    /// Half-width of the velocity estimate (samples).
    pub velocity_half_width: usize,
    /// Median sampling interval [s].
    pub dt: f64,
    /// Position resolution [m].
    pub resolution: f64,
    /// Start model as given (`None` without `--model`) and its held-out RMS.
    pub given: Option<f64>,
    /// Model before the first step (refitted start).
    pub start: Model,
    /// Model error of `start` on the held-out blocks [N]:
    /// [`fit::model_error`] of its weighted RMS and [`Report::floor`].
    pub rms_before: f64,
    /// Model error of the final model on the held-out blocks [N].
    pub rms_after: f64,
    /// Weighted held-out RMS of `start` [N] (noise and resolution included).
    pub raw_before: f64,
    /// Weighted held-out RMS of the final model [N].
    pub raw_after: f64,
    /// The part of a weighted held-out RMS that noise and resolution explain
    /// [N] ([`Prepared::floor`]): what a correct model would show.
    pub floor: f64,
    /// Force-noise level [N] of the residual ([`Prepared::sigma0`]).
    pub sigma0: f64,
    /// Still samples (position within one count over the window; the friction is
    /// the measured force there, not a prediction) and all valid samples.
    pub still: (usize, usize),
    /// Parts of the start structure dropped as not identifiable, with the
    /// reason (e.g. `stribeck`: V at its bound).
    pub dropped: Vec<(Effect, String)>,
    /// Accepted steps.
    pub steps: Vec<Step>,
    /// The last round's candidates (none accepted).
    pub last_round: Vec<Candidate>,
    /// Effects dropped by the backward pass: (effect, held-out model error
    /// without it, with it) [N].
    pub pruned: Vec<(Effect, f64, f64)>,
    /// Effects replaced by a runner-up in the swap pass: (taken, replaced
    /// by, model error before, after) [N].
    pub swapped: Vec<(Effect, Effect, f64, f64)>,
    /// Where the residual concentrates before the first step.
    pub regions: Vec<Region>,
    /// RMS per regime before the first step.
    pub regimes: Vec<RegimeStat>,
    /// Fraction of the residual each signal explains (before the first step).
    pub signals: Vec<(String, f64)>,
    /// The final model.
    pub model: Model,
    /// Residual of the final model.
    pub residual_after: Vec<f64>,
    /// Residual of the start model.
    pub residual_before: Vec<f64>,
    /// Times [s].
    pub t: Vec<f64>,
    /// Signals per sample, by name (for plots).
    pub signal_series: Vec<(String, Vec<f64>)>,
}

/// What the residual is, for reports.
pub const METRIC: &str = "model error [N]: sqrt(rms^2 - floor^2), rms the held-out weighted RMS of the force residual along the measured motion, r = W*(u - F(t, x, v_hat)) - m*a_hat (Savitzky-Golay v_hat, a_hat; W the matching force kernel), floor the part that force noise and encoder resolution explain; still samples (position within one count over the window) are the measured force, re-anchor the presliding memory and carry no weight; weights (speed/direction class x noise/resolution variance) fixed from the start model; time blocks 2, 5, 8 of 10 held out";

fn held_rms(p: &Prepared, m: &Model) -> (f64, Vec<f64>) {
    let r = p.residual(m);
    (p.rms(&r, Some(true)), r)
}

fn bic(p: &Prepared, rms: f64, n_params: usize) -> f64 {
    let n = p.count(true).max(1) as f64;
    n * (rms * rms).max(1e-300).ln() + n_params as f64 * n.ln()
}

fn quick() -> FitOptions {
    FitOptions {
        max_iter: 12,
        rel_tol: 1e-4,
    }
}

/// How many of the best short fits [`fit_multistart`] fits fully before
/// it gives up on finding one that `sound` accepts.
const FULL_FITS: usize = 3;

/// The best of several starting models after a short fit, then fitted
/// fully; when the full fit ends where `sound` rejects it (a parameter at
/// a bound), the next-best short fit is tried, up to [`FULL_FITS`]: a start
/// that runs to a bound on the training blocks must not hide one that
/// converges inside the range.
fn fit_multistart(
    p: &Prepared,
    starts: &[Model],
    sound: &dyn Fn(&Model) -> bool,
    progress: &mut dyn FnMut(&str),
) -> Model {
    if let [only] = starts {
        progress("start 1/1");
        let params = fit::params_of(only);
        return fit::fit(p, only, &params, &FitOptions::default(), &mut |_| {}).model;
    }
    let mut short: Vec<(f64, Model)> = Vec::new();
    for (i, s) in starts.iter().enumerate() {
        progress(&format!("start {}/{}", i + 1, starts.len()));
        let params = fit::params_of(s);
        let r = fit::fit(p, s, &params, &quick(), &mut |_| {});
        short.push((r.cost, r.model));
    }
    short.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut first = None;
    for (_, m) in short.into_iter().take(FULL_FITS) {
        let params = fit::params_of(&m);
        let full = fit::fit(p, &m, &params, &FitOptions::default(), &mut |_| {}).model;
        if sound(&full) {
            return full;
        }
        first.get_or_insert(full);
    }
    first.unwrap_or_else(|| starts.first().cloned().unwrap_or_else(fig5_model))
}

/// The paper's Fig. 5 parameter set as a model (m = 1 kg, no effects): the
/// placeholder start when no start model fits, and the tests' default.
pub(crate) fn fig5_model() -> Model {
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

fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// Linear least squares `min |A·c − b|` with columns `cols` (normal
/// equations, Gauss–Jordan with partial pivoting); `None` when singular or
/// not finite. Also used by `static_curve`.
#[allow(clippy::needless_range_loop)] // dense Gauss–Jordan on a small matrix
pub fn lstsq(cols: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    let n = cols.len();
    let mut a = vec![vec![0.0; n + 1]; n];
    for i in 0..n {
        for j in 0..n {
            a[i][j] = cols[i].iter().zip(&cols[j]).map(|(x, y)| x * y).sum();
        }
        a[i][n] = cols[i].iter().zip(b).map(|(x, y)| x * y).sum();
    }
    for c in 0..n {
        let piv = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[piv][c].abs() < 1e-300 {
            return None;
        }
        a.swap(c, piv);
        for r in 0..n {
            if r != c {
                let f = a[r][c] / a[c][c];
                for k in c..=n {
                    a[r][k] -= f * a[c][k];
                }
            }
        }
    }
    let x: Vec<f64> = (0..n).map(|i| a[i][n] / a[i][i]).collect();
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The base model of MODEL.md §2–§3 (Coulomb + Stribeck + presliding,
/// σ = 0) with its parameters identified from the data: mass and Fc by
/// linear least squares on the faster half of the moving samples, then a
/// grid over V and z_max, then Levenberg–Marquardt.
pub fn initial_base(p: &Prepared, progress: &mut dyn FnMut(&str)) -> Model {
    let mut speeds: Vec<f64> = p
        .valid()
        .map(|i| p.v[i].abs())
        .filter(|s| *s > p.v_rest)
        .collect();
    let v_med = quantile(&mut speeds.clone(), 0.5);
    let v_lo = quantile(&mut speeds, 0.2);
    let fast: Vec<usize> = p
        .valid()
        .filter(|&i| !p.held_out[i] && p.v[i].abs() >= v_med)
        .collect();
    let sgn: Vec<f64> = p.v.iter().map(|v| v.signum()).collect();
    let col_a: Vec<f64> = fast.iter().map(|&i| p.a[i]).collect();
    let col_s: Vec<f64> = fast.iter().map(|&i| p.filter_at(&sgn, i)).collect();
    let b: Vec<f64> = fast.iter().map(|&i| p.filter_at(&p.u_mid, i)).collect();
    let (mut mass, mut fc) = match lstsq(&[col_a, col_s], &b) {
        Some(c) => (c[0], c[1]),
        None => (f64::NAN, f64::NAN),
    };
    if !(fc.is_finite() && fc > 0.0) {
        let mut u: Vec<f64> = fast.iter().map(|&i| p.u_mid[i].abs()).collect();
        fc = quantile(&mut u, 0.5).max(1e-6);
    }
    if !(mass.is_finite() && mass > 0.0) {
        mass = 1e-3 * fc / (v_med.max(1e-12) / 1.0);
    }
    let v_lo = if v_lo.is_finite() && v_lo > 0.0 {
        v_lo
    } else {
        1e-3
    };
    let mut best: Option<(f64, Model)> = None;
    let mut k = 0;
    for vf in [0.3, 1.0, 3.0] {
        for zf in [10.0, 40.0, 160.0, 640.0] {
            k += 1;
            progress(&format!("base model: grid {k}/12"));
            let m = Model {
                mass,
                fc,
                fs: 1.4 * fc,
                v_stribeck: vf * v_lo,
                delta: 1.0,
                sigma: 0.0,
                z_max: zf * p.resolution,
                epsilon: 0.0,
                effects: Effects::default(),
            };
            let c = fit::train_cost(p, &m);
            if c.is_finite() && best.as_ref().is_none_or(|(b, _)| c < *b) {
                best = Some((c, m));
            }
        }
    }
    let start = best.map_or_else(fig5_model, |(_, m)| m);
    progress("base model: fitting");
    let params = fit::params_of(&start);
    fit::fit(p, &start, &params, &FitOptions::default(), &mut |_| {}).model
}

/// The base model identified from the data (a refit once with error
/// weights), with the record's error weights set from it. Without a given
/// model, `diagnose` and `validate` use these weights, so that every figure
/// on one record compares like with like whatever model it is for.
pub fn base_weights(p: &mut Prepared, progress: &mut dyn FnMut(&str)) -> Model {
    let mut model = initial_base(p, progress);
    let r0 = p.residual(&model);
    p.set_error_weights(&model, &r0);
    // The base model was identified with class weights only: refit it once
    // with error weights and take the weights from that fit.
    let params = fit::params_of(&model);
    model = fit::fit(p, &model, &params, &FitOptions::default(), &mut |_| {}).model;
    if degenerate(p, &model, Effect::Stribeck).is_some() {
        // A local minimum with V → 0 or δ at a bound: restart the shape
        // from the data's low speeds before calling Stribeck absent, and
        // before the weights and the floor are taken from this model (a
        // dip run to its bound, Fs = 11·Fc on a slow stick-slip record,
        // makes every moving sample "explained by resolution" and the
        // floor larger than the record's whole rms).
        model = restart_dip(p, model, progress);
    }
    let r1 = p.residual(&model);
    p.set_error_weights(&model, &r1);
    model
}

/// Dry friction `H` along the motion, as the residual sees it (for
/// regressions of the residual).
fn dry_force(p: &Prepared, m: &Model) -> Vec<f64> {
    let mut h = vec![0.0; p.len()];
    p.walk(m, |i, fr| h[i] = fr.dry());
    h
}

/// One-parameter regression of `r` on the filtered series `s` (training
/// samples).
fn regress(p: &Prepared, r: &[f64], s: &[f64]) -> f64 {
    let (mut sx, mut xx) = (0.0, 0.0);
    for i in p.valid().filter(|&i| !p.held_out[i]) {
        let f = p.filter_at(s, i);
        sx += p.weight[i] * f * r[i];
        xx += p.weight[i] * f * f;
    }
    if xx > 0.0 {
        sx / xx
    } else {
        0.0
    }
}

/// Two-parameter regression of `r` on the filtered `sgn(v̂)` and `s`
/// (training samples): `(ΔF, c)` with `r ≈ ΔF·sgn(v̂) + c·s`. A velocity
/// strengthening that the start model lacks is partly taken up by its
/// Coulomb level (a concave one above all); regressing on both gives the
/// candidate's start without that bias.
fn regress_with_level(p: &Prepared, r: &[f64], s: &[f64]) -> (f64, f64) {
    let sgn: Vec<f64> = p.v.iter().map(|v| v.signum()).collect();
    let (mut aa, mut ab, mut bb, mut ar, mut br) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in p.valid().filter(|&i| !p.held_out[i]) {
        let (a, b, w) = (p.filter_at(&sgn, i), p.filter_at(s, i), p.weight[i]);
        aa += w * a * a;
        ab += w * a * b;
        bb += w * b * b;
        ar += w * a * r[i];
        br += w * b * r[i];
    }
    let det = aa * bb - ab * ab;
    if det > 1e-12 * aa * bb && det > 0.0 {
        ((ar * bb - br * ab) / det, (br * aa - ar * ab) / det)
    } else {
        (0.0, regress(p, r, s))
    }
}

/// The best wavelength of a spatial periodogram of `r` over moving samples:
/// `(λ, A·cos φ, A·sin φ, explained fraction)`.
pub fn ripple_scan(p: &Prepared, r: &[f64], filtered: bool) -> (f64, f64, f64, f64) {
    let idx: Vec<usize> = p
        .valid()
        .filter(|&i| !p.held_out[i] && p.v[i].abs() > p.v_rest)
        .collect();
    if idx.len() < 20 {
        return (1.0, 0.0, 0.0, 0.0);
    }
    let (lo, hi) = idx
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &i| {
            (a.min(p.x[i]), b.max(p.x[i]))
        });
    let span = (hi - lo).max(1e-12);
    let total: f64 = idx.iter().map(|&i| p.weight[i] * r[i] * r[i]).sum();
    let lam_min = (50.0 * p.resolution).max(span / 2000.0);
    let lam_max = span / 3.0;
    let mut best = (1.0, 0.0, 0.0, 0.0);
    if lam_max <= lam_min || total <= 0.0 {
        return best;
    }
    let steps = 300;
    for s in 0..=steps {
        let lam = lam_min * (lam_max / lam_min).powf(s as f64 / steps as f64);
        let k = 2.0 * PI / lam;
        let (mut ss, mut sc, mut cc, mut rs, mut rc) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let sin: Vec<f64>;
        let cos: Vec<f64>;
        if filtered {
            let raw_sin: Vec<f64> = p.x.iter().map(|x| (k * x).sin()).collect();
            let raw_cos: Vec<f64> = p.x.iter().map(|x| (k * x).cos()).collect();
            sin = p.filter_all(&raw_sin);
            cos = p.filter_all(&raw_cos);
        } else {
            sin = Vec::new();
            cos = Vec::new();
        }
        for &i in &idx {
            let (a, b) = if filtered {
                (sin[i], cos[i])
            } else {
                ((k * p.x[i]).sin(), (k * p.x[i]).cos())
            };
            let w = p.weight[i];
            ss += w * a * a;
            sc += w * a * b;
            cc += w * b * b;
            rs += w * r[i] * a;
            rc += w * r[i] * b;
        }
        let det = ss * cc - sc * sc;
        if det <= 0.0 {
            continue;
        }
        let c1 = (rs * cc - rc * sc) / det;
        let c2 = (rc * ss - rs * sc) / det;
        let explained = (c1 * rs + c2 * rc) / total;
        if explained > best.3 {
            best = (lam, c1, c2, explained);
        }
    }
    best
}

/// Moves Fc and Fs together by `level` [N], keeping Fc at least a tenth
/// of its value.
fn shift_levels(m: &mut Model, level: f64) {
    let level = level.max(-0.9 * m.fc);
    m.fc += level;
    m.fs += level;
}

/// Starting models for adding `effect` to `m` (refitted from each).
fn candidate_starts(p: &Prepared, m: &Model, effect: Effect, r: &[f64]) -> Vec<Model> {
    let mut out = Vec::new();
    let t_span = (p.t[p.len() - 1] - p.t[0]).max(1e-9);
    let with = |f: &dyn Fn(&mut Model)| {
        let mut c = m.clone();
        f(&mut c);
        c
    };
    match effect {
        Effect::Viscous => {
            let v_max = p.v.iter().fold(1e-12f64, |a, v| a.max(v.abs()));
            let s = regress(p, r, &p.v).max(1e-3 * m.fc / v_max);
            out.push(with(&|c| c.sigma = s));
            let (level, s) = regress_with_level(p, r, &p.v);
            out.push(with(&|c| {
                c.sigma = s.max(1e-3 * m.fc / v_max);
                shift_levels(c, level);
            }));
        }
        Effect::NonlinearViscous => {
            let v_max = p.v.iter().fold(1e-12f64, |a, v| a.max(v.abs()));
            for n in [0.3, 0.6, 1.5, 2.0] {
                let s: Vec<f64> = p.v.iter().map(|v| v.signum() * v.abs().powf(n)).collect();
                let least = 1e-3 * m.fc / v_max.powf(n);
                let sigma_n = regress(p, r, &s).max(least);
                out.push(with(&|c| {
                    c.effects.nonlinear_viscous = Some(NonlinearViscous { sigma_n, n })
                }));
                let (level, sigma_n) = regress_with_level(p, r, &s);
                let sigma_n = sigma_n.max(least);
                out.push(with(&|c| {
                    c.effects.nonlinear_viscous = Some(NonlinearViscous { sigma_n, n });
                    shift_levels(c, level);
                }));
            }
        }
        Effect::Offset => {
            let one = vec![1.0; p.len()];
            let f0 = regress(p, r, &one);
            out.push(with(&|c| c.effects.offset = Some(Offset { f0 })));
        }
        Effect::Asymmetry => {
            let h = dry_force(p, m);
            let a = (regress(p, r, &h)).clamp(-0.5, 0.5);
            for a0 in [a, 0.1, -0.1] {
                out.push(with(&|c| c.effects.asymmetry = Some(Asymmetry { a: a0 })));
            }
        }
        Effect::PositionRipple => {
            let (lam, c1, c2, _) = ripple_scan(p, r, true);
            out.push(with(&|c| {
                c.effects.position_ripple = Some(PositionRipple {
                    amplitude: c1.hypot(c2),
                    wavelength: lam,
                    phase: c2.atan2(c1),
                })
            }));
        }
        Effect::DwellStiction => out.extend(dwell_starts(p, m, r)),
        Effect::FrictionalLag => {
            // Lag and the Stribeck shape trade off (a base model fitted
            // without lag bends V, δ to mimic it), so the shape restarts too.
            // It may even have dropped the Stribeck dip (V → 0): restart
            // it from the data's low speeds as the base model's grid does.
            let v_lo = low_speed(p).unwrap_or(m.v_stribeck);
            for tau_l in [0.01, 0.03, 0.1] {
                out.push(with(&|c| {
                    c.effects.frictional_lag = Some(FrictionalLag { tau_l })
                }));
                if fit::has_effect(m, Effect::Stribeck) {
                    out.push(with(&|c| {
                        c.effects.frictional_lag = Some(FrictionalLag { tau_l });
                        c.delta = 2.0;
                        c.v_stribeck = v_lo;
                        c.fs = c.fs.clamp(1.1 * c.fc, 2.0 * c.fc);
                    }));
                }
            }
        }
        Effect::Drift => {
            let h = dry_force(p, m);
            let ht: Vec<f64> = h.iter().zip(&p.t).map(|(h, t)| h * (t - p.t[0])).collect();
            let beta = regress(p, r, &ht).clamp(-1.0 / t_span, 1.0 / t_span);
            out.push(with(&|c| c.effects.drift = Some(Drift { beta })));
        }
        Effect::Stribeck => {
            for vf in [0.3, 1.0, 3.0] {
                out.push(with(&|c| {
                    c.fs = 1.3 * c.fc;
                    c.v_stribeck = m.v_stribeck * vf;
                }));
            }
        }
        Effect::Presliding => {
            for zf in [10.0, 40.0, 160.0, 640.0] {
                out.push(with(&|c| c.z_max = zf * p.resolution));
            }
        }
    }
    // A dip lost while the effect was missing (a symmetric dip cannot
    // follow an offset or an asymmetry, so the base fit ran it to Fs = Fc
    // or to a bound) does not come back in a local fit, and without it
    // `offset` and `asymmetry` are the same constant shift: the first
    // start is also tried with the dip seeded again, every start for the
    // two look-alikes, which the dip tells apart.
    if !matches!(
        effect,
        Effect::Stribeck | Effect::Presliding | Effect::FrictionalLag
    ) && dip_lost(p, m)
    {
        let take = if look_alike(effect).is_some() {
            out.len()
        } else {
            1
        };
        let seeded: Vec<Model> = out
            .iter()
            .take(take)
            .flat_map(|c| dip_seeds(p, c))
            .collect();
        out.extend(seeded);
    }
    // A base model that used δ at the edge of its range to mimic the
    // missing effect is also restarted from δ = 2.
    if m.delta > 3.0 || m.delta < 0.5 {
        let again: Vec<Model> = out
            .iter()
            .map(|c| {
                let mut c = c.clone();
                c.delta = 2.0;
                c
            })
            .collect();
        out.extend(again);
    }
    out.retain(|c| c.validate().is_ok());
    out
}

/// Starting models for `dwell_stiction`: a grid over the rest threshold
/// `v_rest` and γ, each with ΔFs and the stiction level Fs from a linear
/// regression of the residual on their signatures (the break-away peaks
/// after rests of different length: Fs moves all of them, ΔFs in
/// proportion to `t_d/(t_d + γ)`); the best grid points by the cost drop.
///
/// `v_rest` is not fitted by least squares (t_d jumps with it). The grid
/// holds the encoder's rest (no count change for 50 samples, the 1/T
/// velocity of [`crate::fit`]) and fractions of the Stribeck velocity,
/// which also count the slow presliding creep before a break-away as rest.
fn dwell_starts(p: &Prepared, m: &Model, r: &[f64]) -> Vec<Model> {
    let count_rate = p.resolution / p.dt;
    let mut v_rests = vec![0.02 * count_rate];
    for f in [0.02, 0.05, 0.15] {
        let v = f * m.v_stribeck;
        if v > 0.03 * count_rate {
            v_rests.push(v);
        }
    }
    let stribeck = fit::has_effect(m, Effect::Stribeck);
    let train: Vec<usize> = p.valid().filter(|&i| !p.held_out[i]).collect();
    let f0 = p.friction(m);
    let h = 0.1 * m.fc;
    let mut m_fs = m.clone();
    m_fs.fs += h;
    let d_fs: Vec<f64> = p
        .friction(&m_fs)
        .iter()
        .zip(&f0)
        .map(|(a, b)| (a - b) / h)
        .collect();
    let col_fs: Vec<f64> = train
        .iter()
        .map(|&i| p.weight[i].sqrt() * p.filter_at(&d_fs, i))
        .collect();
    let b: Vec<f64> = train.iter().map(|&i| p.weight[i].sqrt() * r[i]).collect();
    let mut scored: Vec<(f64, Model)> = Vec::new();
    for &v_rest in &v_rests {
        for gamma in [0.1, 0.3, 1.0] {
            let mut c = m.clone();
            c.effects.dwell_stiction = Some(DwellStiction {
                delta_fs: h,
                gamma,
                v_rest,
            });
            let d_dw: Vec<f64> = p
                .friction(&c)
                .iter()
                .zip(&f0)
                .map(|(a, b)| (a - b) / h)
                .collect();
            let col_dw: Vec<f64> = train
                .iter()
                .map(|&i| p.weight[i].sqrt() * p.filter_at(&d_dw, i))
                .collect();
            // r = W*(u − F) − m·a: a friction change dF lowers r by W*dF.
            let cols = if stribeck {
                vec![col_dw.clone(), col_fs.clone()]
            } else {
                vec![col_dw.clone()]
            };
            let Some(coef) = lstsq(&cols, &b) else {
                continue;
            };
            let (dfs, dfs_level) = (coef[0], coef.get(1).copied().unwrap_or(0.0));
            let gain: f64 = col_dw
                .iter()
                .zip(&col_fs)
                .zip(&b)
                .map(|((x, y), b)| {
                    let e = b - dfs * x - dfs_level * y;
                    b * b - e * e
                })
                .sum();
            let mut c = m.clone();
            if stribeck {
                c.fs = (m.fs + dfs_level).max(m.fc * 1.001);
            }
            c.effects.dwell_stiction = Some(DwellStiction {
                delta_fs: dfs.clamp(0.02 * m.fc, 2.0 * m.fc),
                gamma,
                v_rest,
            });
            scored.push((if dfs > 0.0 { gain } else { f64::MIN }, c));
        }
    }
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    scored.into_iter().take(4).map(|(_, c)| c).collect()
}

/// Shortest rest counted by [`dwell_spread`] [s]: the data-side rest at a
/// slow reversal through zero lasts up to about 60 ms at high encoder noise.
pub const MIN_DWELL_REST: f64 = 0.1;

/// Least spread of the dwell factor `t_d/(t_d + γ)` over the rests of a
/// record (see [`dwell_spread`]) for a `dwell_stiction` candidate to count.
/// In the test matrix the identified dwell terms spread 0.27–0.36, the
/// spurious ones (γ of 30–50 ms, fitting "after a rest" against "after a
/// reversal") 0.05–0.07.
pub const MIN_DWELL_SPREAD: f64 = 0.15;

/// Spread (max − min) of `t_d/(t_d + γ)` of `m`'s dwell term over the
/// rests of at least [`MIN_DWELL_REST`] that end in motion (data-side rest: `|v̂| ≤
/// v_rest`); 0 without the effect or with fewer than two such rests.
pub fn dwell_spread(p: &Prepared, m: &Model) -> f64 {
    let Some(dw) = m.effects.dwell_stiction else {
        return 0.0;
    };
    let mut start: Option<f64> = Some(p.t[0]);
    let (mut lo, mut hi, mut n) = (f64::INFINITY, f64::NEG_INFINITY, 0);
    for i in 0..p.len() {
        if p.model_velocity(i).abs() <= dw.v_rest {
            start.get_or_insert(p.t[i]);
        } else if let Some(s) = start.take() {
            let td = p.t[i] - s;
            if td >= MIN_DWELL_REST {
                let f = td / (td + dw.gamma);
                lo = lo.min(f);
                hi = hi.max(f);
                n += 1;
            }
        }
    }
    if n >= 2 {
        hi - lo
    } else {
        0.0
    }
}

/// Share of the remaining gap (model error above the floor) that the
/// general `nonlinear_viscous` must remove beyond `viscous` to be named
/// instead of it.
pub const NESTED_GAP_GAIN: f64 = 0.1;

/// `viscous` is `nonlinear_viscous` with `n = 1`: the general form is
/// taken only when its model error is [`NESTED_GAP_GAIN`] below the nested
/// one's; otherwise `viscous` moves to the front. The comparison is on the
/// gap, not on the raw rms: where noise and resolution dominate the rms,
/// a fixed share of it would hide an exponent the data clearly show.
fn prefer_nested(cands: &mut [Candidate], floor: f64) {
    let pos = |effect: Effect| cands.iter().position(|c| c.effect == effect);
    if let (Some(0), Some(v)) = (pos(Effect::NonlinearViscous), pos(Effect::Viscous)) {
        let general = fit::model_error(cands[0].rms, floor);
        let nested = fit::model_error(cands[v].rms, floor);
        if general > (1.0 - NESTED_GAP_GAIN) * nested {
            cands.swap(0, v);
        }
    }
}

/// The 20 % quantile of the moving speeds [m/s] (`None` without moving
/// samples): where a Stribeck search starts.
fn low_speed(p: &Prepared) -> Option<f64> {
    let mut speeds: Vec<f64> = p
        .valid()
        .map(|i| p.v[i].abs())
        .filter(|s| *s > p.v_rest)
        .collect();
    let v = quantile(&mut speeds, 0.2);
    (v.is_finite() && v > 0.0).then_some(v)
}

/// `m`, or the best of its shape [`restarts`] when that has the lower
/// held-out RMS.
fn restart_dip(p: &Prepared, m: Model, show: &mut dyn FnMut(&str)) -> Model {
    let starts = restarts(p, &m);
    let sound = |c: &Model| degenerate(p, c, Effect::Stribeck).is_none();
    let again = fit_multistart(p, &starts, &sound, &mut |s| {
        show(&format!("restarting the Stribeck shape ({s})"))
    });
    if !dip_run_to_bound(&m, &again) && held_rms(p, &again).0 < held_rms(p, &m).0 {
        again
    } else {
        m
    }
}

/// Whether `m` holds a Stribeck level `Fs` at the top of its range.
fn fs_at_bound(m: &Model) -> bool {
    fit::has_effect(m, Effect::Stribeck) && m.fs - m.fc > 0.99 * fit::FS_EXCESS_MAX * m.fc
}

/// Whether `fitted` holds a Stribeck level at the top of its range that
/// the current model `current` did not hold: a seeded or bent dip that a
/// candidate ran to the bound (on EMPS, `Fs = 11·Fc` beside `viscous`: a
/// hump standing in for the Coulomb level, written as a model) is not a
/// finding of the candidate.
fn dip_run_to_bound(current: &Model, fitted: &Model) -> bool {
    fs_at_bound(fitted) && !fs_at_bound(current)
}

/// Whether `m`'s Stribeck dip is absent (`Fs = Fc`) or degenerate.
fn dip_lost(p: &Prepared, m: &Model) -> bool {
    !fit::has_effect(m, Effect::Stribeck) || degenerate(p, m, Effect::Stribeck).is_some()
}

/// `m` with its Stribeck dip seeded again: `Fs = 1.4·Fc`, δ = 2, `V` at
/// 1 and 3 times the 20 % speed quantile (the base grid's middle).
fn dip_seeds(p: &Prepared, m: &Model) -> Vec<Model> {
    let v_lo = low_speed(p).unwrap_or(1e-3);
    [1.0, 3.0]
        .into_iter()
        .map(|vf| {
            let mut c = m.clone();
            c.fs = 1.4 * c.fc;
            c.v_stribeck = vf * v_lo;
            c.delta = 2.0;
            c
        })
        .collect()
}

/// Restarts of the base shape: `V` at 0.3, 1 and 3 times the 20 % speed
/// quantile, δ = 1 and 2, `Fs = 1.4·Fc`, the rest of `m` kept.
fn restarts(p: &Prepared, m: &Model) -> Vec<Model> {
    let v_lo = low_speed(p).unwrap_or(1e-3);
    let mut out = vec![m.clone()];
    for vf in [0.3, 1.0, 3.0] {
        for delta in [1.0, 2.0] {
            let mut c = m.clone();
            c.fs = 1.4 * c.fc;
            c.v_stribeck = vf * v_lo;
            c.delta = delta;
            out.push(c);
        }
    }
    out
}

/// Least relative rise of the held-out RMS for which a part of the base
/// structure (`stribeck`, `presliding`) is kept: a part whose removal
/// costs less than this is not supported by the record.
pub const KEEP_GAIN: f64 = 0.01;

/// A degenerate base part (a parameter at a bound) is still kept when the
/// model without it is worse by more than this fraction of the held-out
/// RMS: the record needs the shape, only not at an interior value.
pub const DEGENERATE_KEEP: f64 = 0.1;

/// Why the part `effect` of `m` (a catalogue effect, `stribeck` or
/// `presliding` included) is degenerate — a parameter at a bound of its
/// range or at a value the record cannot resolve — or `None`.
pub fn degenerate(p: &Prepared, m: &Model, effect: Effect) -> Option<String> {
    let near = |x: f64, bound: f64| (x / bound).ln().abs() < 0.02;
    match effect {
        Effect::Stribeck => {
            if !fit::has_effect(m, effect) {
                None
            } else if m.v_stribeck < p.v_rest {
                Some(format!(
                    "V = {:.3e} m/s is below the slowest speed the encoder resolves ({:.3e} m/s)",
                    m.v_stribeck, p.v_rest
                ))
            } else if near(m.delta, fit::DELTA_RANGE.0) || near(m.delta, fit::DELTA_RANGE.1) {
                Some(format!("delta = {:.4} at a bound of its range", m.delta))
            } else if m.fs - m.fc < 1e-3 * m.fc {
                Some("Fs - Fc below 0.1 % of Fc".into())
            } else if fs_at_bound(m) {
                Some(format!(
                    "Fs = {:.3}·Fc at the bound of its range",
                    m.fs / m.fc
                ))
            } else {
                None
            }
        }
        Effect::Presliding => {
            (fit::has_effect(m, effect) && m.z_max < 1.5 * p.resolution).then(|| {
                format!(
                    "z_max = {:.3e} m is below 1.5 encoder counts ({:.3e} m)",
                    m.z_max, p.resolution
                )
            })
        }
        Effect::DwellStiction => m.effects.dwell_stiction.and_then(|d| {
            (near(d.gamma, 5e-3) || near(d.gamma, 100.0))
                .then(|| format!("gamma = {} s at a bound", d.gamma))
        }),
        Effect::NonlinearViscous => nonlinear_viscous_degenerate(m),
        Effect::FrictionalLag => m.effects.frictional_lag.and_then(|l| {
            (near(l.tau_l, 1e-3) || near(l.tau_l, 100.0))
                .then(|| format!("tau_l = {} s at a bound", l.tau_l))
        }),
        Effect::Viscous
        | Effect::Offset
        | Effect::Asymmetry
        | Effect::PositionRipple
        | Effect::Drift => None,
    }
}

/// Smallest exponent `n` for which `nonlinear_viscous` is a finding:
/// below it `|v|^n` changes by less than 1.4× per decade of speed (0.15),
/// a level that trades with Fc (on a ramp record a fit ran to n = 0.053
/// beside `viscous` and moved Fc by a third).
pub const NV_MIN_EXPONENT: f64 = 0.15;

/// Why `m`'s `nonlinear_viscous` term is not a finding, or `None`:
/// `n = 1` is `viscous` (MODEL.md §5 names it only for n ≠ 1), and an `n`
/// at the lower bound of [`fit::NV_EXP_RANGE`] is not identified (the upper, 2, is MODEL.md's limit),
/// nor one below [`NV_MIN_EXPONENT`].
pub fn nonlinear_viscous_degenerate(m: &Model) -> Option<String> {
    let nv = m.effects.nonlinear_viscous?;
    let near = |x: f64, bound: f64| (x / bound).ln().abs() < 0.02;
    if (nv.n - 1.0).abs() < 0.1 {
        Some(format!("n = {:.3} is viscous", nv.n))
    } else if near(nv.n, fit::NV_EXP_RANGE.0) {
        // The upper end, n = 2, is MODEL.md's own limit and a valid value;
        // the lower end is only the fit's.
        Some(format!("n = {:.3} at the lower bound of its range", nv.n))
    } else if nv.n < NV_MIN_EXPONENT {
        Some(format!(
            "n = {:.3} is a second Coulomb level, not a velocity strengthening",
            nv.n
        ))
    } else {
        None
    }
}

/// Drops the parts of the base structure that the record does not
/// support: `stribeck` or `presliding` when a parameter of theirs is
/// degenerate ([`degenerate`]), or (with `by_rms`, once the missing
/// effects are in) when the model refitted without them is within
/// [`KEEP_GAIN`] of the held-out RMS with them. Returns the simpler
/// model and what was dropped, with the reason.
fn simplify(
    p: &Prepared,
    mut m: Model,
    by_rms: bool,
    progress: &mut dyn FnMut(&str),
) -> (Model, Vec<(Effect, String)>) {
    let mut dropped = Vec::new();
    // Stribeck once more after presliding: the refit without presliding
    // can run the dip to its bound (EMPS: Fs from 6.9·Fc to 11·Fc).
    for part in [Effect::Stribeck, Effect::Presliding, Effect::Stribeck] {
        if dropped.iter().any(|(d, _)| *d == part) {
            continue;
        }
        if !fit::has_effect(&m, part) || (!by_rms && degenerate(p, &m, part).is_none()) {
            continue;
        }
        progress(&format!("is {part} identifiable?"));
        let without = remove_effect(&m, part, p);
        let params = fit::params_of(&without);
        let refit = fit::fit(p, &without, &params, &FitOptions::default(), &mut |_| {}).model;
        let (with_rms, without_rms) = (held_rms(p, &m).0, held_rms(p, &refit).0);
        // A degenerate part is dropped unless the record clearly needs it
        // (its refit without is worse by more than DEGENERATE_KEEP); a
        // sound one only when it does not help by KEEP_GAIN.
        let reason = match degenerate(p, &m, part) {
            Some(why) if part == Effect::Stribeck && fs_at_bound(&m) => Some(why),
            Some(why) if without_rms <= (1.0 + DEGENERATE_KEEP) * with_rms => Some(why),
            Some(_) => None,
            None => (without_rms <= (1.0 + KEEP_GAIN) * with_rms).then(|| {
                format!(
                    "held-out rms {:.4e} N without it, {:.4e} N with it",
                    without_rms, with_rms
                )
            }),
        };
        if let Some(why) = reason {
            dropped.push((part, why));
            m = refit;
        }
    }
    (m, dropped)
}

/// Without a Stribeck dip (`Fs = Fc`) `V` and `δ` have no effect; they are
/// written as neutral, physical values (as [`remove_effect`] does), never
/// as what a fit left (EMPS: `V = 1.7e-22`, δ at its bound).
fn tidy(p: &Prepared, m: Model) -> Model {
    if fit::has_effect(&m, Effect::Stribeck) {
        m
    } else {
        remove_effect(&m, Effect::Stribeck, p)
    }
}

/// `m` without the catalogue effect `effect`.
fn remove_effect(m: &Model, effect: Effect, p: &Prepared) -> Model {
    let mut c = m.clone();
    let e = &mut c.effects;
    match effect {
        Effect::Viscous => c.sigma = 0.0,
        Effect::Offset => e.offset = None,
        Effect::Asymmetry => e.asymmetry = None,
        Effect::PositionRipple => e.position_ripple = None,
        Effect::DwellStiction => e.dwell_stiction = None,
        Effect::FrictionalLag => e.frictional_lag = None,
        Effect::Drift => e.drift = None,
        Effect::NonlinearViscous => e.nonlinear_viscous = None,
        Effect::Stribeck => {
            // Fs = Fc marks the absence (MODEL.md §7); V and δ then have no
            // effect and are written as neutral, physical values.
            c.fs = c.fc;
            c.v_stribeck = low_speed(p).unwrap_or(1e-3);
            c.delta = 1.0;
        }
        Effect::Presliding => c.z_max = 0.0,
    }
    c
}

/// The signal that localises each effect (for the report and the plot).
pub fn signal_of(effect: Effect) -> &'static str {
    match effect {
        Effect::Viscous
        | Effect::NonlinearViscous
        | Effect::Offset
        | Effect::Asymmetry
        | Effect::Stribeck
        | Effect::FrictionalLag => "velocity",
        Effect::PositionRipple => "position",
        Effect::DwellStiction => "rest time before motion",
        Effect::Drift => "time",
        Effect::Presliding => "time since turning point",
    }
}

/// Per-sample series of the localising signals: velocity, direction,
/// position, time, time since the last turning point, rest time before the
/// current motion (NaN where not defined).
pub fn signal_series(p: &Prepared, m: &Model) -> Vec<(String, Vec<f64>)> {
    let n = p.len();
    let mut dir = vec![0.0; n];
    let mut since_tp = vec![f64::NAN; n];
    let mut rest_before = vec![f64::NAN; n];
    let mut fr = Friction::new(m, p.t[0], p.x[0], p.v[0]);
    let mut last_d = 0i8;
    let mut t_tp = p.t[0];
    let mut rest_start: Option<f64> = Some(p.t[0]);
    let mut last_rest = 0.0;
    let mut t_motion = p.t[0];
    let rest_speed = p.v_rest;
    for i in 0..n {
        fr.update(m, p.t[i], p.x[i], p.model_velocity(i));
        let d = fr.direction();
        if d != last_d {
            t_tp = p.t[i];
            last_d = d;
        }
        dir[i] = f64::from(d);
        since_tp[i] = p.t[i] - t_tp;
        if p.model_velocity(i).abs() <= rest_speed {
            if rest_start.is_none() {
                rest_start = Some(p.t[i]);
            }
        } else if let Some(s) = rest_start.take() {
            last_rest = p.t[i] - s;
            t_motion = p.t[i];
        }
        if rest_start.is_none() && p.t[i] - t_motion < 0.15 {
            rest_before[i] = last_rest;
        }
    }
    vec![
        ("velocity".into(), p.v.clone()),
        ("direction".into(), dir),
        ("position".into(), p.x.clone()),
        ("time".into(), p.t.clone()),
        ("time since turning point".into(), since_tp),
        ("rest time before motion".into(), rest_before),
    ]
}

/// Fraction of the (weighted) residual power explained by binned means of
/// `r·d` (direction-signed where the effect scales friction) against `s`.
fn explained(p: &Prepared, r: &[f64], s: &[f64], dir: &[f64], signed: bool, bins: usize) -> f64 {
    let idx: Vec<usize> = p.valid().filter(|&i| s[i].is_finite()).collect();
    let total: f64 = p.valid().map(|i| p.weight[i] * r[i] * r[i]).sum();
    if idx.len() < 2 * bins || total <= 0.0 {
        return 0.0;
    }
    let mut sorted: Vec<f64> = idx.iter().map(|&i| s[i]).collect();
    sorted.sort_by(f64::total_cmp);
    let edges: Vec<f64> = (1..bins)
        .map(|b| sorted[b * (sorted.len() - 1) / bins])
        .collect();
    let mut sum = vec![0.0; bins];
    let mut wsum = vec![0.0; bins];
    for &i in &idx {
        let b = edges.partition_point(|e| *e < s[i]);
        let y = if signed && dir[i] != 0.0 {
            r[i] * dir[i]
        } else {
            r[i]
        };
        sum[b] += p.weight[i] * y;
        wsum[b] += p.weight[i];
    }
    let ex: f64 = sum
        .iter()
        .zip(&wsum)
        .filter(|(_, w)| **w > 0.0)
        .map(|(s, w)| s * s / w)
        .sum();
    ex / total
}

/// How much of `r` each signal explains.
pub fn localise_signals(
    p: &Prepared,
    r: &[f64],
    series: &[(String, Vec<f64>)],
) -> Vec<(String, f64)> {
    let dir = &series[1].1;
    let mut out = Vec::new();
    for (name, s) in series {
        let f = match name.as_str() {
            "velocity" => explained(p, r, s, dir, false, 24),
            "direction" => explained(p, r, s, dir, false, 2),
            "position" => ripple_scan(p, r, false).3,
            "time" => explained(p, r, s, dir, true, 12),
            "time since turning point" => {
                let l: Vec<f64> = s.iter().map(|v| (v + 1e-4).ln()).collect();
                explained(p, r, &l, dir, true, 12)
            }
            _ => explained(p, r, s, dir, true, 6),
        };
        out.push((name.clone(), f));
    }
    out
}

/// Regime label of every sample under model `m`.
pub fn regimes(p: &Prepared, m: &Model) -> Vec<String> {
    let n = p.len();
    let mut fr = Friction::new(m, p.t[0], p.x[0], p.v[0]);
    let mut out = Vec::with_capacity(n);
    let mut rest_len = 0.0;
    let mut rest_start: Option<f64> = Some(p.t[0]);
    let mut breaking = false;
    let mut sliding: Vec<f64> = p
        .valid()
        .map(|i| p.v[i].abs())
        .filter(|s| *s >= 3.0 * m.v_stribeck)
        .collect();
    sliding.sort_by(f64::total_cmp);
    let band = |s: f64| -> String {
        if sliding.len() < 3 {
            return "sliding".into();
        }
        let q1 = sliding[sliding.len() / 3];
        let q2 = sliding[2 * sliding.len() / 3];
        let (a, b) = if s < q1 {
            (sliding[0], q1)
        } else if s < q2 {
            (q1, q2)
        } else {
            (q2, sliding[sliding.len() - 1])
        };
        format!(
            "sliding {}-{} m/s",
            crate::format::short(a, 2),
            crate::format::short(b, 2)
        )
    };
    for i in 0..n {
        fr.update(m, p.t[i], p.x[i], p.v[i]);
        let s = p.v[i].abs();
        let d = if fr.direction() >= 0 { "+" } else { "-" };
        if s <= p.v_rest {
            if rest_start.is_none() {
                rest_start = Some(p.t[i]);
            }
            out.push("rest".to_string());
            continue;
        }
        if let Some(st) = rest_start.take() {
            rest_len = p.t[i] - st;
            breaking = rest_len >= 0.02;
        }
        if breaking && s >= 2.0 * m.v_stribeck {
            breaking = false;
        }
        let w = fr.presliding().travel(m.z_max, p.x[i]);
        let label = if w < 1.0 {
            "presliding".to_string()
        } else if breaking {
            "break-away".to_string()
        } else if s < 3.0 * m.v_stribeck {
            "low speed".to_string()
        } else {
            band(s)
        };
        out.push(format!("{label} {d}"));
    }
    let _ = rest_len;
    out
}

/// RMS of `r` per regime label, largest first.
pub fn regime_stats(p: &Prepared, r: &[f64], labels: &[String]) -> Vec<RegimeStat> {
    let mut names: Vec<String> = Vec::new();
    let mut acc: Vec<(usize, f64)> = Vec::new();
    for i in p.valid() {
        let k = match names.iter().position(|n| *n == labels[i]) {
            Some(k) => k,
            None => {
                names.push(labels[i].clone());
                acc.push((0, 0.0));
                names.len() - 1
            }
        };
        acc[k].0 += 1;
        acc[k].1 += r[i] * r[i];
    }
    let mut out: Vec<RegimeStat> = names
        .into_iter()
        .zip(acc)
        .map(|(regime, (n, s))| RegimeStat {
            regime,
            n,
            rms: (s / n.max(1) as f64).sqrt(),
        })
        .collect();
    out.sort_by(|a, b| b.rms.total_cmp(&a.rms));
    out
}

/// Contiguous stretches of one regime, the largest residual first.
fn regions_of(p: &Prepared, r: &[f64], labels: &[String], count: usize) -> Vec<Region> {
    let min_len = ((0.01 / p.dt).ceil() as usize).max(3);
    let mut runs = Vec::new();
    let valid = p.valid();
    let mut i = valid.start;
    while i < valid.end {
        let mut j = i;
        let mut s = 0.0;
        while j < valid.end && labels[j] == labels[i] {
            s += r[j] * r[j];
            j += 1;
        }
        if j - i >= min_len {
            runs.push(Region {
                regime: labels[i].clone(),
                t_start: p.t[i],
                t_end: p.t[j - 1],
                rms: (s / (j - i) as f64).sqrt(),
            });
        }
        i = j;
    }
    runs.sort_by(|a, b| b.rms.total_cmp(&a.rms));
    runs.truncate(count);
    runs
}

/// Runs the workflow on `rec` from `start` (`None`: the base model
/// identified from the data).
pub fn diagnose(
    rec: &Record,
    start: Option<&Model>,
    opts: &Options,
    progress: &mut Progress,
) -> Report {
    let mut p = Prepared::with_window(rec, opts.window);
    let mut show = |s: &str| progress.show(s);
    // Error-in-variables weights from the start model, fixed from here on:
    // every figure compared below uses them.
    let mut model = match start {
        Some(m) => {
            let r0 = p.residual(m);
            p.set_error_weights(m, &r0);
            m.clone()
        }
        None => base_weights(&mut p, &mut show),
    };
    let floor = p.floor(Some(true));
    let given = start.map(|m| fit::model_error(held_rms(&p, m).0, floor));
    show("refitting with error weights");
    let params = fit::params_of(&model);
    model = fit::fit(&p, &model, &params, &FitOptions::default(), &mut |_| {}).model;
    // A degenerate base part is kept while effects are missing (they can
    // bend the base fit); the final model is simplified below.
    let mut dropped = Vec::new();
    let start_model = model.clone();
    let (mut rms, mut r) = held_rms(&p, &model);
    let raw_before = rms;
    let residual_before = r.clone();
    let labels = regimes(&p, &model);
    let regimes_before = regime_stats(&p, &r, &labels);
    let regions = regions_of(&p, &r, &labels, 8);
    let series = signal_series(&p, &model);
    let signals = localise_signals(&p, &r, &series);
    let allowed = |e: Effect| opts.candidates.is_empty() || opts.candidates.contains(&e);
    let mut steps = Vec::new();
    let mut last_round = Vec::new();
    // Whether a round restarted the Stribeck shape after a step: the
    // step's choice among look-alikes was then made on another base.
    let mut reshaped = false;
    for round in 0..MAX_ROUNDS {
        let missing: Vec<Effect> = Effect::ALL
            .into_iter()
            .filter(|&e| !fit::has_effect(&model, e) && allowed(e))
            .filter(|e| !dropped.iter().any(|(d, _)| d == e))
            .collect();
        if round > 0 && dip_lost(&p, &model) {
            // The candidates below may seed the dip again (see
            // `candidate_starts`): what the dip alone gains is taken here
            // first, unnamed, so that no effect is credited with it.
            let again = restart_dip(&p, model.clone(), &mut show);
            if again != model {
                reshaped = true;
                model = again;
                (rms, r) = held_rms(&p, &model);
            }
        }
        let (mut cands, mut held_back) = (Vec::new(), Vec::new());
        let n_cur = fit::params_of(&model).len();
        let bic_cur = bic(&p, rms, n_cur);
        for (ci, &effect) in missing.iter().enumerate() {
            let starts = candidate_starts(&p, &model, effect, &r);
            if starts.is_empty() {
                continue;
            }
            let label = format!(
                "round {}: candidate {}/{} {effect}",
                round + 1,
                ci + 1,
                missing.len()
            );
            let sound =
                |m: &Model| degenerate(&p, m, effect).is_none() && !dip_run_to_bound(&model, m);
            let fitted = fit_multistart(&p, &starts, &sound, &mut |s| {
                show(&format!("{label} ({s})"))
            });
            if !fit::has_effect(&fitted, effect) {
                continue;
            }
            // Dwell *time* stiction must make the break-away depend on the
            // rest length; a γ far below every rest of the record only
            // separates "after a rest" from "after a reversal" (the
            // look-alike of MODEL.md §4's rate dependence).
            if effect == Effect::DwellStiction && dwell_spread(&p, &fitted) < MIN_DWELL_SPREAD {
                continue;
            }
            // A fit that ran to a bound of its parameters has not found
            // the effect (or has found a simpler structure).
            if degenerate(&p, &fitted, effect).is_some() {
                continue;
            }
            if visibility(&p, &fitted, effect) < MIN_VISIBILITY {
                continue;
            }
            let (c_rms, _) = held_rms(&p, &fitted);
            let score = bic(&p, c_rms, fit::params_of(&fitted).len()) - bic_cur;
            let candidate = Candidate {
                effect,
                rms: c_rms,
                score,
                model: fitted,
            };
            if dip_run_to_bound(&model, &candidate.model) {
                held_back.push(candidate);
            } else {
                cands.push(candidate);
            }
        }
        cands.sort_by(|a, b| a.score.total_cmp(&b.score));
        held_back.sort_by(|a, b| a.score.total_cmp(&b.score));
        prefer_nested(&mut cands, floor);
        let accept = cands
            .first()
            .is_some_and(|c| c.score < 0.0 && enough_gain(c.effect, rms, c.rms, floor));
        if !accept {
            last_round = cands;
            break;
        }
        let best = cands[0].clone();
        let sig_name = signal_of(best.effect);
        let sig = localise_signals(&p, &r, &signal_series(&p, &model))
            .into_iter()
            .find(|(n, _)| n == sig_name)
            .unwrap_or((sig_name.to_string(), 0.0));
        let (new_rms, new_r) = held_rms(&p, &best.model);
        steps.push(Step {
            effect: best.effect,
            rms_before: fit::model_error(rms, floor),
            rms_after: fit::model_error(new_rms, floor),
            score: best.score,
            model: best.model.clone(),
            signal: sig,
            candidates: cands,
            held_back,
            residual_before: r.clone(),
        });
        model = best.model;
        rms = new_rms;
        r = new_r;
    }
    // Backward pass: greedy forward selection can take a look-alike first
    // (asymmetry for offset) and keep it after the real effect joined.
    // An added effect is dropped when the model refitted without it is
    // held-out within its required gain of the final one.
    let mut pruned = Vec::new();
    if !steps.is_empty() {
        let mut k = 0;
        while k < steps.len() {
            let effect = steps[k].effect;
            show(&format!("backward check: {effect}"));
            let without = remove_effect(&model, effect, &p);
            let params = fit::params_of(&without);
            let refit = fit::fit(&p, &without, &params, &FitOptions::default(), &mut |_| {}).model;
            let (w_rms, w_r) = held_rms(&p, &refit);
            // The share of the gap is a forward rule only: the refit
            // without an effect starts from the final model and often ends
            // below the step's own start, so a real effect (a ripple of 73×
            // the noise) would cost less than a quarter of that gap.
            if gain_above_floor(w_rms, rms, floor) < required_gain(effect) {
                pruned.push((
                    effect,
                    fit::model_error(w_rms, floor),
                    fit::model_error(rms, floor),
                ));
                steps.remove(k);
                model = refit;
                rms = w_rms;
                r = w_r;
            } else {
                k += 1;
            }
        }
    }
    // Swap pass: an effect taken while another was still missing may be
    // the look-alike of a runner-up of its round (nonlinear_viscous for
    // viscous beside drift, asymmetry for offset). With the others in
    // place, each added effect is replaced by the runner-ups of its round
    // (the two next best) when one gives a lower held-out BIC. So too for
    // a single look-alike, and after a restarted Stribeck shape: `offset`
    // and `asymmetry` tie exactly on a base without a dip and differ once
    // it is back, and a step that brought the dip back with one of them
    // fitted the other from the old base.
    let mut swapped = Vec::new();
    if steps.len() > 1 || reshaped || steps.iter().any(|s| look_alike(s.effect).is_some()) {
        for step in steps.iter_mut() {
            let effect = step.effect;
            let mut runner_ups: Vec<&Candidate> = step
                .candidates
                .iter()
                .skip(1)
                .chain(&step.held_back)
                .collect();
            runner_ups.sort_by(|a, b| a.score.total_cmp(&b.score));
            let alts: Vec<Effect> = runner_ups
                .iter()
                .take(2)
                .map(|c| c.effect)
                .filter(|&c| !fit::has_effect(&model, c))
                .collect();
            if alts.is_empty() {
                continue;
            }
            show(&format!("swap check: {effect}"));
            let without = remove_effect(&model, effect, &p);
            let params = fit::params_of(&without);
            let base = fit::fit(&p, &without, &params, &FitOptions::default(), &mut |_| {}).model;
            let base_r = p.residual(&base);
            let bic_cur = bic(&p, rms, fit::params_of(&model).len());
            let mut best: Option<(f64, Effect, Model)> = None;
            for &alt in &alts {
                let starts = candidate_starts(&p, &base, alt, &base_r);
                if starts.is_empty() {
                    continue;
                }
                let sound =
                    |m: &Model| degenerate(&p, m, alt).is_none() && !dip_run_to_bound(&base, m);
                let fitted = fit_multistart(&p, &starts, &sound, &mut |_| {});
                if !fit::has_effect(&fitted, alt) || !sound(&fitted) {
                    continue;
                }
                let a_rms = held_rms(&p, &fitted).0;
                let b = bic(&p, a_rms, fit::params_of(&fitted).len());
                if b < bic_cur && best.as_ref().is_none_or(|(bb, _, _)| b < *bb) {
                    best = Some((b, alt, fitted));
                }
            }
            if let Some((_, alt, m)) = best {
                let (new_rms, new_r) = held_rms(&p, &m);
                swapped.push((
                    effect,
                    alt,
                    fit::model_error(rms, floor),
                    fit::model_error(new_rms, floor),
                ));
                step.effect = alt;
                step.model = m.clone();
                model = m;
                rms = new_rms;
                r = new_r;
            }
        }
    }
    let (simpler, more) = simplify(&p, model.clone(), true, &mut show);
    if !more.is_empty() {
        model = simpler;
        (rms, r) = held_rms(&p, &model);
        dropped.extend(more);
        // Without a dip `offset` and `asymmetry` are one shift (`F0` and
        // `a·Fc`): only their sum is identified. The one named later goes.
        let both = [Effect::Offset, Effect::Asymmetry].map(|e| fit::has_effect(&model, e));
        if both == [true, true] && !fit::has_effect(&model, Effect::Stribeck) {
            if let Some(k) = steps.iter().rposition(|s| look_alike(s.effect).is_some()) {
                let effect = steps.remove(k).effect;
                let without = remove_effect(&model, effect, &p);
                let params = fit::params_of(&without);
                let refit =
                    fit::fit(&p, &without, &params, &FitOptions::default(), &mut |_| {}).model;
                let (w_rms, w_r) = held_rms(&p, &refit);
                pruned.push((
                    effect,
                    fit::model_error(w_rms, floor),
                    fit::model_error(rms, floor),
                ));
                (model, rms, r) = (refit, w_rms, w_r);
            }
        }
    }
    let model = tidy(&p, model);
    progress.finish();
    let still = p.valid().filter(|&i| p.still[i]).count();
    Report {
        pruned,
        swapped,
        n: p.len(),
        half_width: p.kf,
        velocity_half_width: p.k,
        dt: p.dt,
        resolution: p.resolution,
        given,
        start: start_model,
        rms_before: fit::model_error(raw_before, floor),
        rms_after: fit::model_error(rms, floor),
        raw_before,
        raw_after: rms,
        floor,
        sigma0: p.sigma0,
        still: (still, p.valid().len()),
        dropped,
        steps,
        last_round,
        regions,
        regimes: regimes_before,
        signals,
        signal_series: signal_series(&p, &model),
        model,
        residual_after: r,
        residual_before,
        t: p.t.clone(),
    }
}

/// The model as a JSON object with the MODEL.md §7 names.
pub fn model_json(m: &Model) -> serde_json::Value {
    let mut o = serde_json::json!({
        "mass": m.mass, "fc": m.fc, "fs": m.fs, "v_stribeck": m.v_stribeck,
        "delta": m.delta, "sigma": m.sigma, "z_max": m.z_max, "epsilon": m.epsilon,
    });
    let e = effect_params_all(m);
    if !e.is_empty() {
        o["effects"] = serde_json::Value::Object(e);
    }
    o
}

/// The effects of `m` with a table under `[effects]` (MODEL.md §7; the
/// others are keys of the model itself), by name.
fn effect_params_all(m: &Model) -> serde_json::Map<String, serde_json::Value> {
    let mut map = serde_json::Map::new();
    for effect in Effect::ALL {
        let top_level = matches!(
            effect,
            Effect::Viscous | Effect::Stribeck | Effect::Presliding
        );
        if !top_level && fit::has_effect(m, effect) {
            map.insert(effect.name().into(), effect_params(m, effect));
        }
    }
    map
}

/// The fitted parameters of one effect (MODEL.md §7 names).
pub fn effect_params(m: &Model, effect: Effect) -> serde_json::Value {
    let e = &m.effects;
    use serde_json::json;
    match effect {
        Effect::Viscous => json!({"sigma": m.sigma}),
        Effect::Stribeck => json!({"fs": m.fs, "v_stribeck": m.v_stribeck, "delta": m.delta}),
        Effect::Presliding => json!({"z_max": m.z_max}),
        Effect::Offset => json!({"f0": e.offset.map(|o| o.f0)}),
        Effect::Asymmetry => json!({"a": e.asymmetry.map(|a| a.a)}),
        Effect::PositionRipple => e.position_ripple.map_or(
            json!({}),
            |r| json!({"amplitude": r.amplitude, "wavelength": r.wavelength, "phase": r.phase}),
        ),
        Effect::DwellStiction => e.dwell_stiction.map_or(
            json!({}),
            |d| json!({"delta_fs": d.delta_fs, "gamma": d.gamma, "v_rest": d.v_rest}),
        ),
        Effect::FrictionalLag => json!({"tau_l": e.frictional_lag.map(|l| l.tau_l)}),
        Effect::Drift => json!({"beta": e.drift.map(|d| d.beta)}),
        Effect::NonlinearViscous => e
            .nonlinear_viscous
            .map_or(json!({}), |nv| json!({"sigma_n": nv.sigma_n, "n": nv.n})),
    }
}

/// The JSON report (keys in lab/README.md).
pub fn report_json(rep: &Report) -> String {
    use serde_json::json;
    let steps: Vec<_> = rep
        .steps
        .iter()
        .map(|s| {
            json!({
                "effect": s.effect.name(),
                "params": effect_params(&s.model, s.effect),
                "rms_before": s.rms_before,
                "rms_after": s.rms_after,
                "score": s.score,
                "signal": s.signal.0,
                "signal_explained": s.signal.1,
                "candidates": s.candidates.iter().map(|c| json!({"effect": c.effect.name(), "rms": c.rms, "score": c.score})).collect::<Vec<_>>(),
                "tied_with": tied_look_alike(s, rep.floor).map(|(e, _, _)| e.name()),
            })
        })
        .collect();
    let v = json!({
        "effects_added": rep.steps.iter().map(|s| s.effect.name()).collect::<Vec<_>>(),
        "metric": METRIC,
        "rms_before": rep.rms_before,
        "rms_after": rep.rms_after,
        "rms_given": rep.given,
        "rms_raw_before": rep.raw_before,
        "rms_raw_after": rep.raw_after,
        "floor": rep.floor,
        "noise_std": rep.sigma0,
        "floor_explains": if rep.raw_after > 0.0 { (rep.floor / rep.raw_after).powi(2).min(1.0) } else { 1.0 },
        "still_samples": rep.still.0,
        "valid_samples": rep.still.1,
        "dropped": rep.dropped.iter().map(|(n, why)| json!({"part": n.name(), "reason": why})).collect::<Vec<_>>(),
        "regions": rep.regions.iter().map(|r| json!({"regime": r.regime, "t_start": r.t_start, "t_end": r.t_end, "rms": r.rms})).collect::<Vec<_>>(),
        "regimes": rep.regimes.iter().map(|r| json!({"regime": r.regime, "n": r.n, "rms": r.rms})).collect::<Vec<_>>(),
        "signals": rep.signals.iter().map(|(n, f)| json!({"signal": n, "explained": f})).collect::<Vec<_>>(),
        "steps": steps,
        "swapped": rep.swapped.iter().map(|(a, b, before, after)| json!({"effect": a.name(), "replaced_by": b.name(), "rms_before": before, "rms_after": after})).collect::<Vec<_>>(),
        "pruned": rep.pruned.iter().map(|(n, without, with)| json!({"effect": n.name(), "rms_without": without, "rms_with": with})).collect::<Vec<_>>(),
        "rejected": rep.last_round.iter().map(|c| json!({"effect": c.effect.name(), "rms": c.rms, "score": c.score})).collect::<Vec<_>>(),
        "accept_gain": ACCEPT_GAIN,
        "min_gap_share": MIN_GAP_SHARE,
        "start_model": model_json(&rep.start),
        "model": model_json(&rep.model),
        "samples": rep.n,
        "window": rep.half_width,
        "velocity_window": rep.velocity_half_width,
        "dt": rep.dt,
        "resolution": rep.resolution,
    });
    let mut s = serde_json::to_string_pretty(&v).unwrap_or_else(|_| "{}".into());
    s.push('\n');
    s
}

fn pct(before: f64, after: f64) -> String {
    format!("{:.0} %", 100.0 * (before - after) / before)
}

/// The terminal text.
pub fn report_text(rep: &Report, source: &str) -> String {
    use crate::format::short;
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{source}: {} samples, dt = {} s, position resolution {} m, window ±{} samples",
        rep.n,
        short(rep.dt, 4),
        short(rep.resolution, 3),
        rep.half_width
    );
    let _ = writeln!(s, "residual: force along the measured motion (MODEL.md §8: compared locally), held-out time blocks 2, 5, 8 of 10");
    let _ = writeln!(
        s,
        "measurement floor: {} N of the held-out rms is force noise (σ0 = {} N) and encoder resolution; {} of {} samples are still (friction = measured force, not scored); figures below are model error above that floor",
        short(rep.floor, 3),
        short(rep.sigma0, 3),
        rep.still.0,
        rep.still.1
    );
    for (part, why) in &rep.dropped {
        let _ = writeln!(s, "not identifiable here, dropped: `{part}` ({why})");
    }
    if let Some(g) = rep.given {
        let _ = writeln!(
            s,
            "given model: held-out model error {} N as given, {} N refitted",
            short(g, 4),
            short(rep.rms_before, 4)
        );
    } else {
        let _ = writeln!(
            s,
            "start: base model (Coulomb + Stribeck + presliding) identified from the data, held-out model error {} N",
            short(rep.rms_before, 4)
        );
    }
    if let Some(top) = rep.regimes.first() {
        let _ = writeln!(
            s,
            "largest disagreement: {} (rms {} N over {} samples)",
            top.regime,
            short(top.rms, 3),
            top.n
        );
    }
    if let Some(r) = rep.regions.first() {
        let _ = writeln!(
            s,
            "worst window: {} at t = {}-{} s (rms {} N)",
            r.regime,
            short(r.t_start, 5),
            short(r.t_end, 5),
            short(r.rms, 3)
        );
    }
    let mut sig = rep.signals.clone();
    sig.sort_by(|a, b| b.1.total_cmp(&a.1));
    let list: Vec<String> = sig
        .iter()
        .map(|(n, f)| format!("{n} {:.0} %", 100.0 * f))
        .collect();
    let _ = writeln!(s, "residual explained by: {}", list.join(", "));
    for (k, st) in rep.steps.iter().enumerate() {
        let _ = writeln!(
            s,
            "step {}: missing effect `{}` (lines up with {}, {:.0} % explained); adding it shrinks the gap from {} N to {} N ({}), ΔBIC {}",
            k + 1,
            st.effect,
            st.signal.0,
            100.0 * st.signal.1,
            short(st.rms_before, 4),
            short(st.rms_after, 4),
            pct(st.rms_before, st.rms_after),
            short(st.score, 4)
        );
        if let Some((other, mine, theirs)) = tied_look_alike(st, rep.floor) {
            let _ = writeln!(
                s,
                "        `{other}` fits as well (model error {} vs {} N): this record does not tell them apart (they differ only in the Stribeck dip and at break-away)",
                short(theirs, 4),
                short(mine, 4)
            );
        }
        let others: Vec<String> = st
            .candidates
            .iter()
            .skip(1)
            .take(3)
            .map(|c| format!("{} {} N", c.effect, short(c.rms, 3)))
            .collect();
        if !others.is_empty() {
            let _ = writeln!(s, "        next best: {}", others.join(", "));
        }
        let _ = writeln!(s, "        fitted: {}", effect_params(&st.model, st.effect));
    }
    if rep.steps.is_empty() {
        let _ = writeln!(s, "no effect is missing: no candidate lowers the held-out rms by {:.0} % above the floor and removes {:.0} % of the gap with a better BIC", 100.0 * ACCEPT_GAIN, 100.0 * MIN_GAP_SHARE);
    } else {
        let _ = writeln!(
            s,
            "done: no further candidate lowers the held-out rms by {:.0} % above the floor and removes {:.0} % of the gap; gap {} N -> {} N ({}); the remaining rms {} N is {:.0} % noise and resolution",
            100.0 * ACCEPT_GAIN,
            100.0 * MIN_GAP_SHARE,
            short(rep.rms_before, 4),
            short(rep.rms_after, 4),
            pct(rep.rms_before, rep.rms_after),
            short(rep.raw_after, 3),
            100.0 * (rep.floor / rep.raw_after.max(1e-300)).powi(2).min(1.0)
        );
    }
    for (a, b, before, after) in &rep.swapped {
        let _ = writeln!(
            s,
            "swap check: `{a}` replaced by `{b}` (model error {} N -> {} N, lower held-out BIC)",
            short(*before, 4),
            short(*after, 4)
        );
    }
    for (n, without, with) in &rep.pruned {
        let _ = writeln!(
            s,
            "backward check: `{n}` dropped again (held-out rms {} N without it, {} N with it)",
            short(*without, 4),
            short(*with, 4)
        );
    }
    if let Some(c) = rep.last_round.first() {
        let _ = writeln!(
            s,
            "best rejected candidate: {} (held-out rms {} N, ΔBIC {})",
            c.effect,
            short(c.rms, 4),
            short(c.score, 4)
        );
    }
    let added: Vec<&str> = rep.steps.iter().map(|s| s.effect.name()).collect();
    let _ = writeln!(s, "effects added: [{}]", added.join(", "));
    let m = &rep.model;
    let _ = writeln!(
        s,
        "model: mass {} fc {} fs {} v_stribeck {} delta {} sigma {} z_max {}{}",
        short(m.mass, 5),
        short(m.fc, 5),
        short(m.fs, 5),
        short(m.v_stribeck, 4),
        short(m.delta, 3),
        short(m.sigma, 5),
        short(m.z_max, 3),
        if effect_params_all(m).is_empty() {
            String::new()
        } else {
            format!(
                " effects {}",
                serde_json::Value::Object(effect_params_all(m))
            )
        }
    );
    s
}

/// Parameter list for `fit` output.
pub fn params_json(params: &[Param]) -> Vec<String> {
    params.iter().map(|p| format!("{p:?}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Record;
    use crate::fit::Window;

    /// A reversing motion quantised to 1 µm, for starting models only.
    fn prepared() -> Prepared {
        let t: Vec<f64> = (0..2000).map(|i| i as f64 * 1e-3).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|&t| (2e-3 * (3.0 * t).sin() / 1e-6).round() * 1e-6)
            .collect();
        let rec = Record {
            u: t.iter().map(|&t| (3.0 * t).cos()).collect(),
            t,
            x,
            v: None,
            source: "test".into(),
        };
        Prepared::with_window(
            &rec,
            Window {
                velocity: 4,
                force: 32,
            },
        )
    }

    /// A dip at the top of its range is degenerate, a candidate that runs
    /// a dip there is held back (unless the current model's was there
    /// already), and `simplify` drops it even when it helps the fit.
    #[test]
    fn a_dip_at_its_upper_bound_is_held_back_and_dropped() {
        let p = prepared();
        let mut inner = fig5_model();
        inner.v_stribeck = low_speed(&p).expect("moving samples");
        inner.delta = 2.0;
        let mut top = inner.clone();
        top.fs = (1.0 + fit::FS_EXCESS_MAX) * top.fc;
        assert!(fs_at_bound(&top) && !fs_at_bound(&inner));
        assert!(degenerate(&p, &top, Effect::Stribeck).is_some());
        assert!(dip_run_to_bound(&inner, &top));
        assert!(!dip_run_to_bound(&top, &top) && !dip_run_to_bound(&inner, &inner));
        let (simpler, dropped) = simplify(&p, top, true, &mut |_| {});
        assert!(
            dropped.iter().any(|(e, _)| *e == Effect::Stribeck),
            "{dropped:?}"
        );
        assert!(!fs_at_bound(&simpler));
    }

    /// A base whose dip ran to `Fs = Fc` has it seeded again in the
    /// candidates' starts (without it `offset` and `asymmetry` are one
    /// constant shift); a sound dip is left alone.
    #[test]
    fn a_lost_dip_is_seeded_again_in_the_candidate_starts() {
        let p = prepared();
        let r = vec![0.0; p.len()];
        let v_lo = low_speed(&p).expect("moving samples");
        let mut lost = fig5_model();
        lost.fs = lost.fc;
        lost.z_max = 20.0 * p.resolution;
        let mut sound = lost.clone();
        sound.fs = 1.5 * sound.fc;
        sound.v_stribeck = v_lo;
        assert!(dip_lost(&p, &lost) && !dip_lost(&p, &sound));
        // Every start of the look-alikes (one for `offset`, three for
        // `asymmetry`), the first of the others.
        for (effect, want) in [
            (Effect::Offset, 2),
            (Effect::Asymmetry, 6),
            (Effect::Viscous, 2),
        ] {
            let seeded = |m: &Model| {
                candidate_starts(&p, m, effect, &r)
                    .iter()
                    .filter(|c| fit::has_effect(c, Effect::Stribeck))
                    .filter(|c| c.delta == 2.0 && (c.fs / c.fc - 1.4).abs() < 1e-12)
                    .count()
            };
            assert_eq!(seeded(&lost), want, "{effect}");
            assert_eq!(seeded(&sound), 0, "{effect}");
        }
        // A dip at the bound of its range is lost too.
        let mut high = sound.clone();
        high.fs = (1.0 + fit::FS_EXCESS_MAX) * high.fc;
        assert!(degenerate(&p, &high, Effect::Stribeck).is_some());
    }
}
