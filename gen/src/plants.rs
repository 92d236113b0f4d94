//! Plants: the MODEL.md plant `m·ẍ = u − F` and the outside plants (LuGre,
//! generalized Maxwell-slip, a compliant two-mass axis). Each is integrated
//! with fixed-step semi-implicit (symplectic) Euler on a 1 µs tick lattice:
//! small steps (1–5 µs) near rest and in presliding, 25 µs steps in fast
//! gross sliding. The viscous terms `σ·v + σ_n·sgn(v)·|v|^n` are taken
//! implicitly (a monotone scalar solve), the rest explicitly.
//!
//! Units: [m], [m/s], [N], [kg], [s].

use crate::friction::{sgn, Effect, Model, ModelFriction};
use serde::Serialize;

/// Control (sampling) interval [s].
pub const DT: f64 = 1e-3;
/// Integration tick [s]; every step is a whole number of ticks.
pub const TICK: f64 = 1e-6;
/// Ticks per control interval.
pub const TICKS_PER_SAMPLE: u32 = 1000;
/// Ticks of a large step in fast gross sliding (25 µs).
pub const BIG_STEP: u32 = 25;

/// Which plant produces a record.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PlantKind {
    /// MODEL.md §1–§5 exactly.
    Model,
    /// LuGre friction.
    Lugre,
    /// Generalized Maxwell-slip friction.
    MaxwellSlip,
    /// MODEL.md friction on the load of a two-mass axis; the encoder reads the motor.
    Compliant,
    /// MODEL.md plant with ±1-count encoder jitter on the logged position.
    NoisyVelocity,
}

impl PlantKind {
    /// Every plant.
    pub const ALL: [PlantKind; 5] = [
        PlantKind::Model,
        PlantKind::Lugre,
        PlantKind::MaxwellSlip,
        PlantKind::Compliant,
        PlantKind::NoisyVelocity,
    ];
    /// The plants outside MODEL.md.
    pub const OUTSIDE: [PlantKind; 4] = [
        PlantKind::Lugre,
        PlantKind::MaxwellSlip,
        PlantKind::Compliant,
        PlantKind::NoisyVelocity,
    ];

    /// Identifier used on the command line and in truth files.
    pub fn name(self) -> &'static str {
        match self {
            PlantKind::Model => "model",
            PlantKind::Lugre => "lugre",
            PlantKind::MaxwellSlip => "maxwell_slip",
            PlantKind::Compliant => "compliant",
            PlantKind::NoisyVelocity => "noisy_velocity",
        }
    }

    /// Parses an identifier.
    pub fn from_name(s: &str) -> Option<PlantKind> {
        PlantKind::ALL.into_iter().find(|p| p.name() == s)
    }

    /// Whether the hidden effect can be put on this plant (dwell and lag
    /// need the MODEL.md presliding law).
    pub fn supports(self, e: Effect) -> bool {
        match self {
            PlantKind::Lugre | PlantKind::MaxwellSlip => {
                !matches!(e, Effect::DwellStiction | Effect::FrictionalLag)
            }
            _ => true,
        }
    }

    /// Names a correct diagnosis may add besides the hidden effects.
    pub fn accept_extra(self) -> Vec<&'static str> {
        match self {
            PlantKind::Lugre | PlantKind::MaxwellSlip => vec!["frictional_lag"],
            _ => Vec::new(),
        }
    }
}

/// Plant-specific parameters (besides the friction model).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PlantSpec {
    /// MODEL.md plant.
    Model,
    /// LuGre: `ż = v − σ0·|v|·z/S(v)`, `F = σ0·z + σ1·ż + σ·v`.
    Lugre {
        /// Bristle stiffness `σ0` [N/m].
        sigma0: f64,
        /// Bristle damping `σ1` [N·s/m].
        sigma1: f64,
    },
    /// Maxwell-slip elements (spring + elementary stick/slip block).
    MaxwellSlip {
        /// Element stiffnesses `k_i` [N/m].
        stiffness: Vec<f64>,
        /// Element break forces at rest `W_i` [N] (sum = Fs); in motion scaled by `S(v)/Fs`.
        break_force: Vec<f64>,
        /// Element damping while sticking `c_i` [N·s/m].
        damping: Vec<f64>,
    },
    /// Two-mass axis: motor `m1` driven by `u`, load `m2` with friction.
    Compliant {
        /// Motor mass `m1` [kg].
        m1: f64,
        /// Load mass `m2` [kg].
        m2: f64,
        /// Coupling stiffness `k` [N/m].
        k: f64,
        /// Coupling damping `c` [N·s/m].
        c: f64,
        /// Resonance frequency `√(k·(m1+m2)/(m1·m2))/2π` [Hz].
        resonance_hz: f64,
    },
    /// MODEL.md plant with encoder jitter on the measurement.
    NoisyVelocity {
        /// Probability of a ±1-count jitter per sample.
        jitter_prob: f64,
    },
}

/// A friction law integrated along the motion.
pub trait Law: Send {
    /// Called once per integration step at the state `(x, v, t)` before a
    /// step of `h` [s]; advances the law's internal states over the step and
    /// returns the explicit part of the friction [N] (all but the viscous
    /// terms, which the integrator takes implicitly). When `diffs` is given,
    /// `diffs[j]` receives the force of hidden effect `j` (main − without).
    fn step(&mut self, x: f64, v: f64, t: f64, h: f64, diffs: Option<&mut [f64]>) -> f64;
    /// Whether the latest step was in gross sliding.
    fn gross(&self) -> bool;
    /// The main friction model (for its viscous terms).
    fn model(&self) -> &Model;
    /// The largest stiffness of the law near rest [N/m] (sets the small step).
    fn stiffness(&self) -> f64;
    /// The changes of the `dwell_stiction` clock's rest state (time [s],
    /// whether a rest begins); empty for a law without that clock.
    fn rest_log(&self) -> &[(f64, bool)] {
        &[]
    }
}

/// The MODEL.md law (§3 with §5).
pub struct ModelLaw {
    fric: ModelFriction,
}

impl ModelLaw {
    /// Idle at `x0` [m].
    pub fn new(model: Model, hidden: &[Effect], x0: f64) -> Self {
        ModelLaw {
            fric: ModelFriction::new(model, hidden, x0),
        }
    }

    /// The friction state.
    pub fn friction(&self) -> &ModelFriction {
        &self.fric
    }
}

impl Law for ModelLaw {
    fn step(&mut self, x: f64, v: f64, t: f64, h: f64, diffs: Option<&mut [f64]>) -> f64 {
        let e = self.fric.eval(x, v, t, diffs);
        self.fric.advance(v, h);
        e.explicit
    }
    fn gross(&self) -> bool {
        self.fric.w() >= 1.0
    }
    fn model(&self) -> &Model {
        self.fric.model()
    }
    fn stiffness(&self) -> f64 {
        // |d·S − H_r| ≤ 2·Fs, −ln w ≲ 20 right after a turning point.
        let m = self.fric.model();
        40.0 * m.fs_max(60.0) / m.p.z_max
    }
    fn rest_log(&self) -> &[(f64, bool)] {
        self.fric.rest_log()
    }
}

/// One variant of an outside law (main model or main without one effect).
#[derive(Clone, Debug)]
struct OutVar {
    model: Model,
    own: bool,
    /// LuGre bristle deflection [m], or Maxwell-slip element deflections [m].
    z: Vec<f64>,
    /// Dry part of the latest step [N].
    dry: f64,
}

/// The variants of an outside law along the motion (the main model first,
/// then the main model without each hidden effect) and the direction of
/// motion.
struct OutVars {
    vars: Vec<OutVar>,
    /// Direction (−1, +1) of the latest nonzero velocity, 0 before any.
    dir: f64,
}

impl OutVars {
    /// Every variant with `n_states` internal states, relaxed.
    fn new(main: Model, hidden: &[Effect], n_states: usize) -> Self {
        let variant = |model, own| OutVar {
            model,
            own,
            z: vec![0.0; n_states],
            dry: 0.0,
        };
        let without = hidden
            .iter()
            .map(|&e| variant(main.without(e), e.changes_dry()));
        OutVars {
            vars: std::iter::once(variant(main, true))
                .chain(without)
                .collect(),
            dir: 0.0,
        }
    }

    /// The main model.
    fn model(&self) -> &Model {
        &self.vars[0].model
    }

    /// One step: the direction follows the velocity `v`, `dry(i, var, |v|,
    /// dir)` advances the states and the dry part of the main model (`i` =
    /// 0) and of each variant that has its own; returns the main model's
    /// force at `x` and writes the variants' differences to `diffs`.
    fn step(
        &mut self,
        x: f64,
        v: f64,
        diffs: Option<&mut [f64]>,
        mut dry: impl FnMut(usize, &mut OutVar, f64, f64),
    ) -> f64 {
        if v != 0.0 {
            self.dir = sgn(v);
        }
        let speed = v.abs();
        for (i, var) in self.vars.iter_mut().enumerate() {
            if i > 0 && !var.own {
                continue;
            }
            dry(i, var, speed, self.dir);
        }
        if let Some(d) = diffs {
            out_diffs(&self.vars, x, v, d);
        }
        self.vars[0].dry + self.vars[0].model.static_terms(x)
    }
}

fn out_diffs(vars: &[OutVar], x: f64, v: f64, diffs: &mut [f64]) {
    let main = &vars[0];
    let full = main.dry + main.model.static_terms(x) + main.model.viscous_terms(v);
    for (j, out) in diffs.iter_mut().enumerate() {
        let var = &vars[j + 1];
        let dry = if var.own { var.dry } else { main.dry };
        *out = full - (dry + var.model.static_terms(x) + var.model.viscous_terms(v));
    }
}

/// LuGre friction with the §5 additive/scaling effects.
pub struct LugreLaw {
    vars: OutVars,
    sigma0: f64,
    sigma1: f64,
    gross: bool,
}

impl LugreLaw {
    /// Bristles relaxed (`z = 0`).
    pub fn new(model: Model, hidden: &[Effect], sigma0: f64, sigma1: f64) -> Self {
        LugreLaw {
            vars: OutVars::new(model, hidden, 1),
            sigma0,
            sigma1,
            gross: false,
        }
    }
}

impl Law for LugreLaw {
    fn step(&mut self, x: f64, v: f64, t: f64, h: f64, diffs: Option<&mut [f64]>) -> f64 {
        let (sigma0, sigma1) = (self.sigma0, self.sigma1);
        let mut gross = false;
        let f = self.vars.step(x, v, diffs, |i, var, speed, dir| {
            let s = var.model.s(speed, dir, t, 0.0);
            let z = var.z[0];
            let a = sigma0 * speed / s;
            let z_new = if a * h < 1e-9 {
                z + v * h
            } else {
                let z_eq = v / a;
                z_eq + (z - z_eq) * (-a * h).exp()
            };
            var.dry = sigma0 * z + sigma1 * (z_new - z) / h;
            var.z[0] = z_new;
            if i == 0 {
                gross = sigma0 * z_new.abs() > 0.95 * s;
            }
        });
        self.gross = gross;
        f
    }
    fn gross(&self) -> bool {
        self.gross
    }
    fn model(&self) -> &Model {
        self.vars.model()
    }
    fn stiffness(&self) -> f64 {
        self.sigma0
    }
}

/// Generalized Maxwell-slip friction with the §5 additive/scaling effects.
pub struct MaxwellLaw {
    vars: OutVars,
    k: Vec<f64>,
    w0: Vec<f64>,
    c: Vec<f64>,
    all_slip: bool,
}

impl MaxwellLaw {
    /// Elements relaxed. `k` [N/m], `w0` break forces at rest [N], `c` [N·s/m].
    pub fn new(model: Model, hidden: &[Effect], k: &[f64], w0: &[f64], c: &[f64]) -> Self {
        MaxwellLaw {
            vars: OutVars::new(model, hidden, k.len()),
            k: k.to_vec(),
            w0: w0.to_vec(),
            c: c.to_vec(),
            all_slip: false,
        }
    }
}

impl Law for MaxwellLaw {
    fn step(&mut self, x: f64, v: f64, t: f64, h: f64, diffs: Option<&mut [f64]>) -> f64 {
        let (k, w0, c) = (&self.k, &self.w0, &self.c);
        let mut all_slip = true;
        let force = self.vars.step(x, v, diffs, |i, var, speed, dir| {
            let scale = var.model.s(speed, dir, t, 0.0) / var.model.p.fs;
            let mut f = 0.0;
            for (j, z) in var.z.iter_mut().enumerate() {
                let zt = *z + v * h;
                let w = w0[j] * scale;
                let k = k[j];
                if (k * zt).abs() > w {
                    *z = sgn(zt) * w / k;
                } else {
                    *z = zt;
                    f += c[j] * v;
                    if i == 0 {
                        all_slip = false;
                    }
                }
                f += k * *z;
            }
            var.dry = f;
        });
        self.all_slip = all_slip;
        force
    }
    fn gross(&self) -> bool {
        self.all_slip
    }
    fn model(&self) -> &Model {
        self.vars.model()
    }
    fn stiffness(&self) -> f64 {
        self.k.iter().sum()
    }
}

/// Solves `s·(1 + c1) + c2·s^n = p` for `s ≥ 0` (`p ≥ 0`, `c1, c2 ≥ 0`):
/// the implicit viscous update. Newton from the right on a convex function
/// (in `s` for `n ≥ 1`, in `r = s^n` for `n < 1`) converges monotonically.
pub fn solve_viscous(p: f64, c1: f64, c2: f64, n: f64) -> f64 {
    let a = 1.0 + c1;
    if p <= 0.0 {
        return 0.0;
    }
    if c2 == 0.0 {
        return p / a;
    }
    if n == 1.0 {
        return p / (a + c2);
    }
    if n > 1.0 {
        let mut s = p / a;
        for _ in 0..60 {
            let phi = a * s + c2 * s.powf(n) - p;
            let dphi = a + c2 * n * s.powf(n - 1.0);
            let ds = phi / dphi;
            s -= ds;
            if ds.abs() <= 1e-15 * s.abs() {
                break;
            }
        }
        s.max(0.0)
    } else {
        let inv = 1.0 / n;
        let mut r = (p / c2).min((p / a).powf(n));
        for _ in 0..60 {
            let rp = r.powf(inv);
            let psi = a * rp + c2 * r - p;
            let dpsi = a * inv * rp / r + c2;
            let dr = psi / dpsi;
            r -= dr;
            if dr.is_nan() || dr.abs() <= 1e-15 * r.abs() {
                break;
            }
        }
        r.max(0.0).powf(inv)
    }
}

/// The implicit viscous update of velocity: given the explicit prediction
/// `vp` [m/s], returns `v` with `v + (h/m)·(σ·v + σ_n·sgn(v)·|v|^n) = vp`.
///
/// The nonlinear term is taken explicitly (at the old velocity `v`) where it
/// is not stiff (`h/m·σ_n·n·|v|^(n−1) < 0.1` and the sign of motion kept),
/// implicitly otherwise.
fn implicit_velocity(model: &Model, v: f64, vp: f64, h_over_m: f64) -> f64 {
    let c1 = h_over_m * model.p.sigma;
    match model.e.nonlinear_viscous {
        None => vp / (1.0 + c1),
        Some(nv) => {
            let c2 = h_over_m * nv.sigma_n;
            if v != 0.0 {
                let s = v.abs();
                let f = c2 * s.powf(nv.n);
                if nv.n * f / s < 0.1 {
                    let w = vp - sgn(v) * f;
                    if sgn(w) == sgn(v) {
                        return w / (1.0 + c1);
                    }
                }
            }
            sgn(vp) * solve_viscous(vp.abs(), c1, c2, nv.n)
        }
    }
}

/// A plant integrated one control interval at a time.
pub trait Plant: Send {
    /// Integrates one control interval [`DT`] with the force `u` [N] held
    /// and returns the velocity of the friction contact [m/s] at its end;
    /// `diffs[j]` receives the force [N] of hidden effect `j` at the start of
    /// the interval (the sample instant).
    fn interval(&mut self, u: f64, diffs: &mut [f64]) -> f64;
    /// The position the encoder reads [m] (true, not quantised).
    fn encoder(&self) -> f64;
    /// True while the state is finite.
    fn finite(&self) -> bool;
    /// The friction law's [`Law::rest_log`].
    fn rest_log(&self) -> &[(f64, bool)];
}

/// Ticks of the small step for a stiffness `k` [N/m] and mass `m` [kg]:
/// about `0.2/ω`, one of 5, 4, 2, 1 µs.
fn small_ticks(k: f64, m: f64) -> u32 {
    let h = 0.2 / (k / m).sqrt();
    [5u32, 4, 2, 1]
        .into_iter()
        .find(|&n| f64::from(n) * TICK <= h)
        .unwrap_or(1)
}

/// A single mass with a friction law: `m·ẍ = u − F`.
pub struct MassPlant<L: Law> {
    /// Friction law.
    pub law: L,
    /// Position [m].
    pub x: f64,
    /// Velocity [m/s].
    pub v: f64,
    mass: f64,
    sub_steps: SubSteps,
}

impl<L: Law> MassPlant<L> {
    /// At rest at `x0` [m].
    pub fn new(law: L, x0: f64) -> Self {
        let mass = law.model().p.mass;
        let sub_steps = SubSteps::new(small_ticks(law.stiffness(), mass));
        MassPlant {
            law,
            x: x0,
            v: 0.0,
            mass,
            sub_steps,
        }
    }

    /// Time of the start of the next interval [s].
    pub fn time(&self) -> f64 {
        self.sub_steps.sample as f64 * DT
    }
}

fn big_allowed(gross: bool, v: f64, acc: f64, v_s: f64) -> bool {
    let h = f64::from(BIG_STEP) * TICK;
    gross && v.abs() > 3.0 * v_s && h * acc < 0.2 * v.abs()
}

/// The sub-step schedule every plant shares: big steps in fast gross
/// sliding of the friction contact, `small` ticks otherwise.
struct SubSteps {
    /// Control intervals integrated so far.
    sample: u64,
    /// Ticks of a small step.
    small: u32,
    /// `|dv/dt|` of the friction contact over the last sub-step [m/s²].
    acc: f64,
}

impl SubSteps {
    fn new(small: u32) -> Self {
        SubSteps {
            sample: 0,
            small,
            acc: 0.0,
        }
    }

    /// Integrates the next control interval of a plant whose friction
    /// contact moves at `v` [m/s]: `step(law, t, h, diffs)` advances the
    /// plant from time `t` [s] by `h` [s] (`diffs` on the first sub-step
    /// only) and returns the contact's new velocity [m/s] and `|dv/dt|`
    /// [m/s²], which decide whether the next sub-step may be a big one.
    /// Returns the contact's velocity at the end of the interval.
    fn interval<L: Law>(
        &mut self,
        law: &mut L,
        mut v: f64,
        diffs: &mut [f64],
        mut step: impl FnMut(&mut L, f64, f64, Option<&mut [f64]>) -> (f64, f64),
    ) -> f64 {
        let v_s = law.model().p.v_stribeck;
        let mut big = big_allowed(law.gross(), v, self.acc, v_s);
        let mut tick = 0u32;
        let t0 = self.sample as f64 * DT;
        while tick < TICKS_PER_SAMPLE {
            let left = TICKS_PER_SAMPLE - tick;
            let n = if big {
                BIG_STEP.min(left)
            } else {
                self.small.min(left)
            };
            let h = f64::from(n) * TICK;
            let t = t0 + f64::from(tick) * TICK;
            let d = if tick == 0 { Some(&mut *diffs) } else { None };
            (v, self.acc) = step(law, t, h, d);
            big = big_allowed(law.gross(), v, self.acc, v_s);
            tick += n;
        }
        self.sample += 1;
        v
    }
}

impl<L: Law> Plant for MassPlant<L> {
    fn interval(&mut self, u: f64, diffs: &mut [f64]) -> f64 {
        self.sub_steps
            .interval(&mut self.law, self.v, diffs, |law, t, h, d| {
                let f = law.step(self.x, self.v, t, h, d);
                let vp = self.v + h * (u - f) / self.mass;
                let v_new = implicit_velocity(law.model(), self.v, vp, h / self.mass);
                let acc = ((v_new - self.v) / h).abs();
                self.v = v_new;
                self.x += h * v_new;
                (v_new, acc)
            })
    }
    fn encoder(&self) -> f64 {
        self.x
    }
    fn finite(&self) -> bool {
        self.x.is_finite() && self.v.is_finite()
    }
    fn rest_log(&self) -> &[(f64, bool)] {
        self.law.rest_log()
    }
}

/// Two masses: motor `m1` (driven by `u`, read by the encoder) coupled by a
/// spring `k` and damper `c` to the load `m2`, which carries the friction.
pub struct TwoMassPlant<L: Law> {
    /// Friction law on the load.
    pub law: L,
    x1: f64,
    v1: f64,
    x2: f64,
    v2: f64,
    m1: f64,
    m2: f64,
    k: f64,
    c: f64,
    sub_steps: SubSteps,
}

impl<L: Law> TwoMassPlant<L> {
    /// At rest, spring relaxed, both at `x0` [m].
    pub fn new(law: L, x0: f64, m1: f64, m2: f64, k: f64, c: f64) -> Self {
        let sub_steps = SubSteps::new(small_ticks(law.stiffness(), m2));
        TwoMassPlant {
            law,
            x1: x0,
            v1: 0.0,
            x2: x0,
            v2: 0.0,
            m1,
            m2,
            k,
            c,
            sub_steps,
        }
    }
}

impl<L: Law> Plant for TwoMassPlant<L> {
    fn interval(&mut self, u: f64, diffs: &mut [f64]) -> f64 {
        self.sub_steps
            .interval(&mut self.law, self.v2, diffs, |law, t, h, d| {
                let f = law.step(self.x2, self.v2, t, h, d);
                let fsp = self.k * (self.x1 - self.x2) + self.c * (self.v1 - self.v2);
                self.v1 += h * (u - fsp) / self.m1;
                let vp = self.v2 + h * (fsp - f) / self.m2;
                let v2 = implicit_velocity(law.model(), self.v2, vp, h / self.m2);
                let acc = ((v2 - self.v2) / h).abs();
                self.v2 = v2;
                self.x1 += h * self.v1;
                self.x2 += h * self.v2;
                (v2, acc)
            })
    }
    fn encoder(&self) -> f64 {
        self.x1
    }
    fn finite(&self) -> bool {
        self.x1.is_finite() && self.v1.is_finite() && self.x2.is_finite() && self.v2.is_finite()
    }
    fn rest_log(&self) -> &[(f64, bool)] {
        self.law.rest_log()
    }
}

/// Builds the plant of `spec` with friction `model` and shadow variants for
/// `hidden`, at rest at `x = 0`.
pub fn build(spec: &PlantSpec, model: Model, hidden: &[Effect]) -> Box<dyn Plant> {
    match spec {
        PlantSpec::Model | PlantSpec::NoisyVelocity { .. } => {
            Box::new(MassPlant::new(ModelLaw::new(model, hidden, 0.0), 0.0))
        }
        PlantSpec::Lugre { sigma0, sigma1 } => Box::new(MassPlant::new(
            LugreLaw::new(model, hidden, *sigma0, *sigma1),
            0.0,
        )),
        PlantSpec::MaxwellSlip {
            stiffness,
            break_force,
            damping,
        } => Box::new(MassPlant::new(
            MaxwellLaw::new(model, hidden, stiffness, break_force, damping),
            0.0,
        )),
        PlantSpec::Compliant { m1, m2, k, c, .. } => Box::new(TwoMassPlant::new(
            ModelLaw::new(model, hidden, 0.0),
            0.0,
            *m1,
            *m2,
            *k,
            *c,
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viscous_solve() {
        for &(p, c1, c2, n) in &[
            (1.0, 0.5, 0.0, 1.0),
            (1e-3, 0.1, 2.0, 0.3),
            (3.0, 0.0, 0.7, 1.8),
            (1e-9, 0.0, 5.0, 0.5),
            (0.2, 1e3, 1e2, 1.3),
        ] {
            let s = solve_viscous(p, c1, c2, n);
            let r = s * (1.0 + c1) + c2 * s.powf(n) - p;
            assert!(
                r.abs() <= 1e-12 * p.max(1e-300) + 1e-18,
                "{p} {c1} {c2} {n}: {r}"
            );
            assert!(s >= 0.0 && s <= p);
        }
    }

    #[test]
    fn small_step_choice() {
        assert_eq!(small_ticks(1e6, 1.0), 5);
        assert_eq!(small_ticks(1e10, 0.5), 1);
    }
}
