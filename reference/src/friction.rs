//! Friction with the effect catalogue composed, MODEL.md §5 on top of §2–§3.
//!
//! Per sample `(t, x, v)`:
//!
//! ```text
//! sc  = (1 + a·d)·(1 + β·(t − t0))          d = 0 counts as no asymmetry
//! Fc' = Fc·sc
//! Fs' = Fs·sc + ΔFs·t_d/(t_d + γ)
//! S   = Fc' + (Fs' − Fc')·exp(−(|v_s|/V)^δ),  v_s = v_l with frictional_lag, else v
//! H   = the §3 one-turning-point rule (crate::Presliding) with this S
//! F   = H + σ·v + σ_n·sgn(v)·|v|^n + F0 + A·sin(2π·x/λ + φ)
//! ```
//!
//! `d` is the branch direction after this sample's presliding update (so the
//! first motion and a confirmed reversal use the new direction's scaling).
//!
//! * `dwell_stiction`: `t_d` is the length of the most recent interval with
//!   `|v| <= v_rest`, measured on the samples: it is `t − t_start` while at
//!   rest (`t_start` the first sample of the rest), held once `|v| > v_rest`,
//!   and reset to 0 at the first sample of a new rest. The record starts at
//!   rest: `t_start = t0`, so `t_d = 0` at a first sample taken at `t0`.
//!   A caller may give the speed the clock compares with `v_rest`
//!   ([`SampleTerms::rest_speed`]) where `|v|` of the sample is not the best
//!   estimate of it.
//! * `frictional_lag`: `v_l = v` at the first sample; between samples
//!   `τ_L·dv_l/dt = v − v_l` is integrated exactly with `v` linear between the
//!   two samples (first-order hold):
//!   `v_l ← e·v_l + v₁ − e·v₀ − (v₁ − v₀)·(1 − e)·τ_L/h`, `e = exp(−h/τ_L)`.
//! * `drift`: `t` is counted from `t0` given to [`Friction::new`].

use crate::curves::{stribeck_decay, stribeck_from_decay};
use crate::model::Model;
use crate::presliding::Presliding;
use std::f64::consts::PI;

/// Per-sample terms of [`Friction::update_with`]; `None`: computed.
/// `decay` depends on the curve's velocity (`v` [m/s], or with
/// `frictional_lag` the lagged `v_l`, which depends on the velocities so
/// far and `τ_L` alone) and the model's shape, `speed_pow` only on `v` and
/// the shape, `ripple_sin` only on its position `x` [m] and the
/// ripple's wavelength and phase (a cache of them gives the same force);
/// `rest_speed` is an input of its own, the speed estimate the
/// `dwell_stiction` clock runs on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SampleTerms {
    /// The Stribeck decay `exp(−(|v_s|/V)^δ)` ([`stribeck_decay`]) at the
    /// curve's velocity: `v_s = v`, or with `frictional_lag` the lagged
    /// velocity `v_l` (a [`LagFilter`] over the same samples).
    pub decay: Option<f64>,
    /// `|v|^n` of `nonlinear_viscous`.
    pub speed_pow: Option<f64>,
    /// The speed [m/s] that the `dwell_stiction` clock compares with
    /// `v_rest`, where it is estimated otherwise than `|v|` (on measured
    /// data, from the time the axis takes to cross an encoder count);
    /// `None`: `|v|`.
    pub rest_speed: Option<f64>,
    /// `sin(2π·x/λ + φ)` of `position_ripple` at the sample's position.
    pub ripple_sin: Option<f64>,
}

/// The lagged velocity `v_l` [m/s] of `frictional_lag` (MODEL.md §5):
/// `v_l = v` at the first sample, then `τ_L·dv_l/dt = v − v_l` integrated
/// exactly between samples with `v` linear between them (see the module
/// documentation). [`Friction`] runs one; a caller that walks many models
/// with the same `τ_L` over the same samples can run it once and give
/// [`SampleTerms::decay`] (the same bits).
#[derive(Clone, Debug, PartialEq)]
pub struct LagFilter {
    first: bool,
    t_prev: f64,
    v_prev: f64,
    v_l: f64,
    /// The step `(h, τ_L)` and its coefficients
    /// `(exp(−h/τ_L), (1 − exp(−h/τ_L))·τ_L/h)` for that step: the same
    /// step at every sample of a uniformly sampled record (zeros before
    /// the first: h and τ_L are positive).
    step: (f64, f64, f64, f64),
}

impl LagFilter {
    /// The filter before the first sample: time `t0` [s], velocity `v0`
    /// [m/s].
    pub fn new(t0: f64, v0: f64) -> Self {
        LagFilter {
            first: true,
            t_prev: t0,
            v_prev: v0,
            v_l: v0,
            step: (0.0, 0.0, 0.0, 0.0),
        }
    }

    /// Takes the sample at time `t` [s] with velocity `v` [m/s] for the
    /// lag `tau_l` [s] (`None`: no lag, `v_l = v`) and returns `v_l` [m/s].
    pub fn update(&mut self, tau_l: Option<f64>, t: f64, v: f64) -> f64 {
        match tau_l {
            Some(tau_l) if !self.first => {
                let h = t - self.t_prev;
                if h > 0.0 {
                    let (h0, tau0, _, _) = self.step;
                    if h != h0 || tau_l != tau0 {
                        let r = h / tau_l;
                        let ex = (-r).exp();
                        let phi = -(-r).exp_m1() / r; // (1 − e)·τ/h
                        self.step = (h, tau_l, ex, phi);
                    }
                    let (_, _, ex, phi) = self.step;
                    self.v_l = ex * self.v_l + v - ex * self.v_prev - (v - self.v_prev) * phi;
                }
            }
            _ => self.v_l = v,
        }
        self.first = false;
        self.t_prev = t;
        self.v_prev = v;
        self.v_l
    }

    /// `v_l` [m/s] after the last update (`v0` before any).
    pub fn lagged_velocity(&self) -> f64 {
        self.v_l
    }
}

/// Friction force of the full §5 composition, with its memory.
#[derive(Clone, Debug, PartialEq)]
pub struct Friction {
    pre: Presliding,
    t0: f64,
    lag: LagFilter,
    resting: bool,
    rest_start: f64,
    t_d: f64,
    f: f64,
}

impl Friction {
    /// Friction at the start of a record: time `t0` [s], position `x0` [m]
    /// (the idle presliding state sits there), velocity `v0` [m/s] (initial
    /// lag state). No sample is taken; call [`Friction::update`] for each
    /// sample, the first one typically at `(t0, x0, v0)`. `m` is not needed
    /// yet (every update takes the model) and is accepted for symmetry.
    pub fn new(m: &Model, t0: f64, x0: f64, v0: f64) -> Self {
        let _ = m;
        Friction {
            pre: Presliding::new(x0),
            t0,
            lag: LagFilter::new(t0, v0),
            resting: true,
            rest_start: t0,
            t_d: 0.0,
            f: 0.0,
        }
    }

    /// Takes the sample at time `t` [s], position `x` [m], velocity `v` [m/s]
    /// and returns the friction force `F` [N] of the §5 composition.
    pub fn update(&mut self, m: &Model, t: f64, x: f64, v: f64) -> f64 {
        self.update_with(m, t, x, v, SampleTerms::default())
    }

    /// [`Friction::update`] with the terms of `terms` given instead of
    /// computed (the same result to the last bit when they are those of
    /// `m` and `v`): a caller that runs many models of one shape over the
    /// same velocities computes them once. Terms that do not belong to
    /// `m` and `v` give a wrong force. [`SampleTerms::rest_speed`] is the
    /// exception: it replaces `|v|` in the `dwell_stiction` clock alone.
    pub fn update_with(&mut self, m: &Model, t: f64, x: f64, v: f64, terms: SampleTerms) -> f64 {
        let e = &m.effects;
        let v_l = self.lag.update(e.frictional_lag.map(|l| l.tau_l), t, v);
        // Dwell time.
        if let Some(dw) = &e.dwell_stiction {
            if terms.rest_speed.unwrap_or(v.abs()) <= dw.v_rest {
                if !self.resting {
                    self.resting = true;
                    self.rest_start = t;
                }
                self.t_d = (t - self.rest_start).max(0.0);
            } else {
                self.resting = false;
            }
        }

        let drift = e.drift.map_or(1.0, |d| 1.0 + d.beta * (t - self.t0));
        let asym = e.asymmetry.map_or(0.0, |a| a.a);
        let dwell = e
            .dwell_stiction
            .map_or(0.0, |dw| dw.delta_fs * self.t_d / (self.t_d + dw.gamma));
        // With `frictional_lag` the curve sees the lagged velocity.
        let v_s = if e.frictional_lag.is_some() { v_l } else { v };
        let s_of = |d: i8| {
            let sc = (1.0 + asym * f64::from(d)) * drift;
            stribeck_from_decay(m.fc * sc, m.fs * sc + dwell, || {
                terms
                    .decay
                    .unwrap_or_else(|| stribeck_decay(m.v_stribeck, m.delta, v_s))
            })
        };
        let h = self.pre.step(x, m.z_max, m.epsilon, s_of);
        let mut f = h + m.sigma * v;
        if let Some(o) = &e.offset {
            f += o.f0;
        }
        if let Some(nv) = &e.nonlinear_viscous {
            let speed_pow = terms.speed_pow.unwrap_or_else(|| v.abs().powf(nv.n));
            f += nv.sigma_n * v.signum() * speed_pow;
        }
        if let Some(r) = &e.position_ripple {
            let sin = terms
                .ripple_sin
                .unwrap_or_else(|| (2.0 * PI * x / r.wavelength + r.phase).sin());
            f += r.amplitude * sin;
        }
        self.f = f;
        f
    }

    /// Re-anchors the presliding memory at rest: idle at position `x` [m]
    /// with dry friction `h` [N] (see [`Presliding::anchor`]); the other
    /// memories (dwell time, lagged velocity) are kept. `F` becomes `h` plus
    /// the additive terms of the last update.
    pub fn anchor(&mut self, x: f64, h: f64) {
        self.f += h - self.pre.dry();
        self.pre.anchor(x, h);
    }

    /// Friction force `F` [N] returned by the last update (0 before any).
    pub fn force(&self) -> f64 {
        self.f
    }

    /// Dry (hysteretic) part `H` [N] after the last update.
    pub fn dry(&self) -> f64 {
        self.pre.dry()
    }

    /// Branch direction `d` (−1, 0, +1).
    pub fn direction(&self) -> i8 {
        self.pre.direction()
    }

    /// The presliding memory (§3).
    pub fn presliding(&self) -> &Presliding {
        &self.pre
    }

    /// Dwell time `t_d` [s] (0 without `dwell_stiction`).
    pub fn dwell_time(&self) -> f64 {
        self.t_d
    }

    /// Lagged velocity `v_l` [m/s] after the last update (equal to `v`
    /// without `frictional_lag`).
    pub fn lagged_velocity(&self) -> f64 {
        self.lag.lagged_velocity()
    }
}
