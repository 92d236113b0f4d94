//! The residual stage of the workflow: a record prepared for comparing
//! models with it (MODEL.md §1, §5, §8: compare locally), the error weights
//! and the measurement floor that every figure of a record shares.
//!
//! # The residual
//!
//! From the measured positions, a quadratic Savitzky–Golay filter over
//! `2k+1` samples gives the velocity `v̂` and the acceleration `â` at each
//! sample ([`Window`]: the velocity and the force kernel have half-widths of
//! their own). The friction `F_i = F(t_i, x_i, v̂_i)` of the model (all §5
//! effects, [`breakaway_reference::Friction`]) runs along the measured
//! positions ([`Prepared::walk`]), so its memory (turning points, dwell,
//! lag) follows the real motion and nothing is integrated open-loop. The
//! plant `m·ẍ = u − F` with `u` held between samples gives exactly, per
//! sample, `m·(x_{l+1} − 2x_l + x_{l−1})/h² = (u_{l−1} + u_l)/2 − F_l` (F
//! constant over the two intervals), and the Savitzky–Golay second
//! derivative is a weighted sum of these second differences,
//! `â_i = Σ_j W_j·Δ²x_{i+j}/h²` with `Σ W_j = 1`. The residual is therefore
//! the force balance filtered by the same kernel,
//!
//! ```text
//! r_i = Σ_j W_j·(ū_{i+j} − F_{i+j}) − m·â_i,     ū_l = (u_{l−1} + u_l)/2,
//! ```
//!
//! zero for the true model up to noise, with no lag between force and
//! acceleration. Its unit is N (N·m for rotary axes).
//!
//! # What is scored, the weights and the split
//!
//! Still samples (the position within one count over the velocity window)
//! and stops carry the measured force and no weight; every other sample is
//! weighted by its speed/direction class (`|v̂|` at rest, then bins a
//! factor 3 apart, each class a total weight proportional to the square
//! root of its size) times `σ0²/var_i`, the variance a correct model's
//! residual has there from noise and encoder resolution
//! ([`Prepared::set_error_weights`]); [`Prepared::floor`] is the part of a
//! weighted RMS that a correct model shows, and [`model_error`] what lies
//! above it. The record is cut into [`BLOCKS`] consecutive blocks holding
//! equal numbers of moving (scored) samples; every [`HELD_OUT_EVERY`]th
//! block (a third of the motion, [`held_out_block`]) is held out, the rest
//! is the training set of [`crate::fit`].

use crate::reference::{decay_of_power, stribeck_decay, Friction, LagFilter, Model, SampleTerms};
use std::f64::consts::PI;
use std::sync::{Arc, Mutex};

/// Rest threshold in counts per sample: `v_rest = 0.02·q/h`, i.e. a rest
/// is where the position has stayed on its encoder count for 50 samples
/// (the 1/T velocity estimate has decayed below it); every Savitzky–Golay
/// value with a count change inside the window is at least `q/(Σj²·h)`
/// (0.045·q/h for k = 5), above it.
pub const REST_COUNT_RATE: f64 = 0.02;

/// Default half-width `k` of the Savitzky–Golay window (samples).
pub const DEFAULT_HALF_WIDTH: usize = 5;
/// Half-width of the velocity estimate [`auto_window`] chooses (samples).
/// Shorter windows blur the motion least: on the independent example
/// records the true model's residual is at the noise-and-resolution floor
/// with `k = 3, 4`, and 0.01–0.05 N above it with `k = 5` (smoothing bias
/// of `v̂`, which the floor does not contain); the quantisation of `m·â` is
/// the force kernel's business ([`Window`]).
pub const AUTO_HALF_WIDTH: usize = 4;

/// Half-widths [samples] of the two Savitzky–Golay windows of a record.
///
/// The velocity `v̂` that the friction is evaluated at, and the still rule,
/// use `velocity`; the force balance is filtered by the kernel `W` of
/// half-width `force` on both sides (`W∗(ū − F)` against `m·â`, `â` from
/// the same window), so a long force kernel adds no model bias: it only
/// low-passes what is compared. It divides the encoder quantisation of
/// `m·â` by `(K_f/k)^2.5` and the force noise by `(K_f/k)^0.5`, and keeps
/// what varies slower than the kernel (every catalogue effect at the
/// speeds of the records).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    /// Half-width of the velocity estimate `v̂` and of the still rule.
    pub velocity: usize,
    /// Half-width of the force kernel `W` and of `â`.
    pub force: usize,
}

impl Window {
    /// Both half-widths `k`.
    pub fn both(k: usize) -> Window {
        Window {
            velocity: k,
            force: k,
        }
    }
}

/// Largest force half-width [`auto_window`] chooses (samples).
pub const MAX_AUTO_HALF_WIDTH: usize = 64;

/// Least time span [s] of the force half-width [`auto_window`] chooses:
/// ±32 samples at 1 kHz. On the development records (seeds 9000–9039,
/// 9200–9229) the true model's model error fell 5–50× from ±4 to ±32
/// while that of the model without the hidden effect stayed (e.g. 0.016
/// against 0.85 N at ±32, 0.17 against 0.74 N at ±4); ±64 and ±100 went on
/// shrinking both, and a position ripple's share began to fall.
pub const FORCE_WINDOW_SPAN: f64 = 0.032;

/// Ratio of the quantisation noise of `m·â` to the filtered force noise up
/// to which [`auto_window`] keeps the force half-width; above it the
/// kernel grows (a heavy axis with a fine encoder).
pub const MAX_QUANTISATION_RATIO: f64 = 10.0;

/// The two half-widths for `rec`, from the data alone: the velocity
/// [`AUTO_HALF_WIDTH`], the force kernel [`FORCE_WINDOW_SPAN`] (in
/// samples), longer when the quantisation of `m·â` still exceeds the
/// filtered force noise [`MAX_QUANTISATION_RATIO`]-fold, at most
/// [`MAX_AUTO_HALF_WIDTH`].
///
/// A correct model's residual has two noise parts at force half-width
/// `K`: the force noise filtered by the kernel, `σ_f·‖W_K‖`, and the
/// encoder quantisation of `m·â`, `m·(q/√12)·‖c2_K‖/h²`, which falls like
/// `K^−2.5`. `m` comes from a linear least-squares fit of
/// `ū = m·â + Fc·sgn(v̂)` on the faster half of the moving samples, `σ_f`
/// from the logged force alone ([`force_noise`]). Before version 4 one
/// half-width served both, and it stayed at 4–12 because a long velocity
/// window blurs `F(v̂)`; heavy axes kept floors of 20–100× the force noise.
/// Deterministic per record, independent of any model.
pub fn auto_window(rec: &crate::data::Record) -> Window {
    let span = (FORCE_WINDOW_SPAN / rec.dt()).round();
    let floor = if span.is_finite() {
        (span as usize).clamp(AUTO_HALF_WIDTH, MAX_AUTO_HALF_WIDTH)
    } else {
        AUTO_HALF_WIDTH
    };
    Window {
        velocity: AUTO_HALF_WIDTH,
        force: quantisation_window(rec).max(floor),
    }
}

/// Mass [kg] and Coulomb level [N] by linear least squares of the force
/// balance in sliding, `ū = m·â + Fc·sgn(v̂)` (force and sign through the
/// kernel), at the samples `fast`; `None` when the system is singular.
pub fn mass_and_coulomb(p: &Prepared, fast: &[usize]) -> Option<(f64, f64)> {
    let sgn: Vec<f64> = p.v.iter().map(|v| v.signum()).collect();
    let col_a: Vec<f64> = fast.iter().map(|&i| p.a[i]).collect();
    let col_s: Vec<f64> = fast.iter().map(|&i| p.filter_at(&sgn, i)).collect();
    let b: Vec<f64> = fast.iter().map(|&i| p.filter_at(&p.u_mid, i)).collect();
    crate::linalg::lstsq(&[col_a, col_s], &b).map(|c| (c[0], c[1]))
}

/// The smallest force half-width (from [`AUTO_HALF_WIDTH`] up to
/// [`MAX_AUTO_HALF_WIDTH`]) at which the quantisation noise of `m·â` is at
/// most [`MAX_QUANTISATION_RATIO`] times the filtered force noise.
fn quantisation_window(rec: &crate::data::Record) -> usize {
    let p = Prepared::new(rec, DEFAULT_HALF_WIDTH);
    let Some(v_med) = p.median_moving_speed() else {
        return AUTO_HALF_WIDTH;
    };
    let fast: Vec<usize> = p
        .valid()
        .filter(|&i| !p.still[i] && p.v[i].abs() >= v_med)
        .collect();
    let Some((mass, fc)) = mass_and_coulomb(&p, &fast) else {
        return AUTO_HALF_WIDTH;
    };
    if !(mass.is_finite() && mass > 0.0 && fc.is_finite() && fc > 0.0) {
        return AUTO_HALF_WIDTH;
    }
    let w_norm = |k: usize| {
        let (_, c2) = sg_coefficients(k);
        norm(&force_kernel(&c2))
    };
    let sigma_f = p.force_noise;
    let q = p.resolution / 12f64.sqrt();
    let ratio = |k: usize| {
        let (_, c2) = sg_coefficients(k);
        let c2n = norm(&c2);
        mass * q * c2n / (p.dt * p.dt) / (sigma_f * w_norm(k)).max(1e-300)
    };
    (AUTO_HALF_WIDTH..=MAX_AUTO_HALF_WIDTH)
        .find(|&k| ratio(k) <= MAX_QUANTISATION_RATIO)
        .unwrap_or(MAX_AUTO_HALF_WIDTH)
}

/// Standard deviation [N] of the noise on the logged force `u`, from its
/// third differences: `Δ³u` of a command that is smooth over four samples
/// is the noise alone, with variance 20·σ² (a robust median). A digital
/// loop's command is smooth between encoder counts but steps where the
/// count `x` changes (its P and D terms act on the count), so only the
/// windows with no count change on them or on the sample before are used,
/// when the record has at least [`MIN_STABLE_WINDOWS`] of them; otherwise
/// all. On the outside generator's example records it gives 0.0076,
/// 0.0247, 0.0040 and 0.0160 N for a true 0.0076, 0.0247, 0.0039 and
/// 0.0157 N (all windows: 0.0077, 0.0249, 0.0041, 0.0159 N). On
/// development records of position loops at fine encoder resolution, all
/// windows read up to 34× the true noise, the count-stable ones 0.95–1.11×
/// (143 time records: median 1.02× and 1.01×).
pub fn force_noise(u: &[f64], x: &[f64]) -> f64 {
    let third = |i: usize| (u[i + 3] - 3.0 * u[i + 2] + 3.0 * u[i + 1] - u[i]).abs();
    let n = u.len().min(x.len());
    if n < 4 {
        return 0.0;
    }
    let moved = |j: usize| j > 0 && x[j] != x[j - 1];
    let stable: Vec<f64> = (1..n - 3)
        .filter(|&i| !(i - 1..=i + 3).any(moved))
        .map(third)
        .collect();
    let mut d = if stable.len() >= MIN_STABLE_WINDOWS {
        stable
    } else {
        (0..n - 3).map(third).collect()
    };
    let mid = d.len() / 2;
    let (_, med, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    *med / (0.6745 * 20f64.sqrt())
}

/// The `q` quantile of `v` (sorted in place; the element at
/// `round((len − 1)·q)`, NaN when empty).
pub fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// Least number of count-stable windows for [`force_noise`] to use them
/// alone.
pub const MIN_STABLE_WINDOWS: usize = 200;

/// Half-width [samples] of the stop rule ([`Prepared::mark_stops`]): the
/// position on one count over `i−2 … i+2`.
pub const STOP_HALF_WIDTH: usize = 2;

/// Number of blocks of the split (consecutive, equal counts of scored
/// samples: `Prepared::set_split`).
///
/// Version 9.4: 30 blocks, every third held out, instead of blocks 2, 5
/// and 8 of 10. A record's excitation changes over its length (amplitudes
/// and rates of a slow sinusoid, the plateaus of a staircase, the ramps'
/// rates), and three long held-out blocks held motion that the training
/// blocks had little of: on the scored draw 5700000– the fit started from
/// the generator's true model left it at 0.031 N held-out model error on
/// 5700048 (a slow sinusoid, `offset` hidden) and moved it to 0.216 N
/// (mass 7.0 → 13.1 kg, δ 0.63 → 2.40), a minimum of the training blocks
/// that the held-out ones refuted; with 30 blocks both read 0. A block is
/// still many force kernels long (a 10 000-sample motion gives blocks of
/// about 330 samples against a kernel of at most 129), so held-out samples
/// stay apart from the training ones except at the block edges.
pub const BLOCKS: usize = 30;
/// Every how many blocks one is held out (from block
/// `HELD_OUT_EVERY − 1` on: blocks 2, 5, …, 29 of 30).
pub const HELD_OUT_EVERY: usize = 3;

/// Whether block `b` (0-based, of [`BLOCKS`]) is held out.
pub const fn held_out_block(b: usize) -> bool {
    b % HELD_OUT_EVERY == HELD_OUT_EVERY - 1
}

/// Least rms scatter [counts] of the count increments around their local
/// trend that marks a burst ([`Prepared::bursts`]): quantisation alone
/// gives about 0.4 (`1/√6`, two uniform rounding errors per increment),
/// below 0.8 on the smooth motion of the unit test.
pub const BURST_COUNTS: f64 = 1.5;

/// Least scatter of the count increments, as a share of their local mean,
/// that marks a burst ([`Prepared::bursts`]).
pub const BURST_SHARE: f64 = 0.5;

/// `n` flags, set within `±h` samples of each of the `marked` samples.
fn spread(n: usize, marked: impl Iterator<Item = usize>, h: usize) -> Vec<bool> {
    let mut out = vec![false; n];
    for i in marked {
        for o in &mut out[i.saturating_sub(h)..=(i + h).min(n - 1)] {
            *o = true;
        }
    }
    out
}

/// Least length, in samples, of a stay that [`Prepared::count_period_speed`]
/// reads as a stick.
pub const STICK_MIN_STAY: usize = 3;

/// Least ratio of a stay's length to the one before it that
/// [`Prepared::count_period_speed`] reads as a stick. On the suite-like
/// records 3400086 and 3400091 of `breakaway-gen` the axis advanced a
/// count every 1 and 3–4 samples and then held one count for 3 and 13
/// samples, where the generator's dwell clock restarted.
pub const STICK_RATIO: f64 = 2.5;

/// Whether a stay of `len` samples after one of `previous` samples is a
/// stick ([`STICK_MIN_STAY`], [`STICK_RATIO`]).
fn stuck(len: usize, previous: usize) -> bool {
    len >= STICK_MIN_STAY && len as f64 >= STICK_RATIO * previous as f64
}

/// A record prepared for fitting: derivatives, kernel, weights, split.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Time [s].
    pub t: Vec<f64>,
    /// Position [m].
    pub x: Vec<f64>,
    /// `(u_{l−1} + u_l)/2` [N].
    pub u_mid: Vec<f64>,
    /// Velocity estimate [m/s].
    pub v: Vec<f64>,
    /// Acceleration estimate [m/s²] (0 outside the valid range).
    pub a: Vec<f64>,
    /// Force kernel `W_j`, `j = −kf … kf`.
    pub kernel: Vec<f64>,
    /// Half-width `k` of the velocity estimate and of the still rule.
    pub k: usize,
    /// Half-width of the force kernel and of `â` (≥ `k` when chosen by
    /// [`auto_window`]).
    pub kf: usize,
    /// Sample weight (0 outside the valid range, [`Prepared::valid`]).
    pub weight: Vec<f64>,
    /// Held-out flag per sample.
    pub held_out: Vec<bool>,
    /// Position resolution estimate [m] (smallest position step).
    pub resolution: f64,
    /// Rest threshold [m/s]: `|v̂|` below it means the position did not leave
    /// its encoder count within the window.
    pub v_rest: f64,
    /// Sampling interval [s] (median).
    pub dt: f64,
    /// Still samples: the position stays within one encoder count over the
    /// whole window `i−k … i+k` (at rest, dithering on a count boundary, or
    /// creeping by at most a count). There the force balance gives the
    /// friction itself (`F = ū − m·â`, `â ≈ 0`), while the presliding state
    /// at a quantised position is not observable; the model's memory is
    /// re-anchored at the measured force ([`Prepared::friction`]) and the
    /// sample carries no weight.
    pub still: Vec<bool>,
    /// Measured force at still samples [N]: mean of `ū` over the sample and
    /// the two before it (0 elsewhere).
    pub u_still: Vec<f64>,
    /// The speed [m/s] that the `dwell_stiction` clock compares with
    /// `v_rest` ([`Prepared::count_period_speed`]; `|v|` of a record that
    /// gives its velocity).
    rest_speed: Vec<f64>,
    /// Still by the window rule alone (position within one count over
    /// `i−k … i+k`), before [`Prepared::mark_stops`] adds the stops.
    window_still: Vec<bool>,
    /// Samples within the force kernel (`±kf`) of a **burst**: a sample
    /// whose count increments over `i−k … i+k`, less their quadratic trend,
    /// scatter by at least [`BURST_COUNTS`] counts (rms) and by at least
    /// [`BURST_SHARE`] of their mean. The axis then moves in bursts faster
    /// than the sampling (it sticks and slips within a period, as the
    /// self-excited presliding creep of MODEL.md §8 at large `Π` does), so
    /// the velocity at the sample instants is not the one the friction saw,
    /// and the kernel spreads that error over its width. With
    /// [`Prepared::unweigh_bursts`] these samples carry no weight; the
    /// model is still walked through them (not re-anchored: their force is
    /// not the friction).
    pub bursts: Vec<bool>,
    /// Whether the bursts carry no weight ([`Prepared::unweigh_bursts`]);
    /// by default they are weighed like any moving sample.
    bursts_unweighted: bool,
    /// Standard deviation of the noise on the logged force [N]
    /// ([`force_noise`] of the record's `u`).
    pub force_noise: f64,
    /// Variance of the residual of a correct model at each sample [N²]
    /// (noise and resolution, [`Prepared::set_error_weights`]); `σ0²` until
    /// then.
    pub var: Vec<f64>,
    /// [`Prepared::var`] with the slow-motion term at the range the
    /// record shows (`Prepared::slow_spread`) instead of the whole
    /// hysteresis range: what [`Prepared::floor`] expects of a correct
    /// model [N²].
    pub floor_var: Vec<f64>,
    /// Force-noise level of the residual in fast sliding [N] (0 until
    /// [`Prepared::set_error_weights`]).
    pub sigma0: f64,
    /// The per-sample terms of the last few shapes walked.
    terms: TermCache,
}

/// Least number of slow sample pairs for `Prepared::slow_spread`.
pub const MIN_SLOW_PAIRS: usize = 200;

/// The quantile of the slow pairs' differences that `Prepared::slow_spread`
/// reads (a high one: stick-slip between samples comes in bursts), and
/// the normal quantile `z` it corresponds to.
pub const SLOW_QUANTILE: f64 = 0.99;
const SLOW_Z: f64 = 2.576;

/// How many shapes [`TermCache`] keeps of each kind.
const TERM_CACHE_LEN: usize = 8;

/// The per-sample Stribeck decays (by V and δ) and `|v|^n` (by n) along
/// [`Prepared::model_velocity`] of the last shapes walked: a fit walks many
/// models of one shape (every difference column but those of V, δ and n),
/// and `pow`/`exp` were a third of a walk's time. The powers are taken as
/// `exp(p·ln|v|)` from [`Prepared::ln_speed`], which differs from
/// [`crate::reference::stribeck_decay`] and `powf` by rounding only (EMPS: the same fitted
/// model to 13 digits, 9 % less time). With `frictional_lag` the decays of
/// the lagged velocity, which depends on the record and `τ_L` alone, are
/// kept by (V, δ, τ_L), computed exactly as the reference does (the same
/// bits; EMPS 12 % less CPU time with the other changes of that commit).
/// A clone starts empty.
#[derive(Debug, Default)]
struct TermCache {
    decay: Shapes<[u64; 2]>,
    /// With `frictional_lag`: the decays of the lagged velocity, by the
    /// bits of (V, δ, τ_L) (the lag filter runs on the record alone).
    lagged_decay: Shapes<[u64; 3]>,
    speed_pow: Shapes<u64>,
    ln_speed: Mutex<Option<Arc<Vec<f64>>>>,
    /// `sin(2π·x/λ + φ)` along the positions, by the bits of (λ, φ).
    ripple_sin: Shapes<[u64; 2]>,
    /// Training-side filtered series that no parameter changes (the
    /// Jacobian columns of σ and F0, [`Prepared::fixed_column`]).
    fixed: Shapes<FixedColumn>,
}

/// The per-sample series whose training-side filter
/// [`Prepared::fixed_column`] keeps: they depend on the record alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FixedColumn {
    /// The model velocity (`∂F/∂σ`).
    Velocity,
    /// 1 where the axis moves (`∂F/∂F0`).
    Moving,
}

/// Per-sample series by the bits of their shape parameters, oldest first.
type Shapes<K> = Mutex<Vec<(K, Arc<Vec<f64>>)>>;

impl Clone for TermCache {
    fn clone(&self) -> Self {
        TermCache::default()
    }
}

impl TermCache {
    /// The entry for `key` in `cache`, made by `make` when missing (the
    /// newest last; the oldest dropped beyond [`TERM_CACHE_LEN`]).
    fn get<K: PartialEq + Copy>(
        cache: &Shapes<K>,
        key: K,
        make: impl FnOnce() -> Vec<f64>,
    ) -> Arc<Vec<f64>> {
        let lock = || cache.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, v)) = lock().iter().find(|(k, _)| *k == key) {
            return Arc::clone(v);
        }
        let made = Arc::new(make());
        let mut entries = lock();
        if entries.len() >= TERM_CACHE_LEN {
            entries.remove(0);
        }
        entries.push((key, Arc::clone(&made)));
        made
    }

    fn clear(&mut self) {
        *self = TermCache::default();
    }
}

/// Quadratic Savitzky–Golay coefficients of the first and second derivative
/// (per sample², unscaled by `h`), `j = −k … k`.
fn sg_coefficients(k: usize) -> (Vec<f64>, Vec<f64>) {
    let kf = k as f64;
    let js: Vec<f64> = (0..=2 * k).map(|i| i as f64 - kf).collect();
    let s2: f64 = js.iter().map(|j| j * j).sum();
    let mu2 = kf * (kf + 1.0) / 3.0;
    let d: f64 = js.iter().map(|j| (j * j - mu2).powi(2)).sum();
    let c1 = js.iter().map(|j| j / s2).collect();
    let c2 = js.iter().map(|j| 2.0 * (j * j - mu2) / d).collect();
    (c1, c2)
}

/// The Euclidean norm of a kernel.
fn norm(w: &[f64]) -> f64 {
    w.iter().map(|w| w * w).sum::<f64>().sqrt()
}

/// The force kernel `W` with `Δ²W = c2` (summation by parts twice).
fn force_kernel(c2: &[f64]) -> Vec<f64> {
    // c2_j = W_{j−1} − 2W_j + W_{j+1} with W zero outside (−k, k).
    let n = c2.len();
    let mut w = vec![0.0; n + 2]; // w[i+1] = W at index i of c2; w[0] = W_{−k−1}
    for i in 0..n {
        // c2[i] = w[i] − 2 w[i+1] + w[i+2]
        let next = c2[i] - w[i] + 2.0 * w[i + 1];
        if i + 2 < n + 2 {
            w[i + 2] = next;
        }
    }
    // W_j for j = −k … k is w[1 ..= n]; shift so that the kernel applies to
    // the sample l = i + j with Δ²x_l centred at l.
    w[1..=n].to_vec()
}

impl Prepared {
    /// Prepares `rec` with half-width `k` (≥ 2) for both windows.
    pub fn new(rec: &crate::data::Record, k: usize) -> Prepared {
        Self::with_window(rec, Window::both(k))
    }

    /// Prepares `rec` with the half-widths of `window` (each ≥ 2).
    #[allow(clippy::needless_range_loop)] // several arrays indexed together
    pub fn with_window(rec: &crate::data::Record, window: Window) -> Prepared {
        let Window {
            velocity: k,
            force: kf,
        } = window;
        let n = rec.len();
        let dt = rec.dt();
        let xs = Self::despiked(&rec.x);
        let xs = &xs;
        let (c1, _) = sg_coefficients(k);
        let (_, c2) = sg_coefficients(kf);
        let kernel = force_kernel(&c2);
        let mut v = vec![0.0; n];
        let mut a = vec![0.0; n];
        for i in k..n.saturating_sub(k) {
            let sv: f64 = c1.iter().enumerate().map(|(j, p)| p * xs[i + j - k]).sum();
            v[i] = sv / dt;
        }
        for i in kf..n.saturating_sub(kf) {
            let sa: f64 = c2.iter().enumerate().map(|(j, q)| q * xs[i + j - kf]).sum();
            a[i] = sa / (dt * dt);
        }
        // Edges: one-sided differences for the velocity (the friction memory
        // runs there too); no residual is formed there.
        for i in (0..k.min(n)).chain(n.saturating_sub(k)..n) {
            let (i0, i1) = if i + 1 < n { (i, i + 1) } else { (i - 1, i) };
            v[i] = (xs[i1] - xs[i0]) / (rec.t[i1] - rec.t[i0]);
        }
        let mut u_mid = rec.u.clone();
        for i in 1..n {
            u_mid[i] = 0.5 * (rec.u[i - 1] + rec.u[i]);
        }
        let (q, n_rest) = Self::resolution_of(xs);
        // Where the position has not changed over the whole window, the
        // velocity is the encoder's "1/T" estimate: one count over the time
        // since the last count change, with that change's sign. It decays
        // like 1/T during a rest, so `|v| <= v_rest` marks a rest once the
        // position has stayed on its count for q/(v_rest·h) samples.
        let mut last_change: Option<(usize, f64)> = None;
        for i in 0..n {
            if i > 0 && xs[i] != xs[i - 1] {
                last_change = Some((i, (xs[i] - xs[i - 1]).signum()));
            }
            let lo = i.saturating_sub(k);
            let hi = (i + k).min(n - 1);
            if i >= k && i + k < n && xs[lo..=hi].iter().all(|&x| x == xs[i]) {
                v[i] = match last_change {
                    Some((j, sgn)) => sgn * q / (rec.t[i] - rec.t[j]),
                    None => q / (rec.t[i] - rec.t[0] + dt),
                };
            }
        }
        let _ = n_rest;
        let rest_speed = match &rec.v {
            Some(mv) => {
                v.clone_from(mv);
                mv.iter().map(|v| v.abs()).collect()
            }
            None => Self::count_period_speed(xs, &rec.t, q),
        };
        let resolution = q;
        let v_rest = REST_COUNT_RATE * q / dt;
        let mut still = vec![false; n];
        let mut u_still = vec![0.0; n];
        for i in k..n.saturating_sub(k) {
            // The position stays within one encoder count on i−k … i+k:
            // at rest, or dithering on a count boundary, or creeping by at
            // most one count per window (|v| < q/(2k·h), |a| ≈ 0).
            let (lo, hi) = xs[i - k..=i + k]
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            if hi - lo <= 1.5 * q {
                still[i] = true;
                let span = &u_mid[i.saturating_sub(2)..=i];
                u_still[i] = span.iter().sum::<f64>() / span.len() as f64;
            }
        }
        let bursts = Self::bursts_of(xs, q, k, kf);
        let mut p = Prepared {
            bursts,
            bursts_unweighted: false,
            t: rec.t.clone(),
            x: xs.clone(),
            u_mid,
            v,
            a,
            kernel,
            k,
            kf,
            weight: vec![0.0; n],
            held_out: vec![false; n],
            resolution,
            v_rest,
            dt,
            window_still: still.clone(),
            still,
            u_still,
            rest_speed,
            var: vec![0.0; n],
            floor_var: vec![0.0; n],
            sigma0: 0.0,
            force_noise: force_noise(&rec.u, xs),
            terms: TermCache::default(),
        };
        p.set_split();
        p.set_weights();
        p
    }

    /// [`Prepared::bursts`] of positions `xs` with resolution `q` [m]:
    /// the increment window is `±k`, the spread `±kf`. The trend taken out
    /// of the increments is quadratic (a smooth jerk, as at a break-away,
    /// is not a burst).
    fn bursts_of(xs: &[f64], q: f64, k: usize, kf: usize) -> Vec<bool> {
        let n = xs.len();
        if q <= 0.0 || n < 2 * k + 2 {
            return vec![false; n];
        }
        // Count increments into each sample.
        let inc: Vec<f64> = (0..n)
            .map(|i| if i == 0 { 0.0 } else { (xs[i] - xs[i - 1]) / q })
            .collect();
        // Moments of j = −k … k for the least-squares quadratic.
        let js: Vec<f64> = (0..=2 * k).map(|j| j as f64 - k as f64).collect();
        let s0 = js.len() as f64;
        let s2: f64 = js.iter().map(|j| j * j).sum();
        let s4: f64 = js.iter().map(|j| j.powi(4)).sum();
        let det = s0 * s4 - s2 * s2;
        let mut burst = vec![false; n];
        for i in k + 1..n - k {
            let span = &inc[i - k..=i + k];
            let (mut y0, mut y1, mut y2, mut yy) = (0.0, 0.0, 0.0, 0.0);
            for (y, j) in span.iter().zip(&js) {
                y0 += y;
                y1 += y * j;
                y2 += y * j * j;
                yy += y * y;
            }
            let c1 = y1 / s2;
            let c0 = (s4 * y0 - s2 * y2) / det;
            let c2 = (s0 * y2 - s2 * y0) / det;
            let rms = ((yy - c0 * y0 - c1 * y1 - c2 * y2).max(0.0) / s0).sqrt();
            burst[i] = rms >= BURST_COUNTS && rms >= BURST_SHARE * (y0 / s0).abs();
        }
        spread(n, (0..n).filter(|&i| burst[i]), kf)
    }

    /// The positions with single-sample encoder glitches removed: a sample
    /// one count away from two equal neighbours (`x[i−1] = x[i+1] ≠ x[i]`)
    /// takes their value. A real motion cannot leave a count and come back
    /// within one sample at the speeds where friction is modelled, while
    /// encoder jitter (an edge flickering on a count boundary) does exactly
    /// that and would put a spike of `2q/h²` into the acceleration. The
    /// record itself is not changed.
    fn despiked(x: &[f64]) -> Vec<f64> {
        let (q, _) = Self::resolution_of(x);
        let mut out = x.to_vec();
        for i in 1..x.len().saturating_sub(1) {
            if x[i - 1] == x[i + 1] && x[i] != x[i - 1] && (x[i] - x[i - 1]).abs() <= 1.5 * q {
                out[i] = x[i - 1];
            }
        }
        out
    }

    /// Position resolution: the smallest position step of the record
    /// (steps below 1e-12 of the range are rounding, not counts).
    fn resolution_of(x: &[f64]) -> (f64, usize) {
        let range = x.iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x))
            - x.iter().fold(f64::INFINITY, |m, &x| m.min(x));
        let floor = 1e-12 * range.max(1e-300);
        let q = x
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .filter(|d| *d > floor)
            .fold(f64::INFINITY, f64::min);
        let zero = x.windows(2).filter(|w| w[1] == w[0]).count();
        (if q.is_finite() { q } else { range.max(1e-9) }, zero)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Indices with a residual (`K … n−K`, `K` the larger half-width).
    pub fn valid(&self) -> std::ops::Range<usize> {
        let k = self.k.max(self.kf);
        k..self.len().saturating_sub(k)
    }

    /// The range of the measured positions over the valid samples [m].
    pub fn travel(&self) -> f64 {
        let (lo, hi) = self
            .valid()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), i| {
                (a.min(self.x[i]), b.max(self.x[i]))
            });
        (hi - lo).max(0.0)
    }

    /// Median `|v̂|` [m/s] of the valid samples that move (not still), or
    /// `None` when none does.
    pub fn median_moving_speed(&self) -> Option<f64> {
        let mut speeds: Vec<f64> = self
            .valid()
            .filter(|&i| !self.still[i])
            .map(|i| self.v[i].abs())
            .collect();
        speeds.sort_by(f64::total_cmp);
        speeds.get(speeds.len() / 2).copied()
    }

    /// Cuts the record into [`BLOCKS`] consecutive blocks that hold equal
    /// numbers of scored samples (valid and not window-still) and holds out
    /// every [`HELD_OUT_EVERY`]th ([`held_out_block`]). Equal time blocks
    /// would let a record that rests most of the time (a sinusoidal force
    /// mostly below break-away, a servo that holds for seconds) put none
    /// of its motion into the held-out blocks, and every figure would then
    /// compare nothing. With fewer scored samples than blocks the cut falls
    /// back to equal time.
    fn set_split(&mut self) {
        let n = self.len();
        let valid = self.valid();
        let is_scored: Vec<bool> = (0..n)
            .map(|i| valid.contains(&i) && !self.still[i])
            .collect();
        let scored = is_scored.iter().filter(|s| **s).count();
        let (t0, t1) = (self.t[0], self.t[n - 1]);
        let mut before = 0;
        for (i, counts) in is_scored.into_iter().enumerate() {
            let b = if scored >= BLOCKS {
                before * BLOCKS / scored
            } else {
                (((self.t[i] - t0) / (t1 - t0)) * BLOCKS as f64) as usize
            };
            self.held_out[i] = held_out_block(b.min(BLOCKS - 1));
            before += usize::from(counts);
        }
    }

    /// Speed/direction class of a sample (for the weights).
    fn class(&self, i: usize) -> usize {
        let s = self.v[i].abs();
        if s <= self.v_rest {
            return 0;
        }
        let b = ((s / self.v_rest).ln() / 3f64.ln())
            .floor()
            .clamp(0.0, 30.0) as usize;
        1 + 2 * b + usize::from(self.v[i] < 0.0)
    }

    /// Takes the weight off the [`Prepared::bursts`] (class weights now;
    /// the error weights, set later, keep it off).
    pub fn unweigh_bursts(&mut self) {
        self.bursts_unweighted = true;
        self.set_weights();
    }

    /// Whether the bursts carry no weight ([`Prepared::unweigh_bursts`]).
    pub fn bursts_unweighted(&self) -> bool {
        self.bursts_unweighted
    }

    /// Moving samples (valid, not still) within the kernel of a burst.
    pub fn burst_count(&self) -> usize {
        self.valid()
            .filter(|&i| self.bursts[i] && !self.still[i])
            .count()
    }

    fn set_weights(&mut self) {
        let unscored = |p: &Self, i: usize| p.still[i] || (p.bursts_unweighted && p.bursts[i]);
        let mut count = [0usize; 64];
        for i in self.valid().filter(|&i| !unscored(self, i)) {
            count[self.class(i)] += 1;
        }
        let mut total = 0.0;
        for i in self.valid() {
            self.weight[i] = if !unscored(self, i) {
                1.0 / (count[self.class(i)] as f64).sqrt()
            } else {
                0.0
            };
            total += self.weight[i];
        }
        let nv = self.valid().filter(|&i| !unscored(self, i)).count() as f64;
        if total > 0.0 {
            for w in &mut self.weight {
                *w *= nv / total;
            }
        }
    }

    /// Error-in-variables weights for model `m` with residual `r` (of `m`).
    /// The residual of a correct model at moving sample `i` has variance
    ///
    /// ```text
    /// var_i = σ0² + (q²/12)·(Σ_j W_j·|∂F/∂x|_{i+j})² + σ_v²·(Σ_j W_j·|∂F/∂v|_{i+j})²
    ///             + (1/12)·(Σ_j W_j·ΔF_{i+j})² + (1/12)·(Σ_j W_j·U_{i+j})²
    /// ```
    ///
    /// * `σ0` [N]: the force noise through the kernel, the lower of two
    ///   upper bounds: differences of the residual `2K+1` samples apart in
    ///   fast sliding (a robust median; a missing effect that varies along
    ///   the motion inflates it, which on a heavy axis with a position
    ///   ripple made it 250× the noise through the kernel and hid every effect), and
    ///   `σ_f·‖W‖` with `σ_f` from the logged force ([`force_noise`]);
    /// * `q` [m] the encoder count, propagated through the presliding
    ///   stiffness `∂H/∂x = (d·S − H_r)·(−ln w)/z_max` (huge right after a
    ///   turning point);
    /// * `σ_v = q·‖c1‖/(√12·h)` [m/s], the quantisation error of the
    ///   Savitzky–Golay velocity, propagated through the slope of the
    ///   Stribeck curve `g(w)·|S'(v)|`;
    /// * `ΔF = (|∂F/∂x|·|v̂| + |∂F/∂v|·|â|)·h` [N], how far the friction
    ///   moves within one sample period `h` (version 6.4): the residual
    ///   takes the force at the sample instants while the motion
    ///   integrates it over the period, so a presliding branch crossed in
    ///   a fraction of a period is known at its samples only to about that
    ///   change (on three effect-free development records of the MODEL.md
    ///   plant where `frictional_lag` was named falsely, the generator's
    ///   own model had 0.06–0.23 N of model error without this term,
    ///   0.008–0.13 N with it);
    /// * `U = 2·max(Fs, Fc)` [N] at moving samples slower than one count per
    ///   sample, 0 elsewhere (version 7.0): there the axis may stick, slip
    ///   and reverse by less than a count between two samples, unseen, and
    ///   the presliding memory is anywhere in its range (on a servo record
    ///   of the development draws with a position ripple, the generator's
    ///   plant reversed in bursts of about 1 ms while the counts fell
    ///   steadily; its own model's error was 0.21 N without this term,
    ///   0.040 N with it). The weights keep the whole range; the floor
    ///   (version 7.4, [`Prepared::floor_var`]) takes `U` only as far as
    ///   the start model's residual shows it at slow samples
    ///   (`Prepared::slow_spread`): on slow sinusoids the whole range
    ///   made the floor 30× what the generator's own model left (0.48 N
    ///   against 0.016 N), so no effect there could be named.
    ///
    /// Each sample's class weight is multiplied by `σ0²/var_i` (≤ 1); the
    /// variances are kept ([`Prepared::var`], and [`Prepared::floor_var`]
    /// for [`Prepared::floor`]). Called once per record
    /// (from the start model), so every figure compared afterwards uses the
    /// same weights. Returns `σ0`.
    pub fn set_error_weights(&mut self, m: &Model, r: &[f64]) -> f64 {
        self.mark_stops(m);
        let lag = 2 * self.kf + 1;
        let q2 = self.resolution * self.resolution / 12.0;
        // Quantisation error of `m·â`: present wherever a second difference
        // of the counts falls inside the window (an exactly constant count
        // rate has none).
        let c2_norm = self.c2_norm();
        let var_acc = m.mass * m.mass * q2 * (c2_norm / (self.dt * self.dt)).powi(2);
        let n = self.len();
        let curved = spread(
            n,
            (1..n.saturating_sub(1))
                .filter(|&i| self.x[i + 1] - 2.0 * self.x[i] + self.x[i - 1] != 0.0),
            self.kf + 1,
        );
        let fast = self.median_moving_speed().unwrap_or(0.0);
        let pairs = |straight: bool| -> Vec<f64> {
            let mut d: Vec<f64> = self
                .valid()
                .filter(|&i| i + lag < self.valid().end)
                .filter(|&i| self.v[i].abs() >= fast && self.v[i + lag].abs() >= fast)
                .filter(|&i| !self.still[i] && !self.still[i + lag])
                .filter(|&i| !straight || !(curved[i] || curved[i + lag]))
                .map(|i| (r[i] - r[i + lag]).abs())
                .collect();
            d.sort_by(f64::total_cmp);
            d
        };
        let robust = |d: &[f64]| {
            d.get(d.len() / 2)
                .map(|med| med / (0.6745 * std::f64::consts::SQRT_2))
        };
        // The force noise: from windows without count curvature when the
        // record has enough of them, else from all fast windows less the
        // quantisation part.
        let straight = pairs(true);
        // The force noise seen through the kernel, from the logged force
        // alone: an upper bound too (Δ³u also holds the command's own fast
        // variations), but one that no missing effect inflates. The lower
        // of the two bounds is taken.
        let from_data = self.force_noise * self.kernel_norm();
        let sigma0 = match robust(&straight) {
            Some(s) if straight.len() >= 200 && s > 0.0 => s,
            _ => match robust(&pairs(false)) {
                Some(s) if s > 0.0 => (s * s - var_acc).max(0.01 * s * s).sqrt(),
                _ => 1e-3 * m.fc,
            },
        };
        let sigma0 = if from_data > 0.0 {
            sigma0.min(from_data)
        } else {
            sigma0
        };
        let (sx, sv) = self.sensitivities(m);
        // How far the friction moves within one sample period,
        // `|∂F/∂x|·|v̂|·h + |∂F/∂v|·|â|·h` [N]: the residual compares
        // the force at the sample instants with the motion, which
        // integrates it over the period, so a friction that changes by
        // more than the noise within a period (a presliding branch crossed
        // in a fraction of a period, a steep Stribeck slope under a fast
        // acceleration) is known at the sample only to about that change.
        let within: Vec<f64> = (0..n)
            .map(|i| (sx[i] * self.v[i].abs() + sv[i] * self.a[i].abs()) * self.dt)
            .collect();
        // Where the axis moves by less than a count per sample and is not
        // still, it may stick and slip, and reverse, between two samples
        // by less than a count (a limit cycle faster than the sampling,
        // which the counts cannot show): the presliding memory, and with
        // it the dry friction, is then anywhere between −S and S. Such a
        // sample's friction is known only to that range, `2·max(Fs, Fc)`
        // [N] (`2·Fs` for a model with Fs ≥ Fc).
        let range = 2.0 * m.fs.max(m.fc);
        let slow = |i: usize| self.v[i].abs() * self.dt < self.resolution && !self.still[i];
        let hidden_reversal: Vec<f64> = (0..n).map(|i| if slow(i) { range } else { 0.0 }).collect();
        // How much of that range the record shows (a fraction), for the
        // floor only: the weights keep the whole range.
        let shown = range.min(self.slow_spread(r, &slow).unwrap_or(range)) / range;
        // Neither term below can exceed the friction's whole range.
        let cap = range * range;
        let c1_norm = 1.0 / ((self.k * (self.k + 1) * (2 * self.k + 1)) as f64 / 3.0).sqrt();
        let sigma_v2 = q2 * (c1_norm / self.dt).powi(2);
        self.set_weights();
        self.sigma0 = sigma0;
        for i in self.valid() {
            let a = self.filter_at(&sx, i).abs();
            let b = self.filter_at(&sv, i).abs();
            let c = self.filter_at(&within, i);
            let d = self.filter_at(&hidden_reversal, i);
            let acc = if curved[i] { var_acc } else { 0.0 };
            let known = sigma0 * sigma0
                + acc
                + (q2 * a * a).min(cap)
                + (sigma_v2 * b * b).min(cap)
                + (c * c / 12.0).min(cap);
            let hidden = (d * d / 12.0).min(cap);
            self.var[i] = known + hidden;
            self.floor_var[i] = known + hidden * shown * shown;
            self.weight[i] *= sigma0 * sigma0 / self.var[i];
        }
        sigma0
    }

    /// The hidden-reversal range [N] that the residual `r` of the start
    /// model shows at the slow moving samples (`slow`): `√12·σ`, σ from
    /// the [`SLOW_QUANTILE`] of `|r_i − r_{i+2K+1}|` over pairs of slow
    /// samples (`z·√2·σ` for Gaussian differences), the same kernel span
    /// apart as the noise pairs of [`Prepared::set_error_weights`], so
    /// that a disagreement that varies slower than the kernel (a missing
    /// effect) cancels and stick-slip faster than the sampling does not;
    /// `None` with fewer than [`MIN_SLOW_PAIRS`] pairs.
    fn slow_spread(&self, r: &[f64], slow: &dyn Fn(usize) -> bool) -> Option<f64> {
        let lag = 2 * self.kf + 1;
        let end = self.valid().end;
        let mut d: Vec<f64> = self
            .valid()
            .filter(|&i| i + lag < end && slow(i) && slow(i + lag))
            .map(|i| (r[i] - r[i + lag]).abs())
            .collect();
        if d.len() < MIN_SLOW_PAIRS {
            return None;
        }
        Some(12f64.sqrt() * quantile(&mut d, SLOW_QUANTILE) / (SLOW_Z * std::f64::consts::SQRT_2))
    }

    /// Adds the **stops** of the motion to the still samples: a sample
    /// whose position stays on one count over `i−2 … i+2`
    /// ([`STOP_HALF_WIDTH`]) while model `m`, run along the counts, is in
    /// gross sliding (w = 1). The axis has come to rest on that count
    /// (usually after a reversal smaller than a count, which the counts do
    /// not show), so its friction is the holding force; the model, which
    /// sees no reversal, would go on with `±S(v̂)` at the velocity the
    /// window still reports, a disagreement of up to `Fs + |u|` that no
    /// friction effect explains. Such samples are re-anchored and not
    /// scored, like the window-still ones. Inside presliding the rule
    /// does not apply: there the branch itself is the slow motion, and
    /// re-anchoring would restart it. Called once per record from the start
    /// model (from [`Prepared::set_error_weights`]), so every model compared
    /// on the record sees the same still samples.
    pub fn mark_stops(&mut self, m: &Model) {
        let n = self.len();
        // The model velocity changes with the still samples.
        self.terms.clear();
        self.still.clone_from(&self.window_still);
        let h = STOP_HALF_WIDTH;
        let valid = self.valid();
        let mut fr = Friction::new(m, self.t[0], self.x[0], self.model_velocity(0));
        for i in 0..n {
            fr.update(m, self.t[i], self.x[i], self.model_velocity(i));
            if !self.still[i] && valid.contains(&i) && i >= h && i + h < n {
                let on_count = self.x[i - h..=i + h].iter().all(|&x| x == self.x[i]);
                let pre = fr.presliding();
                if on_count && pre.direction() != 0 && pre.travel(m.z_max, self.x[i]) >= 1.0 {
                    self.still[i] = true;
                    let span = &self.u_mid[i - 2..=i];
                    self.u_still[i] = span.iter().sum::<f64>() / span.len() as f64;
                }
            }
            if self.still[i] {
                let additive = fr.force() - fr.dry();
                fr.anchor(self.x[i], self.u_still[i] - additive);
            }
        }
    }

    /// `‖c2‖`, the norm of the Savitzky–Golay second-derivative
    /// coefficients (per sample²).
    fn c2_norm(&self) -> f64 {
        let kf = self.kf as f64;
        let mu2 = kf * (kf + 1.0) / 3.0;
        let d: f64 = (0..=2 * self.kf)
            .map(|i| (i as f64 - kf).powi(2) - mu2)
            .map(|e| e * e)
            .sum();
        2.0 / d.sqrt()
    }

    /// The part of the weighted RMS [N] that noise and resolution explain:
    /// `√(Σ c_i·w_i·v_i / Σ c_i·w_i)` over the samples selected by
    /// `held_out` (`c` class weight, `w = σ0²/var` the error factor, `v`
    /// [`Prepared::floor_var`]), what a correct model would show. 0 before
    /// [`Prepared::set_error_weights`].
    pub fn floor(&self, held_out: Option<bool>) -> f64 {
        let (mut s, mut w) = (0.0, 0.0);
        for i in self.valid() {
            if held_out.is_none_or(|h| self.held_out[i] == h) {
                s += self.weight[i] * self.floor_var[i];
                w += self.weight[i];
            }
        }
        if w > 0.0 {
            (s / w).sqrt()
        } else {
            0.0
        }
    }

    /// The velocity [m/s] the model runs at on sample `i`: `v̂`, and 0 on
    /// the still samples. MODEL.md §5: in measured data a rest is where the
    /// position stays within the encoder's resolution, so the lagged
    /// velocity at rest must not follow the ±1-count dither of a held axis,
    /// whose `v̂` is about `q/(k·h)`. (At still samples the friction is the
    /// measured force in any case. The `dwell_stiction` clock takes its
    /// speed from [`Prepared::rest_speed`] instead.)
    pub fn model_velocity(&self, i: usize) -> f64 {
        if self.still[i] {
            0.0
        } else {
            self.v[i]
        }
    }

    /// The speed [m/s] that the `dwell_stiction` clock compares with
    /// `v_rest` at sample `i` ([`Prepared::count_period_speed`]).
    pub fn rest_speed(&self, i: usize) -> f64 {
        self.rest_speed[i]
    }

    /// Speed [m/s] of the axis for the `dwell_stiction` clock at every
    /// sample of the positions `xs` [m] at times `t` [s], `q` [m] the
    /// encoder count, from the counts alone (the encoder's period, "1/T",
    /// estimate). A **stay** is a run of samples on one count. The speed
    /// over a stay is the step that ends it over the time from the change
    /// that began it, when both changes go the same way (the axis crossed
    /// the whole count); 0 when they go opposite ways (the axis turned
    /// within the count, through zero velocity, and may have moved no more
    /// than a hair either side of a count boundary). The first stay counts
    /// from the record's start, the last one to its end with the last step;
    /// a record that never changes its count has speed 0. At the sample of
    /// a count change the speed is the larger of the stays on either side,
    /// and at least the step less one count over one sample period (a jump
    /// of several counts within a sample is fast motion).
    ///
    /// MODEL.md §5 counts a rest while `|v| ≤ v_rest`, with `v_rest`
    /// usually well below a count per sample. A slow presliding creep
    /// crosses counts at such speeds: `v̂` over the window around each
    /// change reads about a count per window, which would restart the
    /// clock at every count although the axis never moved faster than a
    /// count per stay. An axis that settles on a count after a move is
    /// still moving while its stays are short, and its rest starts with
    /// the first long stay; a dither on a count boundary is rest, and
    /// every reversal passes through rest, as it does in the model.
    /// (Dips below `v_rest` within a count, which restart the clock of a
    /// simulation, cannot be seen, but for the sticks below.)
    ///
    /// A **stick** (version 8.4): a stay that the axis crosses on its way
    /// (both changes the same way) but of at least [`STICK_MIN_STAY`]
    /// samples and [`STICK_RATIO`] times the stay before it counts as rest
    /// too. The count rate fell several-fold within one count, which a
    /// servo-driven axis does when it sticks for a few milliseconds after
    /// a break-away or in a jerky slow move: its velocity passed through
    /// `v_rest`, and MODEL.md's clock starts a new, short rest there,
    /// while the stay's mean speed, a count over its length, still reads
    /// above `v_rest`.
    pub fn count_period_speed(xs: &[f64], t: &[f64], q: f64) -> Vec<f64> {
        let n = xs.len();
        let changes: Vec<usize> = (1..n).filter(|&i| xs[i] != xs[i - 1]).collect();
        let mut speed = vec![0.0; n];
        let Some(&last) = changes.last() else {
            return speed;
        };
        let step = |c: usize| xs[c] - xs[c - 1];
        // Speed over the stay [begin, end): `begin` 0 or a change, `end` the
        // next change or `n`.
        let stay_speed = |begin: usize, end: usize| -> f64 {
            let (to, s) = if end < n {
                (end, step(end))
            } else {
                (n - 1, step(last))
            };
            let turned = begin > 0 && end < n && step(begin).signum() != s.signum();
            if turned || t[to] <= t[begin] {
                0.0
            } else {
                s.abs() / (t[to] - t[begin])
            }
        };
        let mut begin = 0;
        let mut before = 0.0;
        // Samples of the stay before, `None` for the record's first one.
        let mut previous: Option<usize> = None;
        for k in 0..=changes.len() {
            let end = changes.get(k).copied().unwrap_or(n);
            let mut stay = stay_speed(begin, end);
            let len = end - begin;
            if let Some(prev) = previous {
                // Crossed on the way, but far slower than the count before:
                // the axis stuck within it.
                if stay > 0.0 && end < n && stuck(len, prev) {
                    stay = 0.0;
                }
            }
            previous = (begin > 0).then_some(len);
            speed[begin..end].fill(stay);
            if begin > 0 {
                // (The loader admits only increasing times.)
                let jump = (step(begin).abs() - q).max(0.0) / (t[begin] - t[begin - 1]);
                speed[begin] = stay.max(before).max(jump);
            }
            before = stay;
            begin = end;
        }
        speed
    }

    /// Runs the friction memory of `m` along the measured motion and calls
    /// `f(i, &friction)` after each sample's update. After a still sample
    /// the memory is re-anchored at the measured force (see
    /// [`Prepared::still`]): dry friction `ū − (F − H)`, so that the
    /// friction there is `ū` and the next motion starts from it. Every pass
    /// of the lab over a record goes through here, so they all see the same
    /// memory.
    pub fn walk(&self, m: &Model, mut f: impl FnMut(usize, &Friction)) {
        let along = |g: &dyn Fn(f64) -> f64| -> Vec<f64> {
            let ln_speed = self.ln_speed();
            ln_speed.iter().map(|&l| g(l)).collect()
        };
        let (v_s, delta) = (m.v_stribeck, m.delta);
        let decay = match m.effects.frictional_lag {
            None => TermCache::get(&self.terms.decay, [v_s.to_bits(), delta.to_bits()], || {
                let ln_v = v_s.ln();
                along(&|l| decay_of_power((delta * (l - ln_v)).exp()))
            }),
            Some(lag) => {
                let key = [v_s.to_bits(), delta.to_bits(), lag.tau_l.to_bits()];
                TermCache::get(&self.terms.lagged_decay, key, || {
                    let mut filter = LagFilter::new(self.t[0], self.model_velocity(0));
                    (0..self.len())
                        .map(|i| {
                            let v = self.model_velocity(i);
                            stribeck_decay(v_s, delta, filter.update(Some(lag.tau_l), self.t[i], v))
                        })
                        .collect()
                })
            }
        };
        let speed_pow = m.effects.nonlinear_viscous.map(|nv| self.speed_pow(nv.n));
        let ripple_sin = m.effects.position_ripple.map(|r| {
            let key = [r.wavelength.to_bits(), r.phase.to_bits()];
            TermCache::get(&self.terms.ripple_sin, key, || {
                self.x
                    .iter()
                    .map(|&x| (2.0 * PI * x / r.wavelength + r.phase).sin())
                    .collect()
            })
        });
        let mut fr = Friction::new(m, self.t[0], self.x[0], self.model_velocity(0));
        for i in 0..self.len() {
            let terms = SampleTerms {
                decay: Some(decay[i]),
                speed_pow: speed_pow.as_ref().map(|p| p[i]),
                rest_speed: Some(self.rest_speed[i]),
                ripple_sin: ripple_sin.as_ref().map(|r| r[i]),
            };
            fr.update_with(m, self.t[i], self.x[i], self.model_velocity(i), terms);
            f(i, &fr);
            if self.still[i] {
                let additive = fr.force() - fr.dry();
                fr.anchor(self.x[i], self.u_still[i] - additive);
            }
        }
    }

    /// `|v|^n` of [`Prepared::model_velocity`] at every sample (0 at still
    /// samples), as the walk's `nonlinear_viscous` term and its Jacobian
    /// column take it (cached by `n`).
    pub(crate) fn speed_pow(&self, n: f64) -> Arc<Vec<f64>> {
        TermCache::get(&self.terms.speed_pow, n.to_bits(), || {
            self.ln_speed().iter().map(|&l| (n * l).exp()).collect()
        })
    }

    /// `ln |v|` of [`Prepared::model_velocity`] at every sample (−∞ where
    /// it is 0), kept until the still samples change: the powers of the
    /// Stribeck decay and of `nonlinear_viscous` are taken as `exp(p·ln|v|)`
    /// from it (a `powf` per sample and shape was an eighth of a fit's
    /// time).
    fn ln_speed(&self) -> Arc<Vec<f64>> {
        let mut cached = self
            .terms
            .ln_speed
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        Arc::clone(cached.get_or_insert_with(|| {
            Arc::new(
                (0..self.len())
                    .map(|i| self.model_velocity(i).abs().ln())
                    .collect(),
            )
        }))
    }

    /// Per-sample `|∂H/∂x|` [N/m] of the presliding branch (0 in gross
    /// sliding; `w` at least half an encoder count from the turning point)
    /// and `|∂F/∂v|` [N·s/m] (the Stribeck slope times `g(w)`, plus σ) of
    /// model `m` along the motion, in one pass.
    pub fn sensitivities(&self, m: &Model) -> (Vec<f64>, Vec<f64>) {
        let n = self.len();
        let (mut sx, mut sv) = (vec![0.0; n], vec![0.0; n]);
        let w_min = if m.z_max > 0.0 {
            (0.5 * self.resolution / m.z_max).min(0.5)
        } else {
            1.0
        };
        self.walk(m, |i, fr| {
            let pre = fr.presliding();
            let d = pre.direction();
            let w = pre.travel(m.z_max, self.x[i]);
            let g = if d == 0 || m.z_max <= 0.0 {
                1.0
            } else {
                let w = w.max(1e-12);
                w * (1.0 - w.ln())
            };
            if m.z_max > 0.0 && (d == 0 || w < 1.0) {
                let w = w.max(w_min);
                let amp = if d == 0 {
                    (m.fs - fr.dry()).abs().max((m.fs + fr.dry()).abs())
                } else {
                    let gw = w * (1.0 - w.ln());
                    ((fr.dry() - pre.dry_at_turning_point()) / gw).abs()
                };
                sx[i] = amp * (-w.ln()) / m.z_max;
            }
            let s = self.v[i].abs() / m.v_stribeck;
            let slope = if s > 0.0 {
                (m.fs - m.fc) * m.delta / m.v_stribeck
                    * s.powf(m.delta - 1.0)
                    * (-s.powf(m.delta)).exp()
            } else {
                0.0
            };
            sv[i] = g * slope.min(1e12) + m.sigma;
        });
        (sx, sv)
    }

    /// `‖W‖`, the factor by which the kernel scales white force noise.
    pub fn kernel_norm(&self) -> f64 {
        norm(&self.kernel)
    }

    /// Applies the force kernel to a per-sample series `s` at sample `i`.
    pub fn filter_at(&self, s: &[f64], i: usize) -> f64 {
        let mut acc = 0.0;
        for (j, w) in self.kernel.iter().enumerate() {
            acc += w * s[i + j - self.kf];
        }
        acc
    }

    /// The friction `F` of `m` along the measured motion, every sample
    /// ([`Prepared::walk`]: `F = ū` at still samples).
    pub fn friction(&self, m: &Model) -> Vec<f64> {
        let mut f = vec![0.0; self.len()];
        self.walk(m, |i, fr| {
            f[i] = if self.still[i] {
                self.u_still[i]
            } else {
                fr.force()
            }
        });
        f
    }

    /// `ū − F` of `m` at every sample [N], before the force kernel.
    fn force_gap(&self, m: &Model) -> Vec<f64> {
        let f = self.friction(m);
        self.u_mid.iter().zip(&f).map(|(u, f)| u - f).collect()
    }

    /// The residual `r_i` of `m` (0 outside the valid range).
    pub fn residual(&self, m: &Model) -> Vec<f64> {
        let mut r = self.filter_all(&self.force_gap(m));
        for i in self.valid() {
            r[i] -= m.mass * self.a[i];
        }
        r
    }

    /// [`Prepared::filter_at`] at every valid sample (0 elsewhere), with
    /// the loops exchanged: each sample's sum runs over the kernel in the
    /// same order (the same result to the last bit), and the inner loop
    /// over the samples vectorises (the residual's cost with a ±32 kernel
    /// fell about 4×).
    pub fn filter_all(&self, s: &[f64]) -> Vec<f64> {
        let mut acc = vec![0.0; self.len()];
        self.filter_into(s, self.valid(), &mut acc);
        acc
    }

    /// [`Prepared::filter_at`] at every sample of `run` (a range inside
    /// [`Prepared::valid`]), added to `acc`, which holds 0 there.
    fn filter_into(&self, s: &[f64], run: std::ops::Range<usize>, acc: &mut [f64]) {
        if run.is_empty() {
            return;
        }
        // Sample i reads s[i + j − kf]; run.start ≥ kf. Eight taps per
        // pass over the samples (one load and store of the sum for eight
        // products; EMPS 5 % less CPU time than four), added one after
        // another as in `filter_at`.
        let src = |j: usize| &s[run.start + j - self.kf..run.end + j - self.kf];
        let out = &mut acc[run.clone()];
        let mut taps = self.kernel.chunks_exact(8);
        let mut j = 0;
        for w in &mut taps {
            let (s0, s1, s2, s3) = (src(j), src(j + 1), src(j + 2), src(j + 3));
            let (s4, s5, s6, s7) = (src(j + 4), src(j + 5), src(j + 6), src(j + 7));
            for (i, a) in out.iter_mut().enumerate() {
                let mut t = *a + w[0] * s0[i];
                t += w[1] * s1[i];
                t += w[2] * s2[i];
                t += w[3] * s3[i];
                t += w[4] * s4[i];
                t += w[5] * s5[i];
                t += w[6] * s6[i];
                *a = t + w[7] * s7[i];
            }
            j += 8;
        }
        for w in taps.remainder() {
            for (a, x) in out.iter_mut().zip(src(j)) {
                *a += w * x;
            }
            j += 1;
        }
    }

    /// The runs of consecutive valid samples on one side of the split
    /// (`held_out == side`).
    fn runs(&self, side: bool) -> Vec<std::ops::Range<usize>> {
        let mut runs = Vec::new();
        let mut start = None;
        let valid = self.valid();
        for i in valid.clone() {
            match (self.held_out[i] == side, start) {
                (true, None) => start = Some(i),
                (false, Some(s)) => {
                    runs.push(s..i);
                    start = None;
                }
                _ => {}
            }
        }
        if let Some(s) = start {
            runs.push(s..valid.end);
        }
        runs
    }

    /// [`Prepared::filter_all`] on one side of the split only (`held_out
    /// == side`; 0 elsewhere): the same values there, with the kernel
    /// applied only where they are read (a fit reads the training side, a
    /// score the held-out side).
    pub fn filter_on(&self, s: &[f64], side: bool) -> Vec<f64> {
        let mut acc = vec![0.0; self.len()];
        for run in self.runs(side) {
            self.filter_into(s, run, &mut acc);
        }
        acc
    }

    /// [`Prepared::filter_on`] of the series `which` on the training side
    /// (0 at still samples, as [`Prepared::friction`]'s derivatives are),
    /// kept until the still samples change ([`Prepared::mark_stops`]; the
    /// split is set once, when the record is prepared): a fit asks for the
    /// same column at every iteration.
    pub fn fixed_column(&self, which: FixedColumn) -> Arc<Vec<f64>> {
        TermCache::get(&self.terms.fixed, which, || {
            let s: Vec<f64> = (0..self.len())
                .map(|i| match (self.still[i], which) {
                    (true, _) => 0.0,
                    (false, FixedColumn::Velocity) => self.model_velocity(i),
                    (false, FixedColumn::Moving) => 1.0,
                })
                .collect();
            self.filter_on(&s, false)
        })
    }

    /// [`Prepared::residual`] on one side of the split only (see
    /// [`Prepared::filter_on`]).
    pub fn residual_on(&self, m: &Model, side: bool) -> Vec<f64> {
        let mut r = self.filter_on(&self.force_gap(m), side);
        for i in self.valid().filter(|&i| self.held_out[i] == side) {
            r[i] -= m.mass * self.a[i];
        }
        r
    }

    /// Weighted RMS of `r` over the samples selected by `held_out`
    /// (`None`: all valid samples).
    pub fn rms(&self, r: &[f64], held_out: Option<bool>) -> f64 {
        let (mut s, mut w) = (0.0, 0.0);
        for i in self.valid() {
            if held_out.is_none_or(|h| self.held_out[i] == h) {
                s += self.weight[i] * r[i] * r[i];
                w += self.weight[i];
            }
        }
        if w > 0.0 {
            (s / w).sqrt()
        } else {
            f64::NAN
        }
    }

    /// Number of valid samples in the held-out (`true`) or training set.
    pub fn count(&self, held_out: bool) -> usize {
        self.valid()
            .filter(|&i| self.held_out[i] == held_out)
            .count()
    }
}

/// The model error [N] in a weighted RMS `rms` [N] whose noise-and-
/// resolution part is `floor` [N] ([`Prepared::floor`]):
/// `√max(rms² − floor², 0)`.
pub fn model_error(rms: f64, floor: f64) -> f64 {
    (rms * rms - floor * floor).max(0.0).sqrt()
}
#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::data::Record;
    use crate::reference::DwellStiction;
    use std::f64::consts::PI;

    /// A record of `n` samples `dt` [s] apart along the position `x(t)` [m],
    /// under a force of two sinusoids (the lab's unit tests' fixture).
    pub(crate) fn record(n: usize, dt: f64, x: impl Fn(f64) -> f64) -> Record {
        let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
        let u = t
            .iter()
            .map(|&t| (7.0 * t).sin() + 0.3 * (53.0 * t).cos())
            .collect();
        let x = t.iter().map(|&t| x(t)).collect();
        Record {
            t,
            u,
            x,
            v: None,
            source: "test".into(),
        }
    }

    /// The force kernel sums to 1 (`Σ W_j·Δ²x = Σ c2_j·x`, so a parabola
    /// `x = t²` gives `â = 2` exactly) at every half-width.
    #[test]
    fn kernel_gives_the_second_derivative_of_a_parabola() {
        for k in [2, 4, 12, 32, 64] {
            let (_, c2) = sg_coefficients(k);
            let w = force_kernel(&c2);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12, "k {k}");
        }
        let rec = record(400, 1e-3, |t| t * t);
        let p = Prepared::with_window(
            &rec,
            Window {
                velocity: 4,
                force: 32,
            },
        );
        for i in p.valid() {
            assert!((p.a[i] - 2.0).abs() < 1e-6, "a[{i}] = {}", p.a[i]);
            assert!((p.v[i] - 2.0 * p.t[i]).abs() < 1e-9, "v[{i}] = {}", p.v[i]);
        }
    }

    /// A record that rests for its first 80 % and moves only in its last
    /// fifth: equal time blocks would hold out eight blocks of rest (2, 5,
    /// …, 23) and only two of the motion; the split by scored samples
    /// holds out a third of the motion, in ten runs (the last block held
    /// out), and no training block is empty of it.
    #[test]
    fn split_holds_out_a_share_of_the_motion() {
        let (n, q) = (10_000, 1e-6);
        let rec = record(n, 1e-3, |t| {
            let moving = (t - 8.0).max(0.0);
            (1e-3 * moving * moving / q).floor() * q
        });
        let p = Prepared::new(&rec, DEFAULT_HALF_WIDTH);
        let scored: Vec<usize> = p.valid().filter(|&i| !p.still[i]).collect();
        assert!(scored.len() > 1000, "{} moving samples", scored.len());
        assert!(
            scored.iter().all(|&i| p.t[i] > 7.9),
            "motion before t = 8 s"
        );
        let held = scored.iter().filter(|&&i| p.held_out[i]).count();
        let share = held as f64 / scored.len() as f64;
        assert!(
            (share - 1.0 / 3.0).abs() < 0.01,
            "held-out share of the motion {share}"
        );
        let runs = scored
            .windows(2)
            .filter(|w| p.held_out[w[0]] != p.held_out[w[1]])
            .count();
        assert_eq!(
            runs, 19,
            "held-out runs of the motion: blocks 2, 5, …, 29 of 30"
        );
    }

    /// A sinusoidal record of `n` samples, prepared with a ±20 force
    /// kernel, and a series to filter that is no polynomial (non-integer
    /// values, so that a changed order of the sums shows in the bits).
    fn filter_fixture(n: usize) -> (Prepared, Vec<f64>) {
        let rec = record(n, 1e-3, |t| 1e-3 * (3.0 * t).sin());
        let p = Prepared::with_window(
            &rec,
            Window {
                velocity: 4,
                force: 20,
            },
        );
        let s = (0..n)
            .map(|i| ((i * 7919) % 101) as f64 * 0.371 - 18.3)
            .collect();
        (p, s)
    }

    /// Bursts: a quantised smooth motion (a start at 1 m/s², one count per
    /// sample², to a 20 mm/s cruise, then a stop to a 0.3 count per sample
    /// creep) has none, however its counts fall; the count pattern of an
    /// axis that sticks and slips within each period (increments of 1, 20,
    /// 3, 13, … counts, about 10 per sample, as on development record
    /// 3000077 of the independent generator) is one, and the flag spreads
    /// over the force kernel.
    #[test]
    fn bursts_mark_stick_slip_within_a_period_only() {
        let q = 1e-6;
        let (k, kf) = (4, 16);
        let n = 400;
        let speed = |t: f64| -> f64 {
            if t < 0.1 {
                0.0
            } else if t < 0.12 {
                t - 0.1
            } else if t < 0.25 {
                0.02
            } else if t < 0.2697 {
                0.02 - (t - 0.25)
            } else {
                3e-4
            }
        };
        let mut x = 0.37 * q;
        let smooth: Vec<f64> = (0..n)
            .map(|i| {
                // Midpoint rule, 10 sub-steps per sample.
                for s in 0..10 {
                    x += speed((i as f64 + (s as f64 + 0.5) / 10.0) * 1e-3) * 1e-4;
                }
                (x / q).floor() * q
            })
            .collect();
        assert!(Prepared::bursts_of(&smooth, q, k, kf).iter().all(|&b| !b));
        let pattern = [1.0, 20.0, 3.0, 13.0, 10.0, 5.0, 18.0, 1.0, 20.0, 2.0];
        let mut creep = vec![0.0; n];
        for i in 1..n {
            let step = if (150..250).contains(&i) {
                pattern[i % pattern.len()]
            } else {
                0.0
            };
            creep[i] = creep[i - 1] + step * q;
        }
        let b = Prepared::bursts_of(&creep, q, k, kf);
        assert!((150 + k..250 - k).all(|i| b[i]), "creep not marked");
        assert!(b[150 - kf] && !b[150 - kf - k - 2] && !b[250 + kf + k + 1]);
    }

    /// `filter_all` is `filter_at` at every valid sample, to the last bit.
    #[test]
    fn filter_all_is_filter_at() {
        let (_, s) = filter_fixture(500);
        // Force kernels (2k + 1 taps) of every odd length modulo the eight
        // taps per pass.
        let mut lengths = std::collections::BTreeSet::new();
        for force in 16..=31 {
            let window = Window { velocity: 4, force };
            let p = Prepared::with_window(&record(500, 1e-3, |t| 1e-3 * (3.0 * t).sin()), window);
            lengths.insert(p.kernel.len() % 8);
            let all = p.filter_all(&s);
            for (i, got) in all.iter().enumerate() {
                let want = if p.valid().contains(&i) {
                    p.filter_at(&s, i)
                } else {
                    0.0
                };
                assert_eq!(got.to_bits(), want.to_bits(), "force {force}, sample {i}");
            }
        }
        assert_eq!(lengths.len(), 4, "kernel lengths modulo 8: {lengths:?}");
    }

    /// `filter_on` and `residual_on` are `filter_all` and `residual` on
    /// their side of the split, to the last bit, and 0 elsewhere.
    #[test]
    fn one_side_is_the_full_filter_there() {
        let (p, s) = filter_fixture(2000);
        let n = p.len();
        let all = p.filter_all(&s);
        let m = crate::diagnose::fig5_model();
        let r_all = p.residual(&m);
        for side in [false, true] {
            let one = p.filter_on(&s, side);
            let r_one = p.residual_on(&m, side);
            let on_side = |i: usize| p.valid().contains(&i) && p.held_out[i] == side;
            assert!((0..n).any(on_side) && !(0..n).all(on_side));
            for i in 0..n {
                let (want, want_r) = if on_side(i) {
                    (all[i], r_all[i])
                } else {
                    (0.0, 0.0)
                };
                assert_eq!(one[i].to_bits(), want.to_bits(), "side {side} sample {i}");
                assert_eq!(
                    r_one[i].to_bits(),
                    want_r.to_bits(),
                    "side {side} sample {i}"
                );
            }
        }
    }

    /// At 1 kHz the automatic windows are ±4 for the velocity and ±32 for
    /// the force kernel.
    #[test]
    fn automatic_windows_at_one_kilohertz() {
        let rec = record(5000, 1e-3, |t| {
            (1e-4 * (2.0 * t).sin() / 1e-7).round() * 1e-7
        });
        let w = auto_window(&rec);
        assert_eq!(w.velocity, AUTO_HALF_WIDTH);
        assert!(w.force >= 32 && w.force <= MAX_AUTO_HALF_WIDTH, "{w:?}");
    }

    /// MODEL.md §5: in measured data a rest is where the position stays
    /// within the encoder's resolution. A held axis that dithers on a count
    /// boundary (`v̂` of a count per few samples, far above a small `v_rest`)
    /// is at rest all along: the `dwell_stiction` clock the model runs
    /// along the record reads the whole hold when the motion starts.
    #[test]
    fn dwell_clock_counts_a_dithering_hold() {
        let q = 1e-6;
        // 2 s hold with a one-count dither every 7 ms, then a 5 mm/s move.
        let rec = record(3000, 1e-3, |t| {
            if t < 2.0 {
                if ((t * 1e3).round() as i64 / 7) % 2 == 0 {
                    0.0
                } else {
                    q
                }
            } else {
                q * ((t - 2.0) * 5e-3 / q).floor()
            }
        });
        let p = Prepared::with_window(
            &rec,
            Window {
                velocity: 4,
                force: 32,
            },
        );
        let mut m = crate::diagnose::fig5_model();
        m.effects.dwell_stiction = Some(DwellStiction {
            delta_fs: 0.5,
            gamma: 0.5,
            v_rest: 1e-5,
        });
        let start = p.t.iter().position(|&t| t >= 2.05).unwrap_or(0);
        let mut td = 0.0;
        p.walk(&m, |i, fr| {
            if i == start {
                td = fr.dwell_time();
            }
        });
        assert!(td > 1.9 && td < 2.1, "t_d {td} s after a 2 s hold");
    }

    /// The clock's speed from the counts: a creep of one count per 50
    /// samples reads a count per stay (not the count per window that `v̂`
    /// reads around each change); a dither on a count boundary, and the
    /// stay at a reversal, read 0; a jump of four counts within one sample
    /// reads at least three counts per sample however long the stay
    /// before it; fast motion reads its steps per sample.
    #[test]
    fn count_period_speed_of_creep_dither_jump_and_motion() {
        let (q, h) = (1e-6, 1e-3);
        // 100 samples on count 0; counts 1..=5 every 50 samples; dither
        // 5 ↔ 6 every 10 samples; back on 5 for 100 samples; a jump to 9;
        // 100 samples there; then 3 counts per sample.
        let mut xs: Vec<f64> = vec![0.0; 100];
        for c in 1..=5 {
            xs.extend(std::iter::repeat_n(c as f64 * q, 50));
        }
        for j in 0..6 {
            xs.extend(std::iter::repeat_n((5 + (j + 1) % 2) as f64 * q, 10));
        }
        xs.extend(std::iter::repeat_n(5.0 * q, 100));
        xs.extend(std::iter::repeat_n(9.0 * q, 100));
        let fast0 = xs.len();
        xs.extend((1..=20).map(|j| (9 + 3 * j) as f64 * q));
        let t: Vec<f64> = (0..xs.len()).map(|i| i as f64 * h).collect();
        let v = Prepared::count_period_speed(&xs, &t, q);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1e-12);
        // The first stay: the first step over the time from the start.
        assert!(close(v[50], q / (100.0 * h)), "first stay {}", v[50]);
        // The creep: a count per 50 samples on the stays and the changes.
        for i in [100, 125, 150, 199, 275] {
            assert!(close(v[i], q / (50.0 * h)), "creep at {i}: {}", v[i]);
        }
        // The dither: stays between opposite changes read 0.
        let dither = 350 + 15;
        assert_eq!(v[dither], 0.0, "dither");
        assert_eq!(v[dither + 20], 0.0, "dither");
        // The jump of 4 counts in one sample after a 100-sample stay.
        let jump = fast0 - 100;
        assert!(v[jump] >= 2.9 * q / h, "jump {}", v[jump]);
        assert!(
            v[jump - 1] < 0.1 * q / h,
            "stay before the jump {}",
            v[jump - 1]
        );
        // Fast motion: 3 counts per sample.
        assert!(close(v[fast0 + 5], 3.0 * q / h), "motion {}", v[fast0 + 5]);
    }

    /// A stick within a move: an axis crossing a count per sample that
    /// holds one count for 3 samples, or one crossing a count every 4
    /// samples that holds one for 13, reads 0 there (a rest of MODEL.md's
    /// clock); stays that lengthen by less than [`STICK_RATIO`], as a
    /// steady creep's or a smooth slow-down's do, keep their speed.
    #[test]
    fn a_stay_far_longer_than_the_one_before_is_a_stick() {
        let (q, h) = (1e-6, 1e-3);
        // 50 samples on count 0; counts 1..=5 one per sample; 3 samples
        // on count 5 (the stick); counts 6..=9 one per sample; counts
        // 10..=14 every 4 samples; 13 samples on count 15 (the stick);
        // counts 16..=19 every 4 samples; counts 20..=23 every 2, 3, 4, 6
        // samples (a slow-down); then 100 samples at rest.
        let mut xs: Vec<f64> = vec![0.0; 50];
        let mut count = 0;
        let mut stays = |xs: &mut Vec<f64>, lens: &[usize]| {
            for &len in lens {
                count += 1;
                xs.extend(std::iter::repeat_n(count as f64 * q, len));
            }
        };
        stays(&mut xs, &[1, 1, 1, 1]);
        let stick_1 = xs.len();
        stays(&mut xs, &[3, 1, 1, 1, 1, 4, 4, 4, 4]);
        let before_2 = xs.len() - 4;
        stays(&mut xs, &[4]);
        let stick_2 = xs.len();
        stays(&mut xs, &[13, 4, 4, 4, 4, 2, 3, 4]);
        let slow_down = xs.len();
        stays(&mut xs, &[6, 100]);
        let t: Vec<f64> = (0..xs.len()).map(|i| i as f64 * h).collect();
        let v = Prepared::count_period_speed(&xs, &t, q);
        assert_eq!(v[stick_1 + 1], 0.0, "one count per sample, then 3 on one");
        assert_eq!(v[stick_2 + 6], 0.0, "a count per 4 samples, then 13 on one");
        assert!(
            v[before_2 + 1] > 0.2 * q / h,
            "steady creep {}",
            v[before_2 + 1]
        );
        assert!(
            v[slow_down + 2] > 0.1 * q / h,
            "slow-down {}",
            v[slow_down + 2]
        );
    }

    /// Below one count per sample the friction is known only to its whole
    /// hysteresis range (a reversal smaller than a count may hide between
    /// two samples): a creep at half a count per sample carries the
    /// variance `(2·Fs)²/12`, a motion at five counts per sample none of it.
    #[test]
    fn creep_below_a_count_per_sample_is_not_resolved() {
        let q = 1e-6;
        let rec = record(2000, 1e-3, |t| {
            let x = if t < 1.0 {
                0.5e-3 * t
            } else {
                0.5e-3 + 5e-3 * (t - 1.0)
            };
            q * (x / q).floor()
        });
        let mut p = Prepared::with_window(
            &rec,
            Window {
                velocity: 4,
                force: 32,
            },
        );
        let m = crate::diagnose::fig5_model();
        let r = p.residual(&m);
        p.set_error_weights(&m, &r);
        let range = (2.0 * m.fs).powi(2) / 12.0;
        assert!(!p.still[500] && !p.still[1500]);
        assert!(
            p.var[500] >= range && p.var[500] < 1.01 * range + 1.0,
            "creep: var {} N², range {range} N²",
            p.var[500]
        );
        assert!(
            p.var[1500] < 1e-3 * range,
            "5 counts per sample: var {} N²",
            p.var[1500]
        );
    }

    /// A position loop on a fine encoder: its command steps by `Kp·q` at
    /// every count change, which the third differences of all windows read
    /// as noise; the count-stable windows give the logged noise itself.
    #[test]
    fn force_noise_ignores_the_loop_steps_at_count_changes() {
        let (q, kp, sigma) = (1e-7, 2e6, 0.01);
        let mut rng = crate::synth::Rng::new(7);
        let n = 20_000;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 * 1e-3;
                q * (2e-5 * (1.5 * t).sin() / q).floor()
            })
            .collect();
        let u: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 * 1e-3;
                kp * (2e-5 * (1.5 * t).sin() - x[i]) + sigma * rng.normal()
            })
            .collect();
        let all = force_noise(&u, &vec![0.0; n]);
        let stable = force_noise(&u, &x);
        assert!(
            all > 2.0 * sigma,
            "all windows {all}: the steps are visible"
        );
        assert!(
            (stable / sigma - 1.0).abs() < 0.1,
            "count-stable windows {stable} N"
        );
    }

    /// The hidden-reversal range a record shows follows the residual at
    /// slow samples: a disagreement of 1 N that varies slowly (a tenth of
    /// its period over the record) cancels in the pairs and leaves the
    /// noise (0.05 N, so about √12·0.05 N), while bursts from sample to
    /// sample (±0.5 N) keep a range of their size; too few slow samples
    /// leave it unknown.
    #[test]
    fn the_slow_motion_range_is_what_slow_samples_show() {
        let rec = record(4000, 1e-3, |t| 1e-3 * t);
        let p = Prepared::with_window(
            &rec,
            Window {
                velocity: 4,
                force: 32,
            },
        );
        let mut rng = crate::synth::Rng::new(11);
        let slow_drift: Vec<f64> = (0..p.len())
            .map(|i| (2.0 * PI * i as f64 / 40_000.0).sin() + 0.05 * rng.normal())
            .collect();
        let all = |_: usize| true;
        let spread = p.slow_spread(&slow_drift, &all).unwrap();
        let noise = 12f64.sqrt() * 0.05;
        assert!(
            (spread / noise - 1.0).abs() < 0.3,
            "drift: {spread} N against {noise} N"
        );
        let bursts: Vec<f64> = (0..p.len())
            .map(|i| if (i / 7) % 2 == 0 { 0.5 } else { -0.5 })
            .collect();
        let spread = p.slow_spread(&bursts, &all).unwrap();
        assert!(spread > 0.8, "bursts: {spread} N");
        let few = |i: usize| i < 100 + MIN_SLOW_PAIRS / 2;
        assert!(p.slow_spread(&bursts, &few).is_none());
    }
}
