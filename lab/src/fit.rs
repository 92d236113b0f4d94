//! Fitting a friction model to a measured record: its free parameters, their
//! encodings, and the one least-squares solver of the lab, on the residual
//! of [`crate::residual`] (MODEL.md §1, §5, §8: compare locally).
//!
//! # Least squares
//!
//! Levenberg–Marquardt (Marquardt's diagonal scaling) on the training set,
//! with positive parameters on a log scale, `a` through `tanh`, δ through a
//! logistic map onto [`DELTA_RANGE`], and the
//! parameters that enter `F` linearly (mass, σ, F0, ripple sin/cos
//! amplitudes) with analytic Jacobian columns; the other columns are forward
//! differences (one pass along the record each).

use crate::reference::{
    Asymmetry, Drift, DwellStiction, Effect, FrictionalLag, Model, NonlinearViscous, Offset,
    PositionRipple,
};
use crate::residual::{FixedColumn, Prepared};
use rayon::prelude::*;

/// A free parameter of the fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    /// `mass` [kg], linear.
    Mass,
    /// `fc` [N], log.
    Fc,
    /// `fs − fc` [N], log.
    FsExcess,
    /// `v_stribeck` [m/s], log.
    VStribeck,
    /// `delta`, log.
    Delta,
    /// `sigma` [N·s/m], linear, ≥ 0.
    Sigma,
    /// `z_max` [m], log.
    ZMax,
    /// `effects.offset.f0` [N], linear.
    F0,
    /// `effects.asymmetry.a`, tanh.
    Asym,
    /// `A·cos φ` [N], linear.
    RippleC,
    /// `A·sin φ` [N], linear.
    RippleS,
    /// `effects.position_ripple.wavelength` [m], log.
    RippleLambda,
    /// `effects.dwell_stiction.delta_fs` [N], log.
    DwellDfs,
    /// `effects.dwell_stiction.gamma` [s], log.
    DwellGamma,
    /// `effects.frictional_lag.tau_l` [s], log.
    LagTau,
    /// `effects.drift.beta` [1/s], linear (scaled by the record length).
    DriftBeta,
    /// `effects.nonlinear_viscous.sigma_n` [N·(s/m)^n], linear.
    SigmaN,
    /// `effects.nonlinear_viscous.n`, logistic onto [`NV_EXP_RANGE`].
    NvExp,
}

/// Range of the fitted exponent `n` of `nonlinear_viscous` (MODEL.md §5:
/// `0 < n <= 2`).
pub const NV_EXP_RANGE: (f64, f64) = (0.05, 2.0);

/// Which effects of §5 a model has.
pub fn has_effect(m: &Model, effect: Effect) -> bool {
    let e = &m.effects;
    match effect {
        Effect::Viscous => m.sigma > 0.0,
        Effect::Offset => e.offset.is_some(),
        Effect::Asymmetry => e.asymmetry.is_some(),
        Effect::PositionRipple => e.position_ripple.is_some(),
        Effect::DwellStiction => e.dwell_stiction.is_some(),
        Effect::FrictionalLag => e.frictional_lag.is_some(),
        Effect::Drift => e.drift.is_some(),
        Effect::NonlinearViscous => e.nonlinear_viscous.is_some(),
        Effect::Stribeck => m.fs > m.fc,
        Effect::Presliding => m.z_max > 0.0,
    }
}

/// The effects `m` has, in catalogue order ([`Effect::ALL`]).
pub fn effects_of(m: &Model) -> Vec<Effect> {
    Effect::ALL
        .into_iter()
        .filter(|&e| has_effect(m, e))
        .collect()
}

/// The free parameters of a model's structure (mass and Fc always).
pub fn params_of(m: &Model) -> Vec<Param> {
    let mut p = vec![Param::Mass, Param::Fc];
    if has_effect(m, Effect::Stribeck) {
        p.extend([Param::FsExcess, Param::VStribeck, Param::Delta]);
    }
    if has_effect(m, Effect::Presliding) {
        p.push(Param::ZMax);
    }
    if has_effect(m, Effect::Viscous) {
        p.push(Param::Sigma);
    }
    let e = &m.effects;
    if e.offset.is_some() {
        p.push(Param::F0);
    }
    if e.asymmetry.is_some() {
        p.push(Param::Asym);
    }
    if e.position_ripple.is_some() {
        p.extend([Param::RippleC, Param::RippleS, Param::RippleLambda]);
    }
    if e.dwell_stiction.is_some() {
        p.extend([Param::DwellDfs, Param::DwellGamma]);
    }
    if e.frictional_lag.is_some() {
        p.push(Param::LagTau);
    }
    if e.drift.is_some() {
        p.push(Param::DriftBeta);
    }
    if e.nonlinear_viscous.is_some() {
        p.extend([Param::SigmaN, Param::NvExp]);
    }
    p
}

/// Range of the fitted shape exponent δ (MODEL.md §2: typically 0.5 … 2).
pub const DELTA_RANGE: (f64, f64) = (0.3, 4.0);

/// Least mass a fit may reach [kg]: the force balance is linear in the
/// mass, and a record whose accelerations do not resolve the inertia
/// (slow sinusoids, creep) can run it to zero.
pub const MASS_MIN: f64 = 1e-9;

/// Whether `m`'s mass sits at [`MASS_MIN`]: the record did not identify
/// the inertia, and the mass written is not a value of the axis.
pub fn mass_at_bound(m: &Model) -> bool {
    m.mass <= 2.0 * MASS_MIN
}

/// Largest `(Fs − Fc)/Fc` a fit may reach (a stiction level eleven times
/// the Coulomb level is far outside what axes show; a fit that runs there
/// has found no dip).
pub const FS_EXCESS_MAX: f64 = 10.0;

/// Lower bound used for log-scaled values that are 0 in a model.
const TINY: f64 = 1e-300;

fn get(m: &Model, p: Param, sc: Scales) -> f64 {
    let e = &m.effects;
    let rip = e.position_ripple.unwrap_or(PositionRipple {
        amplitude: 0.0,
        wavelength: 1.0,
        phase: 0.0,
    });
    let dw = e.dwell_stiction.unwrap_or(DwellStiction {
        delta_fs: 0.0,
        gamma: 1.0,
        v_rest: 1.0,
    });
    match p {
        Param::Mass => m.mass,
        Param::Fc => m.fc.max(TINY).ln(),
        Param::FsExcess => (m.fs - m.fc).max(1e-6 * m.fc).ln(),
        Param::VStribeck => m.v_stribeck.ln(),
        Param::Delta => {
            // δ = lo + (hi − lo)·sigmoid(θ): smooth, no flat clamp.
            let u = ((m.delta - DELTA_RANGE.0) / (DELTA_RANGE.1 - DELTA_RANGE.0))
                .clamp(1e-6, 1.0 - 1e-6);
            (u / (1.0 - u)).ln()
        }
        Param::Sigma => m.sigma,
        Param::ZMax => m.z_max.max(TINY).ln(),
        Param::F0 => e.offset.map_or(0.0, |o| o.f0),
        Param::Asym => e.asymmetry.map_or(0.0, |a| a.a.clamp(-0.95, 0.95).atanh()),
        Param::RippleC => rip.amplitude * rip.phase.cos(),
        Param::RippleS => rip.amplitude * rip.phase.sin(),
        Param::RippleLambda => rip.wavelength.ln(),
        Param::DwellDfs => dw.delta_fs.max(1e-6 * m.fc).ln(),
        Param::DwellGamma => dw.gamma.ln(),
        Param::LagTau => e.frictional_lag.map_or(0.0, |l| l.tau_l.ln()),
        Param::DriftBeta => e.drift.map_or(0.0, |d| d.beta) * sc.t_span,
        Param::SigmaN => e.nonlinear_viscous.map_or(0.0, |nv| nv.sigma_n),
        Param::NvExp => {
            let n = e.nonlinear_viscous.map_or(0.5, |nv| nv.n);
            let u =
                ((n - NV_EXP_RANGE.0) / (NV_EXP_RANGE.1 - NV_EXP_RANGE.0)).clamp(1e-6, 1.0 - 1e-6);
            (u / (1.0 - u)).ln()
        }
    }
}

fn set(m: &mut Model, p: Param, th: f64, sc: Scales) {
    let e = &mut m.effects;
    match p {
        Param::Mass => m.mass = th.max(MASS_MIN),
        Param::Fc => {
            let excess = m.fs - m.fc;
            m.fc = th.clamp(-200.0, 200.0).exp();
            m.fs = m.fc + excess.max(0.0);
        }
        // Fs ≤ 11·Fc and V ≥ 1 nm/s: beyond, the curve is a spike at v = 0
        // that no record resolves (a base fit once ran to Fs = 7e86 N with
        // V = 1e-87 m/s).
        Param::FsExcess => m.fs = m.fc + th.clamp(-200.0, 200.0).exp().min(FS_EXCESS_MAX * m.fc),
        Param::VStribeck => m.v_stribeck = th.clamp(-200.0, 200.0).exp().max(1e-9),
        Param::Delta => {
            let u = 1.0 / (1.0 + (-th.clamp(-40.0, 40.0)).exp());
            m.delta = DELTA_RANGE.0 + (DELTA_RANGE.1 - DELTA_RANGE.0) * u;
        }
        Param::Sigma => m.sigma = th.max(0.0),
        Param::ZMax => m.z_max = th.clamp(-200.0, 200.0).exp().min(sc.z_max),
        Param::F0 => e.offset = Some(Offset { f0: th }),
        Param::Asym => {
            e.asymmetry = Some(Asymmetry {
                a: th.clamp(-3.0, 3.0).tanh(),
            })
        }
        Param::RippleC | Param::RippleS | Param::RippleLambda => {
            let r = e.position_ripple.unwrap_or(PositionRipple {
                amplitude: 0.0,
                wavelength: 1.0,
                phase: 0.0,
            });
            let (mut c, mut s) = (r.amplitude * r.phase.cos(), r.amplitude * r.phase.sin());
            let mut lam = r.wavelength;
            match p {
                Param::RippleC => c = th,
                Param::RippleS => s = th,
                _ => lam = th.clamp(-200.0, 200.0).exp(),
            }
            e.position_ripple = Some(PositionRipple {
                amplitude: c.hypot(s),
                wavelength: lam,
                phase: s.atan2(c),
            });
        }
        Param::DwellDfs | Param::DwellGamma => {
            let mut d = e.dwell_stiction.unwrap_or(DwellStiction {
                delta_fs: 0.0,
                gamma: 1.0,
                v_rest: 1.0,
            });
            let v = th.clamp(-200.0, 200.0).exp();
            if p == Param::DwellDfs {
                d.delta_fs = v;
            } else {
                d.gamma = v.clamp(GAMMA_RANGE.0, sc.gamma);
            }
            e.dwell_stiction = Some(d);
        }
        Param::LagTau => {
            // τ_L below a millisecond is indistinguishable from no lag at
            // the sampling rates this is for; the bound keeps LM from
            // running off to τ_L → 0.
            e.frictional_lag = Some(FrictionalLag {
                tau_l: th.clamp(1e-3f64.ln(), 100f64.ln()).exp(),
            })
        }
        Param::DriftBeta => {
            e.drift = Some(Drift {
                beta: th / sc.t_span,
            })
        }
        Param::SigmaN | Param::NvExp => {
            let mut nv = e.nonlinear_viscous.unwrap_or(NonlinearViscous {
                sigma_n: 0.0,
                n: 0.5,
            });
            if p == Param::SigmaN {
                nv.sigma_n = th.max(0.0);
            } else {
                let u = 1.0 / (1.0 + (-th.clamp(-40.0, 40.0)).exp());
                nv.n = NV_EXP_RANGE.0 + (NV_EXP_RANGE.1 - NV_EXP_RANGE.0) * u;
            }
            e.nonlinear_viscous = Some(nv);
        }
    }
}

/// What the parameter maps take from the record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scales {
    /// Length of the record [s]: the drift rate is fitted as `β·t_span`.
    pub t_span: f64,
    /// Longest presliding distance `z_max` a fit may reach [m]
    /// ([`presliding_cap`]).
    pub z_max: f64,
    /// Longest dwell time constant `γ` a fit may reach [s]
    /// ([`dwell_gamma_cap`]).
    pub gamma: f64,
}

impl Scales {
    /// No record behind the parameters (steady-state curves): `t_span` of
    /// 1 s, no bound on `z_max`.
    pub const UNIT: Scales = Scales {
        t_span: 1.0,
        z_max: f64::INFINITY,
        gamma: GAMMA_RANGE.1,
    };

    /// The scales of the record `p` for a fit from `m0`.
    pub fn of(p: &Prepared, m0: &Model) -> Scales {
        Scales {
            t_span: (p.t[p.len() - 1] - p.t[0]).max(1e-9),
            z_max: presliding_cap(p),
            gamma: dwell_gamma_cap(p, m0),
        }
    }
}

/// `BIC = n·ln(rms²) + k·ln(n)` of a fit with `k` parameters whose RMS
/// [N] over `n` points is `rms` (the one criterion every selection of the
/// lab scores with).
pub fn bic(n: usize, rms: f64, k: usize) -> f64 {
    let n = n.max(1) as f64;
    n * (rms * rms).max(1e-300).ln() + k as f64 * n.ln()
}

/// The parameter vector of `m` for `params`.
pub fn encode(m: &Model, params: &[Param], sc: Scales) -> Vec<f64> {
    params.iter().map(|&p| get(m, p, sc)).collect()
}

/// `m` with the parameter vector `th` applied.
pub fn decode(m: &Model, params: &[Param], th: &[f64], sc: Scales) -> Model {
    let mut out = m.clone();
    for (&p, &x) in params.iter().zip(th) {
        set(&mut out, p, x, sc);
    }
    out
}

/// Fit settings.
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    /// Most Levenberg–Marquardt iterations.
    pub max_iter: usize,
    /// Stop when an accepted step lowers the cost by less than this fraction.
    pub rel_tol: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            max_iter: 40,
            rel_tol: 1e-6,
        }
    }
}

/// Outcome of a fit.
#[derive(Clone, Debug)]
pub struct FitResult {
    /// The fitted model.
    pub model: Model,
    /// Weighted training cost `Σ w·r²`.
    pub cost: f64,
    /// Passes along the record used.
    pub passes: usize,
}

/// The training samples of a record and the roots `√w` of their weights
/// (taken once per fit, not per pass).
struct Training {
    idx: Vec<usize>,
    root_weight: Vec<f64>,
}

impl Training {
    fn of(p: &Prepared) -> Training {
        let idx: Vec<usize> = p.valid().filter(|&i| !p.held_out[i]).collect();
        let root_weight = idx.iter().map(|&i| p.weight[i].sqrt()).collect();
        Training { idx, root_weight }
    }

    /// `√w·s` at the training samples of the per-sample series `s`.
    fn weigh(&self, s: &[f64]) -> Vec<f64> {
        self.idx
            .iter()
            .zip(&self.root_weight)
            .map(|(&i, w)| w * s[i])
            .collect()
    }
}

/// The training residual vector `√w·r` of `m`.
fn train_vec(p: &Prepared, m: &Model, training: &Training) -> Vec<f64> {
    training.weigh(&p.residual_on(m, false))
}

/// Weighted training cost of `m`.
pub fn train_cost(p: &Prepared, m: &Model) -> f64 {
    train_vec(p, m, &Training::of(p))
        .iter()
        .map(|e| e * e)
        .sum()
}

/// Analytic Jacobian column `∂r/∂θ` for parameters that enter linearly.
fn analytic_column(p: &Prepared, m: &Model, par: Param, training: &Training) -> Option<Vec<f64>> {
    let negated = |s: &[f64]| -> Vec<f64> { training.weigh(s).into_iter().map(|e| -e).collect() };
    // The force's derivative is 0 at a still sample, where the friction is
    // the measured force whatever the model (`Prepared::friction`): the
    // filtered columns are kept by the record ([`Prepared::fixed_column`]).
    let lam = || {
        m.effects
            .position_ripple
            .map_or(1.0, |r| r.wavelength)
            .to_bits()
    };
    let which = match par {
        Param::Mass => return Some(negated(&p.a)),
        Param::Sigma => FixedColumn::Velocity,
        Param::F0 => FixedColumn::Moving,
        Param::SigmaN => {
            FixedColumn::SignedPower(m.effects.nonlinear_viscous.map_or(0.5, |nv| nv.n).to_bits())
        }
        Param::RippleC => FixedColumn::RippleSin(lam()),
        Param::RippleS => FixedColumn::RippleCos(lam()),
        _ => return None,
    };
    Some(negated(&p.fixed_column(which)))
}

/// Encoder counts of the shortest [`presliding_cap`] (the longest start of
/// the base model's grid).
pub const PRESLIDING_CAP_COUNTS: f64 = 640.0;

/// The longest presliding distance `z_max` [m] a fit may reach on `p`: the
/// range of its positions, at least [`PRESLIDING_CAP_COUNTS`] encoder
/// counts. A longer one never reaches gross sliding on the record, so the
/// record cannot tell it from any other long one; it is where a fit goes
/// when the branch memory carries the friction over the whole stroke. On
/// development record 2400158 (point-to-point moves over 39 mm) the base
/// fit ran to `z_max` = 66 m with Fc = 8e-13 N (true: 1.9 µm and 25.6 N),
/// and no candidate could leave that basin.
pub fn presliding_cap(p: &Prepared) -> f64 {
    p.travel().max(PRESLIDING_CAP_COUNTS * p.resolution)
}

/// Range of the dwell time constant `γ` [s] (`dwell_stiction`): from
/// 5 ms, below which a rest of a few samples saturates it, to 100 s, or
/// [`dwell_gamma_cap`] where that is shorter. The lower end, and 100 s,
/// count as bounds ([`crate::diagnose::degenerate`]).
pub const GAMMA_RANGE: (f64, f64) = (5e-3, 100.0);

/// [`dwell_gamma_cap`] in units of the record's longest rest.
pub const GAMMA_CAP_RESTS: f64 = 4.0;

/// The longest dwell time constant `γ` [s] a fit from `m0` may reach on
/// `p`: [`GAMMA_CAP_RESTS`] times the longest rest that `m0`'s dwell
/// clock counts in the record ([`Prepared::rests`], at `m0`'s `v_rest`,
/// which no fit moves), at most 100 s; 100 s without the effect or
/// without such a rest.
///
/// Past a few rests the record shows Fs rising with the rest length but
/// not saturating: `ΔFs·t_d/(t_d + γ)` is then `(ΔFs/γ)·t_d` within the
/// curvature the longest rest still shows, and only the ratio, the rise
/// rate, is resolved. The fit follows it to the top of the range, where
/// `ΔFs` grows with `γ` (on the suite-like record 9600045, rests of
/// 0.13–1.6 s, the fit ended at γ = 99.9 s with ΔFs = 281 N on an axis
/// of Fc = 2.4 N, and the candidate that took 74 % of the gap was
/// rejected as a parameter at its bound). As with [`presliding_cap`],
/// the record cannot tell a longer `γ` from any other long one; a fit at
/// the cap names the effect with its rise rate, and the report says that
/// the saturation is not seen.
pub fn dwell_gamma_cap(p: &Prepared, m0: &Model) -> f64 {
    m0.effects
        .dwell_stiction
        .and_then(|d| p.rests(d.v_rest))
        .map_or(GAMMA_RANGE.1, |(_, longest, _)| gamma_cap_of(longest))
}

/// [`dwell_gamma_cap`] of a record whose longest rest is `longest` [s].
pub fn gamma_cap_of(longest: f64) -> f64 {
    (GAMMA_CAP_RESTS * longest).min(GAMMA_RANGE.1)
}

/// Levenberg–Marquardt fit of the parameters `params` of `m0` on the
/// training set, in the [`Scales`] of the record for `m0` (`z_max` at
/// most [`presliding_cap`], `γ` at most [`dwell_gamma_cap`]); `tick` is
/// called once per iteration (for progress).
pub fn fit(
    p: &Prepared,
    m0: &Model,
    params: &[Param],
    opts: &FitOptions,
    tick: &mut dyn FnMut(usize),
) -> FitResult {
    let scales = Scales::of(p, m0);
    let training = Training::of(p);
    let th0 = encode(m0, params, scales);
    let problem = ModelProblem {
        p,
        m0,
        params,
        training: &training,
        scales,
    };
    let (th, cost, passes) = levenberg_marquardt(&problem, th0, opts, tick);
    FitResult {
        model: decode(m0, params, &th, scales),
        cost,
        passes,
    }
}

/// A least-squares problem for [`levenberg_marquardt`]: a residual vector
/// of a parameter vector, and optionally analytic Jacobian columns.
pub trait Residuals: Sync {
    /// The weighted residual vector at `th` (its squared sum is the cost).
    fn residuals(&self, th: &[f64]) -> Vec<f64>;

    /// `∂e/∂θ_j` at `th` when known in closed form; `None`: forward
    /// differences.
    fn column(&self, j: usize, th: &[f64]) -> Option<Vec<f64>> {
        let _ = (j, th);
        None
    }
}

/// The record fit as a [`Residuals`] problem.
struct ModelProblem<'a> {
    p: &'a Prepared,
    m0: &'a Model,
    params: &'a [Param],
    training: &'a Training,
    scales: Scales,
}

impl Residuals for ModelProblem<'_> {
    fn residuals(&self, th: &[f64]) -> Vec<f64> {
        let m = decode(self.m0, self.params, th, self.scales);
        train_vec(self.p, &m, self.training)
    }

    fn column(&self, j: usize, th: &[f64]) -> Option<Vec<f64>> {
        let m = decode(self.m0, self.params, th, self.scales);
        analytic_column(self.p, &m, *self.params.get(j)?, self.training)
    }
}

/// Levenberg–Marquardt (Marquardt's diagonal scaling) from `th0`: the one
/// solver of the lab. Returns the parameters, the cost `Σ e²` and the
/// number of residual evaluations.
pub fn levenberg_marquardt(
    problem: &dyn Residuals,
    th0: Vec<f64>,
    opts: &FitOptions,
    tick: &mut dyn FnMut(usize),
) -> (Vec<f64>, f64, usize) {
    let np = th0.len();
    let mut th = th0;
    let mut e = problem.residuals(&th);
    let mut passes = 1;
    let mut cost: f64 = e.iter().map(|v| v * v).sum();
    let mut lambda = 1e-3;
    for it in 0..opts.max_iter {
        tick(it);
        // The columns are independent: computed in parallel, each exactly
        // as alone (the fit does not depend on the number of threads).
        let cols: Vec<(Vec<f64>, usize)> = (0..np)
            .into_par_iter()
            .map(|j| {
                if let Some(c) = problem.column(j, &th) {
                    return (c, 0);
                }
                let h = 1e-4 * th[j].abs().max(1.0);
                let mut th2 = th.clone();
                th2[j] += h;
                let e2 = problem.residuals(&th2);
                (e2.iter().zip(&e).map(|(a, b)| (a - b) / h).collect(), 1)
            })
            .collect();
        passes += cols.iter().map(|c| c.1).sum::<usize>();
        let cols: Vec<Vec<f64>> = cols.into_iter().map(|c| c.0).collect();
        let (a, ate) = crate::linalg::normal_equations(&cols, &e);
        let g: Vec<f64> = ate.iter().map(|s| -s).collect();
        let mut improved = false;
        let mut rel = 0.0;
        while lambda < 1e10 {
            let mut aa = a.clone();
            for (d, row) in aa.iter_mut().enumerate() {
                row[d] += lambda * a[d][d].max(1e-12 * (1.0 + a[d][d]));
            }
            let Some(step) = crate::linalg::solve_spd(&aa, &g) else {
                lambda *= 10.0;
                continue;
            };
            let th2: Vec<f64> = th.iter().zip(&step).map(|(a, b)| a + b).collect();
            let e2 = problem.residuals(&th2);
            passes += 1;
            let c2: f64 = e2.iter().map(|v| v * v).sum();
            if c2.is_finite() && c2 < cost {
                rel = (cost - c2) / cost;
                th = th2;
                e = e2;
                cost = c2;
                lambda = (lambda / 3.0).max(1e-9);
                improved = true;
                break;
            }
            lambda *= 4.0;
        }
        if !improved || rel < opts.rel_tol {
            break;
        }
    }
    (th, cost, passes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::residual::tests::record;
    use std::f64::consts::PI;

    /// A 2 mm sinusoid (1 Hz, 2 s at 1 kHz) read by an encoder of `q` [m].
    fn stroke(q: f64, amplitude: f64) -> Prepared {
        let w = 2.0 * PI;
        let rec = record(2000, 1e-3, |t| (amplitude * (w * t).sin() / q).floor() * q);
        Prepared::new(&rec, 4)
    }

    /// The fitted presliding distance never exceeds the record's travel
    /// (here 2 mm, more than 640 counts), however long the start.
    #[test]
    fn presliding_distance_is_at_most_the_travel() {
        let p = stroke(1e-6, 1e-3);
        let cap = presliding_cap(&p);
        assert!((cap - p.travel()).abs() < 1e-12 && (cap - 2e-3).abs() < 2e-5);
        let mut m = crate::diagnose::fig5_model();
        m.z_max = 50.0; // metres: far beyond the stroke
        for max_iter in [0, 40] {
            let opts = FitOptions {
                max_iter,
                ..FitOptions::default()
            };
            let fitted = fit(&p, &m, &[Param::ZMax, Param::Fc], &opts, &mut |_| {});
            assert!(fitted.model.z_max <= cap, "z_max {}", fitted.model.z_max);
        }
        // A record that hardly moves keeps the base grid's longest start.
        let q = stroke(1e-6, 1e-6);
        assert!((presliding_cap(&q) - PRESLIDING_CAP_COUNTS * q.resolution).abs() < 1e-15);
    }
}
