//! Synthetic measurements with hidden effects (`breakaway-lab synth`).
//!
//! A truth model (MODEL.md §2–§3 base plus the requested §5 effects, values
//! drawn from the seed) drives the plant `m·ẍ = u − F` (§1) under a
//! realistic excitation, sampled at 1 kHz:
//!
//! * rests of varied length (u = 0) — for `dwell_stiction`;
//! * force-ramp break-away tests `u = ±k·t` with rates independent of the
//!   rest lengths — so that dwell time and the rate dependence the presliding
//!   model already produces (§4) can be told apart;
//! * closed-loop velocity plateaus in both directions (PI velocity loop at
//!   1 kHz, zero-order hold) at speeds from about 3·V to 20·V — for
//!   `viscous`, `offset`/`asymmetry` (both directions), `position_ripple`
//!   (each plateau travels several wavelengths) and `drift`;
//! * slow reversals (a cosine velocity reference through zero) on every
//!   other cycle — presliding after turning points and the low-speed
//!   hysteresis of `frictional_lag`.
//!
//! The plant is integrated with semi-implicit Euler at 50 sub-steps per
//! sample (h = 20 µs), the friction memory updated at every sub-step
//! ([`Friction::update`]); the presliding stiffness gives `ω·h < 0.05`.
//! Noise: the position is quantised (encoder), the logged force carries
//! white noise. The truth models keep `Π = √(2·Fs·z_max/m)/V` below 2.5
//! (MODEL.md §8: rests are quiet).

use crate::data::Record;
use crate::reference::{
    Asymmetry, Drift, DwellStiction, Effect, Effects, Friction, FrictionalLag, Model,
    NonlinearViscous, Offset, PositionRipple,
};
use crate::Error;
use std::f64::consts::PI;

/// Whether `synth` can hide `effect`: every effect of the catalogue of
/// MODEL.md §5 but `stribeck` and `presliding`, which the base model always
/// has.
pub fn hideable(effect: Effect) -> bool {
    !matches!(effect, Effect::Stribeck | Effect::Presliding)
}

/// Parses a list of hidden effects: `none`, or names of [`hideable`]
/// effects separated by commas (repeats count once). The error names the
/// item at fault.
pub fn parse_hidden(list: &str) -> Result<Vec<Effect>, String> {
    if list.trim() == "none" {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for name in list.split(',').map(str::trim) {
        if name == "none" {
            return Err("`none` stands alone: it cannot be listed with effects".into());
        }
        let effect = name
            .parse::<Effect>()
            .ok()
            .filter(|&e| hideable(e))
            .ok_or_else(|| {
                let names: Vec<&str> = Effect::ALL
                    .into_iter()
                    .filter(|&e| hideable(e))
                    .map(Effect::name)
                    .collect();
                format!(
                    "unknown effect `{name}` (expected {} or none)",
                    names.join(", ")
                )
            })?;
        if !out.contains(&effect) {
            out.push(effect);
        }
    }
    Ok(out)
}

/// Measurement noise level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Noise {
    /// Encoder 0.1 µm, force noise 0.3 % of Fc.
    Low,
    /// Encoder 0.4 µm, force noise 1.5 % of Fc.
    High,
}

impl Noise {
    /// Parses `low` / `high`.
    pub fn parse(s: &str) -> Option<Noise> {
        match s {
            "low" => Some(Noise::Low),
            "high" => Some(Noise::High),
            _ => None,
        }
    }

    /// The name.
    pub fn name(self) -> &'static str {
        match self {
            Noise::Low => "low",
            Noise::High => "high",
        }
    }
}

/// What to generate.
#[derive(Clone, Debug, PartialEq)]
pub struct SynthSpec {
    /// Hidden effects ([`hideable`] ones; `stribeck` and `presliding` are
    /// in every base model).
    pub effects: Vec<Effect>,
    /// Seed of every random choice.
    pub seed: u64,
    /// Noise level.
    pub noise: Noise,
    /// Base parameter set, 0 or 1.
    pub set: usize,
}

/// A small deterministic generator (SplitMix64).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// Seeded generator.
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x9E37_79B9_7F4A_7C15)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }

    /// ±1 with equal odds.
    pub fn sign(&mut self) -> f64 {
        if self.next_u64() & 1 == 0 {
            1.0
        } else {
            -1.0
        }
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.unit().max(1e-300);
        let u2 = self.unit();
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }

    /// Shuffles `v` in place (Fisher–Yates).
    pub fn shuffle<T>(&mut self, v: &mut [T]) {
        for i in (1..v.len()).rev() {
            let j = (self.next_u64() % (i as u64 + 1)) as usize;
            v.swap(i, j);
        }
    }
}

/// Sampling interval of the synthetic records [s].
pub const DT: f64 = 1e-3;
/// Sub-steps per sample.
const SUB: usize = 50;
/// Duration of the smooth start of a force ramp [s].
const RAMP_ONSET: f64 = 0.05;
/// Nominal record length used to scale `drift` [s].
const NOMINAL_SPAN: f64 = 15.0;

/// The truth model of `spec`; an error names the invalid parameter.
pub fn truth_model(spec: &SynthSpec) -> Result<Model, Error> {
    let mut rng = Rng::new(spec.seed.wrapping_mul(31).wrapping_add(7));
    let jitter = |rng: &mut Rng| rng.range(0.9, 1.1);
    let mut m = if spec.set == 0 {
        Model {
            mass: 1.0,
            fc: 1.0,
            fs: 1.5,
            v_stribeck: 3e-3,
            delta: 2.0,
            sigma: 0.0,
            z_max: 1e-5,
            epsilon: 0.0,
            effects: Effects::default(),
        }
    } else {
        Model {
            mass: 2.0,
            fc: 2.0,
            fs: 2.7,
            v_stribeck: 5e-3,
            delta: 1.0,
            sigma: 0.0,
            z_max: 2e-5,
            epsilon: 0.0,
            effects: Effects::default(),
        }
    };
    m.mass *= jitter(&mut rng);
    let excess = (m.fs - m.fc) * jitter(&mut rng);
    m.fc *= jitter(&mut rng);
    m.fs = m.fc + excess;
    m.v_stribeck *= jitter(&mut rng);
    m.z_max *= jitter(&mut rng);
    let fc = m.fc;
    let v_stribeck = m.v_stribeck;
    for &effect in &spec.effects {
        let e = &mut m.effects;
        match effect {
            Effect::Viscous => m.sigma = rng.range(0.25, 0.4) * fc / 0.05,
            Effect::Offset => {
                e.offset = Some(Offset {
                    f0: rng.sign() * rng.range(0.1, 0.2) * fc,
                })
            }
            Effect::Asymmetry => {
                e.asymmetry = Some(Asymmetry {
                    a: rng.sign() * rng.range(0.1, 0.2),
                })
            }
            Effect::PositionRipple => {
                e.position_ripple = Some(PositionRipple {
                    amplitude: rng.range(0.08, 0.15) * fc,
                    wavelength: rng.range(2e-3, 4e-3),
                    phase: rng.range(0.0, 2.0 * PI),
                })
            }
            Effect::DwellStiction => {
                e.dwell_stiction = Some(DwellStiction {
                    delta_fs: rng.range(0.5, 0.8) * fc,
                    gamma: rng.range(0.2, 0.5),
                    // A rest is slower than 5 % of the Stribeck velocity.
                    // A threshold near zero (3e-7 m/s was used) is crossed
                    // again by the ringing of the presliding spring at
                    // every ramp start, which restarted the rest interval:
                    // t_d at break-away was ~0 in almost every test and the
                    // effect was absent from the data. 0.05·V also covers
                    // the presliding creep before break-away.
                    v_rest: 0.05 * v_stribeck,
                })
            }
            Effect::FrictionalLag => {
                e.frictional_lag = Some(FrictionalLag {
                    tau_l: rng.range(0.02, 0.05),
                })
            }
            Effect::Drift => {
                e.drift = Some(Drift {
                    beta: rng.sign() * rng.range(0.2, 0.3) / NOMINAL_SPAN,
                })
            }
            Effect::NonlinearViscous => {
                // Concave or convex strengthening, never near n = 1.
                let n = if rng.sign() > 0.0 {
                    rng.range(0.4, 0.7)
                } else {
                    rng.range(1.4, 1.8)
                };
                e.nonlinear_viscous = Some(NonlinearViscous {
                    sigma_n: rng.range(0.25, 0.4) * fc / 0.05f64.powf(n),
                    n,
                })
            }
            Effect::Stribeck | Effect::Presliding => {} // always in the base model
        }
    }
    m.validate()
        .map_err(|e| Error::Runtime(format!("truth model: {e}")))?;
    Ok(m)
}

/// One step of the excitation.
#[derive(Clone, Copy, Debug)]
enum Segment {
    /// `u = 0` for this long [s].
    Rest(f64),
    /// `u = dir·k·τ` until the speed exceeds the switch speed.
    Ramp { dir: f64, k: f64 },
    /// Closed-loop motion: plateau at `dir·speed` for `hold` [s], with a
    /// slow reversal when `reversal`, then back to 0.
    Move {
        dir: f64,
        speed: f64,
        hold: f64,
        reversal: bool,
    },
    /// `u` from its value to 0 in this long [s].
    Release(f64),
}

/// Velocity reference of a `Move` at `tau` [s] into it; `None` when done.
/// Returns `(v_ref, a_ref)`.
fn move_reference(
    v0: f64,
    dir: f64,
    speed: f64,
    hold: f64,
    reversal: bool,
    v_rev: f64,
    tau: f64,
) -> Option<(f64, f64)> {
    const ACC: f64 = 0.25; // [m/s²]
    let target = dir * speed;
    let t1 = (target - v0).abs() / ACC;
    if tau < t1 {
        let s = (target - v0).signum();
        return Some((v0 + s * ACC * tau, s * ACC));
    }
    let mut tau = tau - t1;
    if tau < hold {
        return Some((target, 0.0));
    }
    tau -= hold;
    let mut v_end = target;
    if reversal {
        let ta = (speed - v_rev) / ACC;
        if tau < ta {
            return Some((target - dir * ACC * tau, -dir * ACC));
        }
        tau -= ta;
        const T_REV: f64 = 0.7;
        let w = 2.0 * PI / T_REV;
        if tau < 1.5 * T_REV {
            return Some((
                dir * v_rev * (w * tau).cos(),
                -dir * v_rev * w * (w * tau).sin(),
            ));
        }
        tau -= 1.5 * T_REV;
        v_end = -dir * v_rev;
    }
    let td = v_end.abs() / ACC;
    if tau < td {
        return Some((v_end - v_end.signum() * ACC * tau, -v_end.signum() * ACC));
    }
    tau -= td;
    (tau < 0.1).then_some((0.0, 0.0))
}

/// True velocity [m/s] and dwell time `t_d` [s] of the truth per sample.
pub type Trace = Vec<(f64, f64)>;

/// Generates the record and its truth model.
pub fn generate(spec: &SynthSpec) -> Result<(Record, Model), Error> {
    generate_traced(spec).map(|(r, m, _)| (r, m))
}

/// [`generate`], also returning the truth's true velocity and dwell time
/// `t_d` [s] at every sample (for checks).
pub fn generate_traced(spec: &SynthSpec) -> Result<(Record, Model, Trace), Error> {
    let truth = truth_model(spec)?;
    let mut rng = Rng::new(spec.seed);
    let (q, f_noise) = match spec.noise {
        Noise::Low => (1e-7, 0.003 * truth.fc),
        Noise::High => (4e-7, 0.015 * truth.fc),
    };
    let n_cycles = 6;
    let mut rests = vec![0.05, 0.15, 0.35, 0.7, 1.2, 1.8];
    let mut rates = vec![2.0, 4.0, 8.0, 3.0, 6.0, 2.5];
    let mut speeds = vec![3.0, 6.0, 10.0, 4.0, 15.0, 20.0];
    rng.shuffle(&mut rests);
    rng.shuffle(&mut rates);
    rng.shuffle(&mut speeds);
    let v_nom = if spec.set == 0 { 3e-3 } else { 5e-3 };
    let first_dir = rng.sign();
    let mut segments = Vec::new();
    for c in 0..n_cycles {
        let dir = if c % 2 == 0 { first_dir } else { -first_dir };
        let speed = speeds[c] * v_nom;
        segments.push(Segment::Rest(rests[c]));
        segments.push(Segment::Ramp {
            dir,
            k: rates[c] * truth.fc,
        });
        segments.push(Segment::Move {
            dir,
            speed,
            hold: (0.012 / speed).clamp(0.25, 0.8),
            reversal: c % 2 == 1,
        });
        segments.push(Segment::Release(0.05));
    }
    segments.push(Segment::Rest(0.3));

    // Plant and loop.
    let m = truth.mass;
    let kp = 250.0 * m;
    let ki = kp * 50.0;
    let v_switch = 2.0 * truth.v_stribeck;
    let v_rev = 2.5 * truth.v_stribeck;
    let h = DT / SUB as f64;
    let mut fr = Friction::new(&truth, 0.0, 0.0, 0.0);
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let mut f = fr.update(&truth, 0.0, 0.0, 0.0);
    let mut rec = Record {
        t: Vec::new(),
        u: Vec::new(),
        x: Vec::new(),
        v: None,
        source: "synth".into(),
    };
    let mut t = 0.0;
    let mut u = 0.0f64;
    let mut trace = Vec::new();
    for seg in segments {
        let t_seg = t;
        let u_seg = u;
        let mut integ = u;
        let v0 = v;
        let mut s_count = 0usize;
        loop {
            let tau = s_count as f64 * DT;
            let cmd = match seg {
                Segment::Rest(d) => (tau < d).then_some(0.0),
                Segment::Ramp { dir, k } => {
                    let fmax = 4.0 * truth.fs;
                    // Smooth onset over RAMP_ONSET: an abrupt change of the
                    // force rate rings the undamped presliding spring and
                    // its velocity touches zero once per period.
                    let ramp = if tau < RAMP_ONSET {
                        k * tau * tau / (2.0 * RAMP_ONSET)
                    } else {
                        k * (tau - 0.5 * RAMP_ONSET)
                    };
                    (v.abs() < v_switch && ramp < fmax).then_some(u_seg + dir * ramp)
                }
                Segment::Move {
                    dir,
                    speed,
                    hold,
                    reversal,
                } => move_reference(v0, dir, speed, hold, reversal, v_rev, tau).map(|(vr, ar)| {
                    let e = vr - v;
                    integ += ki * e * DT;
                    kp * e + integ + m * ar
                }),
                Segment::Release(d) => (tau < d).then_some(u_seg * (1.0 - tau / d)),
            };
            let Some(cmd) = cmd else { break };
            u = cmd;
            rec.t.push(t);
            rec.u.push(u + f_noise * rng.normal());
            rec.x.push(q * (x / q).round());
            trace.push((v, fr.dwell_time()));
            for s in 0..SUB {
                let ts = t + (s + 1) as f64 * h;
                v += h * (u - f) / m;
                x += h * v;
                f = fr.update(&truth, ts, x, v);
            }
            if !(x.is_finite() && v.is_finite()) {
                return Err(Error::Runtime(format!(
                    "synthetic plant diverged at t = {t} s"
                )));
            }
            s_count += 1;
            t = (rec.t.len()) as f64 * DT;
            let _ = t_seg;
        }
    }
    Ok((rec, truth, trace))
}
