//! Full-dynamics simulation of the plant `m·ẍ = u − F` (MODEL.md §1, §4),
//! with the friction memory of §3 (and the effects of §5 for [`simulate`]).
//!
//! # Integration scheme and why
//!
//! The state is `(x, v)`; the friction memory (turning point, extremum,
//! `H_r`, dwell, lag) is updated only at accepted step ends, each of which is
//! a *sample* of the same rule as [`crate::Presliding::update`] /
//! [`crate::Friction::update`]; the stages inside a step evaluate `F` on a
//! copy of the committed memory. The integrator is the explicit embedded
//! Dormand–Prince 5(4) pair with its 4th-order dense output, per-component
//! mixed tolerances (`tol·z_max` on `x`, `tol·min(V, √(Fs·z_max/m))` on `v`,
//! relative `tol`) and standard step-size control.
//!
//! * **Events.** Every zero of `v` is located (bisection on the dense output,
//!   then the step is re-taken up to the event) and a sample with `v = 0` is
//!   committed there, so `x` is monotone inside every step and the
//!   one-turning-point memory sees each extremum exactly. With `ε > 0` the
//!   confirmation of a pending reversal (`d·(x_ext − x) = ε`, where `H`
//!   jumps), the return to `x_ext` from a pending reversal and (with
//!   `dwell_stiction`) `|v| = v_rest` are located the same way. The
//!   break-away instant `w = w_b` is located and refined by one Newton step
//!   in time. Hence the right-hand side is smooth inside every step except
//!   for the `w → 0` singularity below.
//! * **Stiffness.** Right after a turning point `dH/dx = (d·S − H_r)·(−ln w)/
//!   z_max` grows without bound, but only logarithmically: the local
//!   frequency `√(dH/dx / m)` at `w = 1e-16` is only ≈ 6× that at `w = 0.5`.
//!   The explicit stability limit `h ≲ 3.3/ω` is therefore of the same order
//!   as the step needed anyway to resolve the presliding oscillation that the
//!   negative damping `∂H/∂v = g(w)·S'(v) < 0` excites (§8); an implicit
//!   scheme would buy nothing, since those oscillations and their turning
//!   points must be resolved. The `w·ln w` kink at each turning point is
//!   handled by step-size control (small steps for a short time).
//!
//! # Convergence
//!
//! The step size of DP5(4) scales as `tol^{1/5}`, so dividing `tol` by 32
//! halves the steps. Measured on `t_ba` (m = 1 kg, Fc = 1 N, Fs = 1.5 N,
//! V = 1 mm/s, z_max = 10 µm, w_b = 0.95), `tol` = 3.1e-8 … 9.5e-13:
//!
//! * δ = 2, k = 1 N/s: successive differences 1.5e-5, 4.4e-7, 1.3e-8 s
//!   (ratios 34, 35 ≈ 2⁵: fifth order); the finest two agree to 8e-9
//!   relative.
//! * δ = 1, k = 10 N/s (turning points during presliding): differences
//!   2.2e-7, 1.0e-8, 3.5e-9 s; the finest two agree to 2.6e-8 relative, and
//!   two more levels give 1.5e-10, 1.4e-11 s.
//!
//! Where presliding is self-excited (§8; e.g. δ = 1, m = 1 kg, k ≲ 1 N/s,
//! Π ≈ 5.5) the creep breaks up into micro stick-slip whose phase depends on
//! every rounding error: `t_ba` is then reproducible only to ≈ 0.5 %, for any
//! integrator (a fixed-step RK4 shows the same scatter). The default
//! `tol = 1e-10` is far below that and costs ≲ 0.1 s per break-away in
//! release builds.

use crate::friction::Friction;
use crate::model::{ArgumentError, Model, ModelError};
use crate::presliding::Presliding;
use std::fmt;

/// Result of [`simulate_break_away`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DynamicBreakAway {
    /// Actuation force at break-away `k·t_ba` [N].
    pub f_ba: f64,
    /// Instant [s] at which `w` first reaches `w_b`.
    pub t_ba: f64,
    /// Velocity [m/s] at that instant.
    pub v_b: f64,
}

/// One output sample of [`simulate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Time [s].
    pub t: f64,
    /// Position [m].
    pub x: f64,
    /// Velocity [m/s].
    pub v: f64,
    /// Actuation force `u(t)` [N].
    pub u: f64,
    /// Friction force `F` [N] (the §5 composition).
    pub f: f64,
}

/// Integrator settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimOptions {
    /// Tolerance [-]: relative tolerance and scale of the absolute ones
    /// (`tol·z_max` [m] on `x`, `tol·min(V, √(Fs·z_max/m))` [m/s] on `v`).
    pub tol: f64,
    /// Bound on the number of (accepted + rejected) steps.
    pub max_steps: usize,
}

impl Default for SimOptions {
    /// `tol = 1e-10`, `max_steps = 50_000_000`.
    fn default() -> Self {
        SimOptions {
            tol: 1e-10,
            max_steps: 50_000_000,
        }
    }
}

/// Failure of a simulation.
#[derive(Clone, Debug, PartialEq)]
pub enum SimError {
    /// An argument (or the model's `z_max`) is out of range.
    Argument(ArgumentError),
    /// The model fails [`Model::validate`].
    Model(ModelError),
    /// `w` did not reach `w_b` before `t_limit` [s] (= 100·Fs/k).
    NoBreakAway {
        /// The time bound [s].
        t_limit: f64,
    },
    /// The step count bound was hit at time `t` [s].
    TooManySteps {
        /// Time reached [s].
        t: f64,
        /// Steps taken.
        steps: usize,
    },
    /// The step size underflowed or the state became non-finite at `t` [s]
    /// (e.g. a non-finite `u(t)`).
    Breakdown {
        /// Time reached [s].
        t: f64,
    },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Argument(e) => e.fmt(f),
            SimError::Model(e) => write!(f, "invalid model: {e}"),
            SimError::NoBreakAway { t_limit } => {
                write!(f, "no break-away before t = {t_limit:?} s")
            }
            SimError::TooManySteps { t, steps } => {
                write!(f, "step bound ({steps}) hit at t = {t:?} s")
            }
            SimError::Breakdown { t } => {
                write!(
                    f,
                    "integration broke down (step underflow or non-finite state) at t = {t:?} s"
                )
            }
        }
    }
}

impl std::error::Error for SimError {}

/// A friction law with memory, sampled at accepted steps.
trait Law: Clone {
    fn sample(&mut self, m: &Model, t: f64, x: f64, v: f64) -> f64;
    fn pres(&self) -> &Presliding;
}

impl Law for Presliding {
    fn sample(&mut self, m: &Model, _t: f64, x: f64, v: f64) -> f64 {
        self.update(m, x, v)
    }
    fn pres(&self) -> &Presliding {
        self
    }
}

impl Law for Friction {
    fn sample(&mut self, m: &Model, t: f64, x: f64, v: f64) -> f64 {
        self.update(m, t, x, v)
    }
    fn pres(&self) -> &Presliding {
        self.presliding()
    }
}

// Dormand–Prince 5(4) tableau.
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// 5th-order weights minus 4th-order weights (error estimate).
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// Dense-output coefficients (Hairer, Nørsett & Wanner, `dopri5`).
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// One Dormand–Prince step from `(t, y)` with step `h`.
struct Trial {
    h: f64,
    y0: [f64; 2],
    y1: [f64; 2],
    k: [[f64; 2]; 7],
    err: f64,
}

impl Trial {
    /// Dense output at `θ ∈ [0, 1]`.
    fn at(&self, theta: f64) -> [f64; 2] {
        let mut out = [0.0; 2];
        let t1 = 1.0 - theta;
        for (i, o) in out.iter_mut().enumerate() {
            let ydiff = self.y1[i] - self.y0[i];
            let bspl = self.h * self.k[0][i] - ydiff;
            let r4 = ydiff - self.h * self.k[6][i] - bspl;
            let r5 = self.h * (0..7).map(|j| D[j] * self.k[j][i]).sum::<f64>();
            *o = self.y0[i] + theta * (ydiff + t1 * (bspl + theta * (r4 + t1 * r5)));
        }
        out
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Event {
    /// `v = 0`.
    Turn,
    /// Pending reversal confirmed at `x` = this boundary.
    Confirm(f64),
    /// Return to `x_ext` from a pending reversal.
    Return(f64),
    /// `|v| = v_rest` (dwell).
    Rest,
    /// `w = w_b`.
    BreakAway,
}

struct Integrator<'a, L: Law, U: Fn(f64) -> f64> {
    m: &'a Model,
    u: U,
    law: L,
    t: f64,
    y: [f64; 2],
    h: f64,
    h_max: f64,
    atol: [f64; 2],
    rtol: f64,
    steps: usize,
    max_steps: usize,
    /// `w_b` when locating break-away.
    w_b: Option<f64>,
    /// `v_rest` when locating dwell boundaries.
    v_rest: Option<f64>,
}

/// Outcome of one accepted step.
enum Stepped {
    Normal,
    BreakAway(DynamicBreakAway),
}

fn sgn(a: f64) -> f64 {
    if a > 0.0 {
        1.0
    } else if a < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Smallest `θ` in `(lo, hi]` with `p(θ)` (given `p(hi)`, `!p(lo)`).
fn bisect(mut lo: f64, mut hi: f64, p: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi || hi - lo < 1e-14 {
            break;
        }
        if p(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

impl<L: Law, U: Fn(f64) -> f64> Integrator<'_, L, U> {
    fn rhs(&self, t: f64, y: [f64; 2]) -> [f64; 2] {
        let mut law = self.law.clone();
        let f = law.sample(self.m, t, y[0], y[1]);
        [y[1], ((self.u)(t) - f) / self.m.mass]
    }

    fn trial(&self, h: f64) -> Trial {
        let mut k = [[0.0; 2]; 7];
        k[0] = self.rhs(self.t, self.y);
        for s in 1..7 {
            let mut ys = self.y;
            for (i, y) in ys.iter_mut().enumerate() {
                *y += h * (0..s).map(|j| A[s][j] * k[j][i]).sum::<f64>();
            }
            k[s] = self.rhs(self.t + C[s] * h, ys);
        }
        let mut y1 = self.y;
        for (i, y) in y1.iter_mut().enumerate() {
            *y += h * (0..6).map(|j| A[6][j] * k[j][i]).sum::<f64>();
        }
        let mut acc = 0.0;
        for i in 0..2 {
            let e = h * (0..7).map(|j| E[j] * k[j][i]).sum::<f64>();
            let sc = self.atol[i] + self.rtol * self.y[i].abs().max(y1[i].abs());
            acc += (e / sc) * (e / sc);
        }
        Trial {
            h,
            y0: self.y,
            y1,
            k,
            err: (0.5 * acc).sqrt(),
        }
    }

    /// Earliest event inside an acceptable trial step: `(θ, event)`.
    fn find_event(&self, tr: &Trial) -> Option<(f64, Event)> {
        let p = self.law.pres();
        let d = f64::from(p.direction());
        let x0 = tr.y0[0];
        let x1 = tr.y1[0];
        let v0 = tr.y0[1];
        let s = if v0 != 0.0 {
            sgn(v0)
        } else if tr.k[0][1] != 0.0 {
            sgn(tr.k[0][1])
        } else {
            sgn(tr.y1[1])
        };
        let mut best: Option<(f64, Event)> = None;
        let mut offer = |theta: f64, ev: Event| {
            if best.is_none_or(|(b, _)| theta < b) {
                best = Some((theta, ev));
            }
        };
        // v = 0.
        if s != 0.0 {
            let mut prev = 0.0;
            for th in [0.25, 0.5, 0.75, 1.0] {
                let v = if th == 1.0 { tr.y1[1] } else { tr.at(th)[1] };
                if s * v <= 0.0 {
                    offer(bisect(prev, th, |q| s * tr.at(q)[1] <= 0.0), Event::Turn);
                    break;
                }
                prev = th;
            }
        }
        let eps = self.m.epsilon;
        if eps > 0.0 && d != 0.0 {
            let x_ext = p.extremum();
            let back = |x: f64| d * (x_ext - x);
            if back(x0) <= eps && back(x1) > eps {
                let th = bisect(0.0, 1.0, |q| back(tr.at(q)[0]) > eps);
                offer(th, Event::Confirm(x_ext - d * eps));
            }
            if back(x0) > 0.0 && back(x1) <= 0.0 {
                let th = bisect(0.0, 1.0, |q| back(tr.at(q)[0]) <= 0.0);
                offer(th, Event::Return(x_ext));
            }
        }
        if let Some(w_b) = self.w_b {
            let dir = if d != 0.0 { d } else { s };
            if dir != 0.0 && s == dir {
                let x_r = p.turning_point();
                let w = |x: f64| dir * (x - x_r) / self.m.z_max;
                if w(x0) < w_b && w(x1) >= w_b {
                    let th = bisect(0.0, 1.0, |q| w(tr.at(q)[0]) >= w_b);
                    offer(th, Event::BreakAway);
                }
            }
        }
        if let Some(vr) = self.v_rest {
            let rest0 = v0.abs() <= vr;
            if (tr.y1[1].abs() <= vr) != rest0 {
                let th = bisect(0.0, 1.0, |q| (tr.at(q)[1].abs() <= vr) != rest0);
                offer(th, Event::Rest);
            }
        }
        best
    }

    fn commit(&mut self, t: f64, y: [f64; 2]) {
        self.t = t;
        self.y = y;
        self.law.sample(self.m, t, y[0], y[1]);
    }

    /// One accepted step, not beyond `t_stop`.
    fn step(&mut self, t_stop: f64) -> Result<Stepped, SimError> {
        loop {
            self.steps += 1;
            if self.steps > self.max_steps {
                return Err(SimError::TooManySteps {
                    t: self.t,
                    steps: self.max_steps,
                });
            }
            let remaining = t_stop - self.t;
            let h_free = self.h.min(self.h_max);
            let limited = remaining <= h_free;
            let h = if limited { remaining } else { h_free };
            let min_h = 1e-15 * self.t.abs().max(1e-300);
            if (h.is_nan() || h <= min_h) && !limited {
                return Err(SimError::Breakdown { t: self.t });
            }
            let tr = self.trial(h);
            let finite = tr.y1.iter().all(|v| v.is_finite()) && tr.err.is_finite();
            if !finite {
                self.h = 0.25 * h;
                continue;
            }
            let factor = if tr.err == 0.0 {
                5.0
            } else {
                (0.9 * tr.err.powf(-0.2)).clamp(0.2, 5.0)
            };
            if tr.err > 1.0 {
                self.h = h * factor;
                continue;
            }
            // A step shortened to land on `t_stop` does not shrink the proposal.
            let h_next = if limited && factor >= 1.0 {
                self.h
            } else {
                h * factor
            };
            let ev = self.find_event(&tr);
            let Some((theta, ev)) = ev else {
                let t1 = if limited { t_stop } else { self.t + h };
                self.commit(t1, tr.y1);
                self.h = h_next;
                return Ok(Stepped::Normal);
            };
            // Re-take the step up to the event.
            let he = theta * h;
            let tr2 = self.trial(he);
            if tr2.err.is_nan() || tr2.err > 1.0 || !tr2.y1.iter().all(|v| v.is_finite()) {
                self.h = 0.5 * he;
                continue;
            }
            let te = self.t + he;
            let mut y = tr2.y1;
            match ev {
                Event::Turn => y[1] = 0.0,
                Event::Confirm(xb) => {
                    // Make sure the committed sample confirms the reversal
                    // (projecting onto the boundary would keep it pending).
                    let p = self.law.pres();
                    let d = f64::from(p.direction());
                    let back = |x: f64| d * (p.extremum() - x);
                    let mut nudge = (xb.abs().max(self.m.z_max)) * 4.0 * f64::EPSILON;
                    if back(y[0]) <= self.m.epsilon {
                        y[0] = xb;
                        while back(y[0]) <= self.m.epsilon {
                            y[0] = xb - d * nudge;
                            nudge *= 2.0;
                        }
                    }
                }
                Event::Return(xb) => y[0] = xb,
                Event::Rest => {
                    // Make sure the committed sample is across |v| = v_rest.
                    if let Some(vr) = self.v_rest {
                        let rest0 = self.y[1].abs() <= vr;
                        if (y[1].abs() <= vr) == rest0 {
                            let sign = if y[1] != 0.0 {
                                sgn(y[1])
                            } else {
                                sgn(self.y[1])
                            };
                            let mag = if rest0 {
                                vr * (1.0 + 4.0 * f64::EPSILON)
                            } else {
                                vr * (1.0 - 4.0 * f64::EPSILON)
                            };
                            y[1] = sign * mag;
                        }
                    }
                }
                Event::BreakAway => {
                    let p = self.law.pres();
                    let w_b = self.w_b.unwrap_or(1.0);
                    let dir = if p.direction() != 0 {
                        f64::from(p.direction())
                    } else {
                        sgn(y[1])
                    };
                    let w = dir * (y[0] - p.turning_point()) / self.m.z_max;
                    let a = self.rhs(te, y)[1];
                    let mut dt = 0.0;
                    if y[1] != 0.0 {
                        dt = (w_b - w) * self.m.z_max / (dir * y[1]);
                        if !dt.is_finite() || dt.abs() > he {
                            dt = 0.0;
                        }
                    }
                    let t_ba = te + dt;
                    return Ok(Stepped::BreakAway(DynamicBreakAway {
                        f_ba: (self.u)(t_ba),
                        t_ba,
                        v_b: y[1] + a * dt,
                    }));
                }
            }
            self.commit(te, y);
            self.h = h_next.min(h);
            return Ok(Stepped::Normal);
        }
    }
}

fn arg_err(name: &'static str, value: f64, requirement: &'static str) -> SimError {
    SimError::Argument(ArgumentError::new(name, value, requirement))
}

fn check_model(m: &Model) -> Result<(), SimError> {
    m.validate().map_err(SimError::Model)?;
    if m.z_max.is_nan() || m.z_max <= 0.0 {
        return Err(arg_err(
            "z_max",
            m.z_max,
            "z_max > 0 (a model without presliding needs a sticking rule)",
        ));
    }
    Ok(())
}

fn tolerances(m: &Model, tol: f64) -> [f64; 2] {
    let v_scale = m.v_stribeck.min((m.fs * m.z_max / m.mass).sqrt());
    [tol * m.z_max, tol * v_scale]
}

/// Break-away under the ramp `u = k·t` by the full dynamics (MODEL.md §4):
/// from idle at rest (`x = 0`, `v = 0`, `d = 0`), integrate `m·ẍ = k·t − F`
/// with `F` from [`Presliding`] (no effects, the model's `ε` applies) until
/// `w` first reaches `w_b` [-]; `k` [N/s]. Returns `t_ba` [s],
/// `f_ba = k·t_ba` [N] and the velocity [m/s] there. Uses
/// [`SimOptions::default`].
pub fn simulate_break_away(m: &Model, k: f64, w_b: f64) -> Result<DynamicBreakAway, SimError> {
    simulate_break_away_with(m, k, w_b, &SimOptions::default())
}

/// [`simulate_break_away`] with explicit integrator options.
pub fn simulate_break_away_with(
    m: &Model,
    k: f64,
    w_b: f64,
    opts: &SimOptions,
) -> Result<DynamicBreakAway, SimError> {
    check_model(m)?;
    if !(k.is_finite() && k > 0.0) {
        return Err(arg_err("k", k, "finite k > 0"));
    }
    if !(w_b > 0.0 && w_b < 1.0) {
        return Err(arg_err("w_b", w_b, "0 < w_b < 1"));
    }
    check_tol(opts)?;
    let t_limit = 100.0 * m.fs / k;
    let t_nat = (m.mass * m.z_max / m.fs).sqrt();
    let mut it = Integrator {
        m,
        u: |t: f64| k * t,
        law: Presliding::new(0.0),
        t: 0.0,
        y: [0.0, 0.0],
        h: 1e-3 * t_nat.min(m.fs / k),
        h_max: 0.02 * m.fs / k,
        atol: tolerances(m, opts.tol),
        rtol: opts.tol,
        steps: 0,
        max_steps: opts.max_steps,
        w_b: Some(w_b),
        v_rest: None,
    };
    it.commit(0.0, [0.0, 0.0]);
    while it.t < t_limit {
        if let Stepped::BreakAway(b) = it.step(t_limit)? {
            return Ok(b);
        }
    }
    Err(SimError::NoBreakAway { t_limit })
}

fn check_tol(opts: &SimOptions) -> Result<(), SimError> {
    if !(opts.tol > 0.0 && opts.tol < 1.0) {
        return Err(arg_err("tol", opts.tol, "0 < tol < 1"));
    }
    Ok(())
}

/// General simulation of `m·ẍ = u(t) − F` from `(x0, v0)` at `t = 0` to
/// `t_end` [s], with `F` from [`Friction`] (all effects of the model; the
/// record starts at `t = 0`). `u(t)` [N] is evaluated where the integrator
/// needs it. Returns samples at `t = 0, dt_out, 2·dt_out, …` [s] up to
/// `t_end` (inclusive within rounding). Uses [`SimOptions::default`]. The
/// model needs `z_max > 0` (no sticking rule for ideal switching).
pub fn simulate(
    m: &Model,
    u: &dyn Fn(f64) -> f64,
    x0: f64,
    v0: f64,
    t_end: f64,
    dt_out: f64,
) -> Result<Vec<Sample>, SimError> {
    let opts = SimOptions::default();
    check_model(m)?;
    if !x0.is_finite() {
        return Err(arg_err("x0", x0, "finite"));
    }
    if !v0.is_finite() {
        return Err(arg_err("v0", v0, "finite"));
    }
    if !(t_end.is_finite() && t_end >= 0.0) {
        return Err(arg_err("t_end", t_end, "finite t_end >= 0"));
    }
    if !(dt_out.is_finite() && dt_out > 0.0) {
        return Err(arg_err("dt_out", dt_out, "finite dt_out > 0"));
    }
    let n_f = (t_end / dt_out * (1.0 + 1e-12)).floor();
    if n_f > 1e8 {
        return Err(arg_err(
            "dt_out",
            dt_out,
            "at most 1e8 output samples (t_end/dt_out)",
        ));
    }
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let n = n_f as usize;
    let t_nat = (m.mass * m.z_max / m.fs).sqrt();
    let mut it = Integrator {
        m,
        u,
        law: Friction::new(m, 0.0, x0, v0),
        t: 0.0,
        y: [x0, v0],
        h: 1e-3 * t_nat.min(dt_out),
        h_max: dt_out,
        atol: tolerances(m, opts.tol),
        rtol: opts.tol,
        steps: 0,
        max_steps: opts.max_steps,
        w_b: None,
        v_rest: m.effects.dwell_stiction.map(|d| d.v_rest),
    };
    it.commit(0.0, [x0, v0]);
    let mut out = Vec::with_capacity(n + 1);
    let mut push = |it: &Integrator<'_, Friction, &dyn Fn(f64) -> f64>| {
        let s = Sample {
            t: it.t,
            x: it.y[0],
            v: it.y[1],
            u: (it.u)(it.t),
            f: it.law.force(),
        };
        if s.x.is_finite() && s.v.is_finite() {
            out.push(s);
            Ok(())
        } else {
            Err(SimError::Breakdown { t: it.t })
        }
    };
    push(&it)?;
    for i in 1..=n {
        #[allow(clippy::cast_precision_loss)]
        let t_out = i as f64 * dt_out;
        while t_out - it.t > 1e-12 * dt_out {
            it.step(t_out)?;
        }
        push(&it)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear spring `F = x` (unit mass): `x = cos t`.
    #[derive(Clone)]
    struct Spring(Presliding);
    impl Law for Spring {
        fn sample(&mut self, _m: &Model, _t: f64, x: f64, _v: f64) -> f64 {
            x
        }
        fn pres(&self) -> &Presliding {
            &self.0
        }
    }

    #[test]
    fn dense_output_is_fourth_order() {
        // The spring law below ignores the friction model; any valid one does.
        let unit = "mass = 1\nfc = 1\nfs = 1\nv_stribeck = 1\ndelta = 1\n\
                    sigma = 0\nz_max = 1\nepsilon = 0\n";
        let m = Model::from_toml_str(unit).expect("a valid model file");
        let err_at = |h: f64| {
            let it = Integrator {
                m: &m,
                u: |_t: f64| 0.0,
                law: Spring(Presliding::new(0.0)),
                t: 0.3,
                y: [0.3f64.cos(), -(0.3f64.sin())],
                h,
                h_max: h,
                atol: [1e-9; 2],
                rtol: 1e-9,
                steps: 0,
                max_steps: 10,
                w_b: None,
                v_rest: None,
            };
            let tr = it.trial(h);
            let mut worst = 0.0f64;
            for i in 1..10 {
                let th = f64::from(i) / 10.0;
                let y = tr.at(th);
                let t = 0.3 + th * h;
                worst = worst
                    .max((y[0] - t.cos()).abs())
                    .max((y[1] + t.sin()).abs());
            }
            // End point and error estimate.
            assert!((tr.y1[0] - (0.3 + h).cos()).abs() < 1e-3 * h.powi(5));
            worst
        };
        let (e1, e2) = (err_at(0.2), err_at(0.1));
        // Local error of a 4th-order interpolant: O(h^5), ratio ≈ 32.
        assert!(e1 / e2 > 20.0, "{e1} {e2}");
        assert!(e2 < 1e-7, "{e2}");
    }
}
