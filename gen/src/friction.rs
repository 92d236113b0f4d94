//! The friction model of MODEL.md §2, §3 and §5, written afresh for the
//! generator (it shares no code with the crates it is used to judge).
//!
//! * §2: `S(v) = Fc + (Fs − Fc)·exp(−(|v|/V)^δ)`, `F_ss = sgn(v)·S + σ·v`.
//! * §3: rate-independent presliding with `g(w) = w·(1 − ln w)`, a single
//!   remembered turning point, deadband `ε = 0`, the idle start rule and the
//!   rule "`H_r ←` the H of the latest sample at `x_ext`".
//! * §5: the effect catalogue with the composition formula.
//!
//! Units: positions [m], velocities [m/s], forces [N], times [s], masses [kg].

use serde::Serialize;
use std::cmp::Ordering;

/// One effect of the MODEL.md §5 catalogue (the dynamic ones; `stribeck` and
/// `presliding` are part of the base model here).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Effect {
    /// `F += σ·v`.
    Viscous,
    /// `F += F0`.
    Offset,
    /// `Fc`, `Fs` scaled by `1 + a·d`.
    Asymmetry,
    /// `F += A·sin(2π·x/λ + φ)`.
    PositionRipple,
    /// `Fs` raised by `ΔFs·t_d/(t_d + γ)`.
    DwellStiction,
    /// `S` evaluated at a lagged velocity.
    FrictionalLag,
    /// `Fc`, `Fs` scaled by `1 + β·t`.
    Drift,
    /// `F += σ_n·sgn(v)·|v|^n`.
    NonlinearViscous,
}

impl Effect {
    /// Every effect, in catalogue order.
    pub const ALL: [Effect; 8] = [
        Effect::Viscous,
        Effect::Offset,
        Effect::Asymmetry,
        Effect::PositionRipple,
        Effect::DwellStiction,
        Effect::FrictionalLag,
        Effect::Drift,
        Effect::NonlinearViscous,
    ];

    /// The catalogue identifier (MODEL.md §5).
    pub fn name(self) -> &'static str {
        match self {
            Effect::Viscous => "viscous",
            Effect::Offset => "offset",
            Effect::Asymmetry => "asymmetry",
            Effect::PositionRipple => "position_ripple",
            Effect::DwellStiction => "dwell_stiction",
            Effect::FrictionalLag => "frictional_lag",
            Effect::Drift => "drift",
            Effect::NonlinearViscous => "nonlinear_viscous",
        }
    }

    /// Parses a catalogue identifier.
    pub fn from_name(s: &str) -> Option<Effect> {
        Effect::ALL.into_iter().find(|e| e.name() == s)
    }

    /// True when the effect changes the dry (hysteretic) part `H`, so that a
    /// model without it needs its own presliding memory.
    pub fn changes_dry(self) -> bool {
        matches!(
            self,
            Effect::Asymmetry | Effect::DwellStiction | Effect::FrictionalLag | Effect::Drift
        )
    }

    /// True when the effect can be seen in steady-state (constant-velocity)
    /// records (MODEL.md §6).
    pub fn steady_visible(self) -> bool {
        matches!(
            self,
            Effect::Viscous | Effect::NonlinearViscous | Effect::Offset | Effect::Asymmetry
        )
    }
}

/// Base parameters of MODEL.md §2–§3 (plus the moving mass of §1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Params {
    /// Moving mass `m` [kg].
    pub mass: f64,
    /// Coulomb level `Fc` [N].
    pub fc: f64,
    /// Stiction level `Fs` [N].
    pub fs: f64,
    /// Stribeck velocity `V` [m/s].
    pub v_stribeck: f64,
    /// Shape exponent `δ` [-].
    pub delta: f64,
    /// Viscous coefficient `σ` [N·s/m] (the effect `viscous` when > 0).
    pub sigma: f64,
    /// Presliding distance `z_max` [m].
    pub z_max: f64,
}

/// `offset`: `F += F0`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Offset {
    /// Constant force `F0` [N] (signed).
    pub f0: f64,
}

/// `asymmetry`: levels scaled by `1 + a·d`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Asymmetry {
    /// Asymmetry `a` [-], `−1 < a < 1`.
    pub a: f64,
}

/// `position_ripple`: `F += A·sin(2π·x/λ + φ)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PositionRipple {
    /// Amplitude `A` [N].
    pub amplitude: f64,
    /// Wavelength `λ` [m].
    pub wavelength: f64,
    /// Phase `φ` [rad].
    pub phase: f64,
}

/// `dwell_stiction`: `Fs` raised by `ΔFs·t_d/(t_d + γ)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DwellStiction {
    /// Rise `ΔFs` [N] of the stiction level after a long rest.
    pub delta_fs: f64,
    /// Time constant `γ` [s].
    pub gamma: f64,
    /// Rest threshold `v_rest` [m/s].
    pub v_rest: f64,
}

/// `frictional_lag`: `τ_L·dv_l/dt = v − v_l`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FrictionalLag {
    /// Lag time constant `τ_L` [s].
    pub tau_l: f64,
}

/// `drift`: levels scaled by `1 + β·t`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Drift {
    /// Relative drift rate `β` [1/s].
    pub beta: f64,
}

/// `nonlinear_viscous`: `F += σ_n·sgn(v)·|v|^n`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct NonlinearViscous {
    /// Coefficient `σ_n` [N·(s/m)^n].
    pub sigma_n: f64,
    /// Exponent `n` [-], `0 < n ≤ 2`.
    pub n: f64,
}

/// The effect tables of MODEL.md §7 (`viscous` is [`Params::sigma`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Effects {
    /// `[effects.offset]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset: Option<Offset>,
    /// `[effects.asymmetry]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub asymmetry: Option<Asymmetry>,
    /// `[effects.position_ripple]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position_ripple: Option<PositionRipple>,
    /// `[effects.dwell_stiction]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dwell_stiction: Option<DwellStiction>,
    /// `[effects.frictional_lag]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frictional_lag: Option<FrictionalLag>,
    /// `[effects.drift]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drift: Option<Drift>,
    /// `[effects.nonlinear_viscous]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nonlinear_viscous: Option<NonlinearViscous>,
}

impl Effects {
    /// True when no table is present.
    pub fn is_empty(&self) -> bool {
        *self == Effects::default()
    }
}

/// `S(v)` of MODEL.md §2: the magnitude of the steady-state dry friction at
/// speed `speed = |v|` [m/s] for levels `fc`, `fs` [N], Stribeck velocity
/// `v_s` [m/s] and exponent `delta`.
pub fn stribeck(speed: f64, fc: f64, fs: f64, v_s: f64, delta: f64) -> f64 {
    let r = speed.abs() / v_s;
    if r == 0.0 {
        return fs;
    }
    fc + (fs - fc) * (-(r.powf(delta))).exp()
}

/// `sgn(v)` of MODEL.md: −1, 0 or +1 (0 for ±0 and NaN, unlike
/// [`f64::signum`]).
pub fn sgn(v: f64) -> f64 {
    match v.partial_cmp(&0.0) {
        Some(Ordering::Greater) => 1.0,
        Some(Ordering::Less) => -1.0,
        Some(Ordering::Equal) | None => 0.0,
    }
}

/// The presliding shape `g(w) = w·(1 − ln w)` of MODEL.md §3, clamped to
/// `g(0) = 0` and `g(w ≥ 1) = 1`.
pub fn g(w: f64) -> f64 {
    if w <= 0.0 {
        0.0
    } else if w >= 1.0 {
        1.0
    } else {
        w * (1.0 - w.ln())
    }
}

/// A complete friction model: base parameters and effect tables.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model {
    /// Base parameters.
    pub p: Params,
    /// Effect tables.
    pub e: Effects,
}

impl Model {
    /// The paper's setting with δ = 2 (m = 1 kg, Fc = 1 N, Fs = 1.5 N,
    /// V = 1 mm/s, z_max = 10 µm, no effects): the tests' fixture.
    pub fn paper() -> Model {
        Model {
            p: Params {
                mass: 1.0,
                fc: 1.0,
                fs: 1.5,
                v_stribeck: 1e-3,
                delta: 2.0,
                sigma: 0.0,
                z_max: 1e-5,
            },
            e: Effects::default(),
        }
    }

    /// True when `effect` is present (for `viscous`: `σ > 0`).
    pub fn has(&self, effect: Effect) -> bool {
        match effect {
            Effect::Viscous => self.p.sigma > 0.0,
            Effect::Offset => self.e.offset.is_some(),
            Effect::Asymmetry => self.e.asymmetry.is_some(),
            Effect::PositionRipple => self.e.position_ripple.is_some(),
            Effect::DwellStiction => self.e.dwell_stiction.is_some(),
            Effect::FrictionalLag => self.e.frictional_lag.is_some(),
            Effect::Drift => self.e.drift.is_some(),
            Effect::NonlinearViscous => self.e.nonlinear_viscous.is_some(),
        }
    }

    /// The same model with `effect` removed.
    pub fn without(&self, effect: Effect) -> Model {
        let mut m = *self;
        match effect {
            Effect::Viscous => m.p.sigma = 0.0,
            Effect::Offset => m.e.offset = None,
            Effect::Asymmetry => m.e.asymmetry = None,
            Effect::PositionRipple => m.e.position_ripple = None,
            Effect::DwellStiction => m.e.dwell_stiction = None,
            Effect::FrictionalLag => m.e.frictional_lag = None,
            Effect::Drift => m.e.drift = None,
            Effect::NonlinearViscous => m.e.nonlinear_viscous = None,
        }
        m
    }

    /// The scaled levels `(Fc', Fs')` [N] of the §5 composition for direction
    /// `d` (−1, 0, +1), time `t` [s] from the record start and rest length
    /// `t_d` [s].
    pub fn levels(&self, d: f64, t: f64, t_d: f64) -> (f64, f64) {
        let mut sc = 1.0;
        if let Some(a) = self.e.asymmetry {
            sc *= 1.0 + a.a * d;
        }
        if let Some(b) = self.e.drift {
            sc *= 1.0 + b.beta * t;
        }
        let mut fs = self.p.fs * sc;
        if let Some(dw) = self.e.dwell_stiction {
            fs += dw.delta_fs * t_d / (t_d + dw.gamma);
        }
        (self.p.fc * sc, fs)
    }

    /// `S` [N] with the scaled levels at speed `speed` [m/s].
    pub fn s(&self, speed: f64, d: f64, t: f64, t_d: f64) -> f64 {
        let (fc, fs) = self.levels(d, t, t_d);
        stribeck(speed, fc, fs, self.p.v_stribeck, self.p.delta)
    }

    /// The velocity-dependent additive terms `σ·v + σ_n·sgn(v)·|v|^n` [N].
    pub fn viscous_terms(&self, v: f64) -> f64 {
        let mut f = self.p.sigma * v;
        if let Some(nv) = self.e.nonlinear_viscous {
            f += nv.sigma_n * v.signum() * v.abs().powf(nv.n);
        }
        f
    }

    /// The position/constant additive terms `F0 + A·sin(2π·x/λ + φ)` [N].
    pub fn static_terms(&self, x: f64) -> f64 {
        let mut f = 0.0;
        if let Some(o) = self.e.offset {
            f += o.f0;
        }
        if let Some(r) = self.e.position_ripple {
            f += r.amplitude * (std::f64::consts::TAU * x / r.wavelength + r.phase).sin();
        }
        f
    }

    /// The steady-state friction `F_ss(v)` [N] of §2 with the effects that a
    /// constant-velocity run shows (levels at `t = 0`, no dwell, no lag; the
    /// ripple averages out over a run).
    pub fn steady(&self, v: f64) -> f64 {
        let d = sgn(v);
        let mut f = d * self.s(v.abs(), d, 0.0, 0.0) + self.viscous_terms(v);
        if let Some(o) = self.e.offset {
            f += o.f0;
        }
        f
    }

    /// The largest stiction level the composition can reach over a record of
    /// length `duration` [s] [N].
    pub fn fs_max(&self, duration: f64) -> f64 {
        let mut sc = 1.0;
        if let Some(a) = self.e.asymmetry {
            sc *= 1.0 + a.a.abs();
        }
        if let Some(b) = self.e.drift {
            sc *= 1.0 + (b.beta * duration).max(0.0);
        }
        self.p.fs * sc + self.e.dwell_stiction.map_or(0.0, |d| d.delta_fs)
    }
}

/// One variant of the model tracked along the motion: the main model or the
/// main model without one hidden effect (to measure that effect's force).
#[derive(Clone, Debug)]
struct Variant {
    model: Model,
    /// Whether its dry part differs from the main model's.
    own_dry: bool,
    /// Dry friction at the turning point `H_r` [N].
    h_r: f64,
    /// Dry friction of the latest sample at `x_ext` [N].
    h_ext: f64,
    /// Dry friction `H` of the latest evaluation [N].
    h: f64,
}

/// The dynamic MODEL.md friction (§3 with §5) along a motion, with optional
/// shadow variants that each lack one hidden effect.
#[derive(Clone, Debug)]
pub struct ModelFriction {
    variants: Vec<Variant>,
    /// Direction `d` (0 only at idle).
    d: f64,
    /// Turning point `x_r` [m].
    x_r: f64,
    /// Extremum in direction `d` [m].
    x_ext: f64,
    /// Length of the latest rest interval `t_d` [s].
    t_d: f64,
    /// Whether the motion is in a rest interval (`|v| ≤ v_rest`).
    in_rest: bool,
    /// With `dwell_stiction`: each change of `in_rest` as (time [s], whether
    /// a rest begins), in the order of the evaluations.
    rest_log: Vec<(f64, bool)>,
    /// Lagged velocity `v_l` [m/s].
    v_l: f64,
    /// Whether `v_l` has been set at the first sample.
    lag_set: bool,
    /// Normalised travel `w` of the latest evaluation.
    w: f64,
}

/// Result of one evaluation of [`ModelFriction`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionEval {
    /// Dry (hysteretic) part `H` [N] of the main model.
    pub h: f64,
    /// `H + F0 + A·sin(…)` [N]: the main force without the velocity terms.
    pub explicit: f64,
    /// Normalised travel `w` since the last turning point.
    pub w: f64,
    /// Direction `d`.
    pub d: f64,
}

impl ModelFriction {
    /// A friction at idle at position `x0` [m] for the main model `main`;
    /// one shadow variant per effect in `hidden` (each lacks that effect).
    pub fn new(main: Model, hidden: &[Effect], x0: f64) -> Self {
        let mut variants = vec![Variant {
            model: main,
            own_dry: true,
            h_r: 0.0,
            h_ext: 0.0,
            h: 0.0,
        }];
        for &e in hidden {
            variants.push(Variant {
                model: main.without(e),
                own_dry: e.changes_dry(),
                h_r: 0.0,
                h_ext: 0.0,
                h: 0.0,
            });
        }
        ModelFriction {
            variants,
            d: 0.0,
            x_r: x0,
            x_ext: x0,
            t_d: 0.0,
            in_rest: true,
            rest_log: Vec::new(),
            v_l: 0.0,
            lag_set: false,
            w: 0.0,
        }
    }

    /// The main model.
    pub fn model(&self) -> &Model {
        &self.variants[0].model
    }

    /// Normalised travel `w` of the latest evaluation (1 in gross sliding).
    pub fn w(&self) -> f64 {
        self.w
    }

    /// Direction `d` of the latest evaluation.
    pub fn direction(&self) -> f64 {
        self.d
    }

    /// Rest length `t_d` [s].
    pub fn rest_length(&self) -> f64 {
        self.t_d
    }

    /// With `dwell_stiction`, the changes of the dwell clock's rest state
    /// so far: (time [s], whether a rest begins); the record starts at rest.
    pub fn rest_log(&self) -> &[(f64, bool)] {
        &self.rest_log
    }

    /// Evaluates the friction at the true position `x` [m], velocity `v`
    /// [m/s] and time `t` [s]; this is one "sample" of MODEL.md §3 (the
    /// turning-point memory is updated with `x`). When `diffs` is given,
    /// `diffs[j]` receives `F_main − F_without_hidden_j` [N] (full forces
    /// including the velocity terms).
    pub fn eval(&mut self, x: f64, v: f64, t: f64, diffs: Option<&mut [f64]>) -> FrictionEval {
        // Turning-point memory (§3, ε = 0).
        let mut at_ext = false;
        if self.d == 0.0 {
            if x != self.x_r {
                self.d = if x > self.x_r { 1.0 } else { -1.0 };
                self.x_ext = x;
                at_ext = true;
            }
        } else if self.d * (x - self.x_ext) >= 0.0 {
            self.x_ext = x;
            at_ext = true;
        } else {
            self.d = -self.d;
            self.x_r = self.x_ext;
            self.x_ext = x;
            at_ext = true;
            for var in &mut self.variants {
                var.h_r = var.h_ext;
            }
        }
        // Rest intervals for dwell_stiction (a new interval restarts t_d).
        let v_rest = self.variants[0]
            .model
            .e
            .dwell_stiction
            .map_or(0.0, |dw| dw.v_rest);
        if v.abs() <= v_rest {
            if !self.in_rest {
                self.in_rest = true;
                self.t_d = 0.0;
                if v_rest > 0.0 {
                    self.rest_log.push((t, true));
                }
            }
        } else {
            if self.in_rest && v_rest > 0.0 {
                self.rest_log.push((t, false));
            }
            self.in_rest = false;
        }
        if !self.lag_set {
            self.v_l = v;
            self.lag_set = true;
        }
        let main = self.variants[0].model;
        let w = if self.d == 0.0 {
            0.0
        } else {
            ((x - self.x_r).abs() / main.p.z_max).min(1.0)
        };
        self.w = w;
        let gw = g(w);
        let d = self.d;
        let t_d = self.t_d;
        let v_l = self.v_l;
        let mut h_main = 0.0;
        for (i, var) in self.variants.iter_mut().enumerate() {
            if i > 0 && !var.own_dry {
                continue;
            }
            let h = if d == 0.0 {
                0.0
            } else {
                let vs = if var.model.e.frictional_lag.is_some() {
                    v_l
                } else {
                    v
                };
                let s = var.model.s(vs.abs(), d, t, t_d);
                var.h_r + (d * s - var.h_r) * gw
            };
            var.h = h;
            if at_ext {
                var.h_ext = h;
            }
            if i == 0 {
                h_main = h;
            }
        }
        let explicit = h_main + main.static_terms(x);
        if let Some(diffs) = diffs {
            let full = explicit + main.viscous_terms(v);
            for (j, out) in diffs.iter_mut().enumerate() {
                let var = &self.variants[j + 1];
                let h = if var.own_dry { var.h } else { h_main };
                let fj = h + var.model.static_terms(x) + var.model.viscous_terms(v);
                *out = full - fj;
            }
        }
        FrictionEval {
            h: h_main,
            explicit,
            w,
            d,
        }
    }

    /// Advances the time-continuous internal states (lagged velocity, rest
    /// length) over a step `h` [s] taken at velocity `v` [m/s].
    pub fn advance(&mut self, v: f64, h: f64) {
        if let Some(l) = self.variants[0].model.e.frictional_lag {
            self.v_l += (v - self.v_l) * (1.0 - (-h / l.tau_l).exp());
        }
        if self.in_rest {
            self.t_d += h;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> Model {
        Model::paper()
    }

    #[test]
    fn stribeck_limits() {
        assert_eq!(stribeck(0.0, 1.0, 1.5, 1e-3, 2.0), 1.5);
        assert!((stribeck(1.0, 1.0, 1.5, 1e-3, 2.0) - 1.0).abs() < 1e-12);
        // |v| = V: Fc + (Fs − Fc)/e.
        let s = stribeck(1e-3, 1.0, 1.5, 1e-3, 2.0);
        assert!((s - (1.0 + 0.5 / std::f64::consts::E)).abs() < 1e-12);
        // Symmetric in v.
        assert_eq!(
            stribeck(-2e-3, 1.0, 1.5, 1e-3, 0.7),
            stribeck(2e-3, 1.0, 1.5, 1e-3, 0.7)
        );
    }

    #[test]
    fn g_values() {
        assert_eq!(g(0.0), 0.0);
        assert_eq!(g(1.0), 1.0);
        assert_eq!(g(2.0), 1.0);
        // g(0.5) = 0.5·(1 + ln 2).
        assert!((g(0.5) - 0.5 * (1.0 + 2f64.ln())).abs() < 1e-15);
        // g(0.15) = 0.43 (MODEL.md §3).
        assert!((g(0.15) - 0.43).abs() < 0.005);
    }

    #[test]
    fn presliding_branch_by_hand() {
        let m = base();
        let mut f = ModelFriction::new(m, &[], 0.0);
        // Idle: H = 0.
        let e = f.eval(0.0, 0.0, 0.0, None);
        assert_eq!(e.h, 0.0);
        assert_eq!(e.d, 0.0);
        // Move to x = 0.5·z_max at rest velocity: H = Fs·g(0.5).
        let e = f.eval(5e-6, 0.0, 0.0, None);
        assert_eq!(e.d, 1.0);
        assert!((e.h - 1.5 * g(0.5)).abs() < 1e-12);
        // Continue to x = z_max: H = Fs (gross sliding at v = 0).
        let e = f.eval(1e-5, 0.0, 0.0, None);
        assert!((e.h - 1.5).abs() < 1e-12);
        // Reverse: back by 0.25·z_max at v = 0: H = 1.5 + (−1.5 − 1.5)·g(0.25).
        let e = f.eval(0.75e-5, 0.0, 0.0, None);
        assert_eq!(e.d, -1.0);
        let want = 1.5 + (-1.5 - 1.5) * (0.25 * (1.0 - 0.25f64.ln()));
        assert!((e.h - want).abs() < 1e-12, "{} vs {want}", e.h);
    }

    #[test]
    fn turning_point_takes_latest_h_at_extremum() {
        let m = base();
        let mut f = ModelFriction::new(m, &[], 0.0);
        f.eval(4e-6, 0.0, 0.0, None);
        // Still at the same extremum, but now sliding fast: S ≈ Fc.
        let at = f.eval(4e-6, 1.0, 0.0, None);
        let expect = 1.0 * g(0.4);
        assert!((at.h - expect).abs() < 1e-9);
        // Reversal: the branch starts at that latest H.
        let back = f.eval(4e-6 - 1e-15, 0.0, 0.0, None);
        assert!((back.h - expect).abs() < 1e-6);
    }

    #[test]
    fn composition_levels() {
        let mut m = base();
        m.e.asymmetry = Some(Asymmetry { a: 0.1 });
        m.e.drift = Some(Drift { beta: 0.01 });
        m.e.dwell_stiction = Some(DwellStiction {
            delta_fs: 0.2,
            gamma: 1.0,
            v_rest: 1e-4,
        });
        let (fc, fs) = m.levels(-1.0, 10.0, 1.0);
        let sc = 0.9 * 1.1;
        assert!((fc - sc).abs() < 1e-12);
        assert!((fs - (1.5 * sc + 0.1)).abs() < 1e-12);
        // d = 0 counts as no asymmetry.
        let (fc0, _) = m.levels(0.0, 0.0, 0.0);
        assert!((fc0 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn additive_terms_and_diffs() {
        let mut m = base();
        m.p.sigma = 2.0;
        m.e.offset = Some(Offset { f0: 0.3 });
        m.e.nonlinear_viscous = Some(NonlinearViscous {
            sigma_n: 1.0,
            n: 0.5,
        });
        let hidden = [Effect::Viscous, Effect::Offset, Effect::NonlinearViscous];
        let mut f = ModelFriction::new(m, &hidden, 0.0);
        let mut d = [0.0; 3];
        f.eval(2e-5, -0.04, 0.0, Some(&mut d));
        assert!((d[0] - 2.0 * -0.04).abs() < 1e-12);
        assert!((d[1] - 0.3).abs() < 1e-12);
        assert!((d[2] + 0.2).abs() < 1e-12);
    }
}
