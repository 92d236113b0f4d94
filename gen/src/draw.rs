//! Drawing a record's parameters from its seed.
//!
//! Every random choice comes from a ChaCha8 stream keyed by
//! `(seed, purpose, attempt)`, so a record depends on its seed only (and on
//! the overrides given), never on how many records are generated with it.
//!
//! Ranges (log-uniform unless said): m 0.5–50 kg; Fc 0.5–50 N; Fs/Fc
//! uniform 1.1–1.8; V 0.3–5 mm/s; δ uniform 0.6–2.2; encoder q 0.1–2 µm;
//! z_max = 6–100 counts; Π = √(2·Fs·z_max/m)/V ∈ [0.5, 15]; force noise std
//! 0.1–0.6 % of Fc; length 20–40 s; loop bandwidth 10–40 Hz.

use crate::excite::{Context, Family};
use crate::friction::{
    Asymmetry, Drift, DwellStiction, Effect, Effects, FrictionalLag, Model, NonlinearViscous,
    Offset, Params, PositionRipple,
};
use crate::plants::{PlantKind, PlantSpec};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;

/// Which records a suite holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// MODEL.md plant, dynamic families.
    Model,
    /// Outside plants (LuGre, Maxwell-slip, compliant, noisy velocity).
    Outside,
    /// Steady-state records.
    Steady,
    /// A mix: ~15 % steady, the rest dynamic with ~35 % outside plants.
    Mixed,
}

impl Kind {
    /// Parses `model|outside|steady|mixed`.
    pub fn from_name(s: &str) -> Option<Kind> {
        match s {
            "model" => Some(Kind::Model),
            "outside" => Some(Kind::Outside),
            "steady" => Some(Kind::Steady),
            "mixed" => Some(Kind::Mixed),
            _ => None,
        }
    }
}

/// Random-stream purposes.
#[derive(Clone, Copy, Debug)]
pub enum Purpose {
    /// Family, plant and hidden effects (never redrawn).
    Choice = 0,
    /// The excitation schedule.
    Schedule = 1,
    /// Force noise on the logged u.
    Noise = 2,
    /// Encoder jitter.
    Jitter = 3,
    /// Numeric parameters (redrawn with each attempt).
    Params = 4,
}

/// The random stream for `(seed, purpose, attempt)`.
pub fn stream(seed: u64, purpose: Purpose, attempt: u32) -> ChaCha8Rng {
    let mut r = ChaCha8Rng::seed_from_u64(seed);
    r.set_stream((purpose as u64) << 32 | u64::from(attempt));
    r
}

/// Overrides of the drawn choices.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// Family instead of the drawn one.
    pub family: Option<Family>,
    /// Plant instead of the drawn one.
    pub plant: Option<PlantKind>,
    /// Hidden effects instead of the drawn ones.
    pub effects: Option<Vec<Effect>>,
    /// For steady records: make the model lack `stribeck` (`Fs = Fc`).
    pub stribeck_absent: Option<bool>,
    /// Record length [s] instead of the drawn one (tests use short records).
    pub duration: Option<f64>,
}

/// A drawn record (before the effect sizes are fitted to the visibility
/// targets).
#[derive(Clone, Debug)]
pub struct Draw {
    /// Seed.
    pub seed: u64,
    /// Attempt (sub-seed) that gave this draw.
    pub attempt: u32,
    /// Excitation family.
    pub family: Family,
    /// Plant.
    pub plant: PlantKind,
    /// Plant parameters.
    pub spec: PlantSpec,
    /// True friction model with the hidden effects at pilot sizes.
    pub model: Model,
    /// Hidden effects.
    pub hidden: Vec<Effect>,
    /// Visibility targets (effect RMS / noise std), one per hidden effect.
    pub targets: Vec<f64>,
    /// Steady records only: the model lacks `stribeck` (`Fs = Fc`).
    pub stribeck_absent: bool,
    /// Encoder count `q` [m].
    pub q: f64,
    /// Force-noise std on the logged u [N].
    pub noise_std: f64,
    /// Record length [s].
    pub duration: f64,
    /// Controller bandwidth [Hz].
    pub bandwidth_hz: f64,
    /// What the excitation knows.
    pub ctx: Context,
}

impl Draw {
    /// `Π = √(2·Fs·z_max/m)/V`.
    pub fn pi(&self) -> f64 {
        let p = &self.model.p;
        (2.0 * p.fs * p.z_max / p.mass).sqrt() / p.v_stribeck
    }
}

/// Log-uniform in [a, b].
pub(crate) fn lu(rng: &mut ChaCha8Rng, a: f64, b: f64) -> f64 {
    (rng.gen_range(a.ln()..=b.ln())).exp()
}

/// Uniform in [a, b].
pub(crate) fn uni(rng: &mut ChaCha8Rng, a: f64, b: f64) -> f64 {
    rng.gen_range(a..=b)
}

/// ±1 with equal odds.
pub(crate) fn sign(rng: &mut ChaCha8Rng) -> f64 {
    if rng.gen_bool(0.5) {
        1.0
    } else {
        -1.0
    }
}

/// Largest relative level change of `drift` over a record.
pub const DRIFT_MAX: f64 = 0.3;
/// Largest `|a|` of `asymmetry`.
pub const ASYM_MAX: f64 = 0.5;
/// Range of `τ_L` [s] the visibility fit may use.
pub const LAG_RANGE: (f64, f64) = (1e-3, 0.2);

/// Draws record `seed` (attempt `attempt`) of `kind` with `ov` applied.
/// Errors name an inconsistent override.
pub fn draw(seed: u64, attempt: u32, kind: Kind, ov: &Overrides) -> Result<Draw, String> {
    let mut r = stream(seed, Purpose::Choice, 0);
    let rng = &mut r;
    // Family and plant.
    let fam_u: f64 = rng.gen();
    let dyn_i = rng.gen_range(0..Family::DYNAMIC.len());
    let out_i = rng.gen_range(0..PlantKind::OUTSIDE.len());
    let plant_u: f64 = rng.gen();
    let mut family = match kind {
        Kind::Steady => Family::Steady,
        Kind::Mixed if fam_u < 0.15 => Family::Steady,
        _ => Family::DYNAMIC[dyn_i],
    };
    if let Some(f) = ov.family {
        family = f;
    }
    let mut plant = match kind {
        Kind::Outside => PlantKind::OUTSIDE[out_i],
        Kind::Mixed if plant_u < 0.35 => PlantKind::OUTSIDE[out_i],
        _ => PlantKind::Model,
    };
    if family == Family::Steady {
        plant = PlantKind::Model;
    }
    if let Some(p) = ov.plant {
        if family == Family::Steady && p != PlantKind::Model {
            return Err("steady records use the model plant".into());
        }
        plant = p;
    }
    // Hidden effects: none ~15 %, one ~65 %, two ~20 %.
    let n_u: f64 = rng.gen();
    let n_eff = if n_u < 0.15 {
        0
    } else if n_u < 0.80 {
        1
    } else {
        2
    };
    // Candidates: index 8 stands for "stribeck absent" (steady only).
    let mut cands: Vec<usize> = Vec::new();
    for (i, e) in Effect::ALL.iter().enumerate() {
        let ok = if family == Family::Steady {
            e.steady_visible()
        } else {
            plant.supports(*e)
        };
        if ok {
            cands.push(i);
        }
    }
    if family == Family::Steady {
        cands.push(8);
    }
    let mut picked: Vec<usize> = Vec::new();
    while picked.len() < n_eff {
        let c = cands[rng.gen_range(0..cands.len())];
        if !picked.contains(&c) {
            picked.push(c);
        }
    }
    let mut stribeck_absent = picked.contains(&8);
    let mut hidden: Vec<Effect> = picked
        .iter()
        .filter(|&&i| i < 8)
        .map(|&i| Effect::ALL[i])
        .collect();
    if let Some(e) = &ov.effects {
        hidden = e.clone();
        stribeck_absent = false;
    }
    if let Some(s) = ov.stribeck_absent {
        stribeck_absent = s;
    }
    if stribeck_absent && family != Family::Steady {
        return Err("`stribeck-absent` is for steady records only".into());
    }
    for e in &hidden {
        if family == Family::Steady && !e.steady_visible() {
            return Err(format!(
                "effect `{}` cannot be seen in a steady-state record (steady allows viscous, nonlinear_viscous, offset, asymmetry, stribeck-absent)",
                e.name()
            ));
        }
        if !plant.supports(*e) {
            return Err(format!(
                "effect `{}` needs the presliding law of the `model` plant; plant `{}` does not carry it",
                e.name(),
                plant.name()
            ));
        }
    }
    hidden.sort();
    hidden.dedup();

    // Numeric parameters: their own stream, redrawn with each attempt.
    let mut r = stream(seed, Purpose::Params, attempt);
    let rng = &mut r;

    // Base parameters with the Π check.
    let fc = lu(rng, 0.5, 50.0);
    let fs = fc * uni(rng, 1.1, 1.8);
    let fs = if stribeck_absent { fc } else { fs };
    let delta = uni(rng, 0.6, 2.2);
    let q = lu(rng, 0.1e-6, 2e-6);
    let z_max = lu(rng, 6.0, 100.0) * q;
    let mut mass = lu(rng, 0.5, 50.0);
    let mut v_s = lu(rng, 0.3e-3, 5e-3);
    let pi = |m: f64, v: f64| (2.0 * fs * z_max / m).sqrt() / v;
    let mut tries = 0;
    while !(0.5..=15.0).contains(&pi(mass, v_s)) && tries < 400 {
        if tries % 2 == 0 {
            v_s = lu(rng, 0.3e-3, 5e-3);
        } else {
            mass = lu(rng, 0.5, 50.0);
        }
        tries += 1;
    }
    if !(0.5..=15.0).contains(&pi(mass, v_s)) {
        // Put V where Π = 5 (z_max and Fs fixed).
        v_s = (2.0 * fs * z_max / mass).sqrt() / 5.0;
    }
    let noise_std = fc * uni(rng, 0.001, 0.006);
    let mut duration = uni(rng, 20.0, 40.0);
    if let Some(d) = ov.duration {
        duration = d;
    }
    let mut bandwidth_hz = uni(rng, 10.0, 40.0);

    // Effect parameters at pilot sizes, one target per hidden effect.
    let mut p = Params {
        mass,
        fc,
        fs,
        v_stribeck: v_s,
        delta,
        sigma: 0.0,
        z_max,
    };
    let mut e = Effects::default();
    let mut targets = Vec::new();
    for &eff in &hidden {
        let target = lu(rng, 3.0, 100.0);
        targets.push(target);
        let ft = target * noise_std;
        match eff {
            Effect::Viscous => p.sigma = ft / (4.0 * v_s),
            Effect::Offset => e.offset = Some(Offset { f0: ft * sign(rng) }),
            Effect::Asymmetry => {
                e.asymmetry = Some(Asymmetry {
                    a: (ft / fc).clamp(0.03, 0.3) * sign(rng),
                })
            }
            Effect::PositionRipple => {
                e.position_ripple = Some(PositionRipple {
                    amplitude: ft * 2f64.sqrt(),
                    wavelength: lu(rng, 0.5e-3, 20e-3),
                    phase: uni(rng, 0.0, TAU),
                })
            }
            Effect::DwellStiction => {
                e.dwell_stiction = Some(DwellStiction {
                    delta_fs: 2.0 * ft,
                    gamma: lu(rng, 0.2, 2.0),
                    v_rest: 0.05 * v_s,
                })
            }
            Effect::FrictionalLag => {
                e.frictional_lag = Some(FrictionalLag {
                    tau_l: lu(rng, 5e-3, 50e-3),
                })
            }
            Effect::Drift => {
                let b = (ft * 3f64.sqrt() / (fc * duration)).min(DRIFT_MAX / duration);
                e.drift = Some(Drift {
                    beta: b * sign(rng),
                })
            }
            Effect::NonlinearViscous => {
                let n = if rng.gen_bool(0.5) {
                    uni(rng, 0.3, 0.8)
                } else {
                    uni(rng, 1.3, 2.0)
                };
                e.nonlinear_viscous = Some(NonlinearViscous {
                    sigma_n: ft / (4.0 * v_s).powf(n),
                    n,
                })
            }
        }
    }
    let model = Model { p, e };

    // Plant parameters.
    let spec = match plant {
        PlantKind::Model => PlantSpec::Model,
        PlantKind::NoisyVelocity => PlantSpec::NoisyVelocity {
            jitter_prob: uni(rng, 0.01, 0.03),
        },
        PlantKind::Lugre => {
            let sigma0 = fs / z_max;
            PlantSpec::Lugre {
                sigma0,
                sigma1: (sigma0 * mass).sqrt() * uni(rng, 0.1, 0.5),
            }
        }
        PlantKind::MaxwellSlip => {
            let n = rng.gen_range(4..=8);
            let mut r: Vec<f64> = (0..n).map(|_| lu(rng, 0.03, 1.0)).collect();
            r.sort_by(f64::total_cmp);
            r[n - 1] = 1.0;
            let wts: Vec<f64> = (0..n).map(|_| uni(rng, 0.5, 1.5)).collect();
            let wsum: f64 = wts.iter().sum();
            let break_force: Vec<f64> = wts.iter().map(|w| fs * w / wsum).collect();
            let stiffness: Vec<f64> = break_force
                .iter()
                .zip(&r)
                .map(|(w, ri)| w / (ri * z_max))
                .collect();
            let k_tot: f64 = stiffness.iter().sum();
            let zeta = 0.02;
            let damping = stiffness
                .iter()
                .map(|k| k * 2.0 * zeta * (mass / k_tot).sqrt())
                .collect();
            PlantSpec::MaxwellSlip {
                stiffness,
                break_force,
                damping,
            }
        }
        PlantKind::Compliant => {
            let f_r = uni(rng, 20.0, 80.0);
            let frac = uni(rng, 0.2, 0.6);
            let m1 = mass * frac;
            let m2 = mass - m1;
            let mu = m1 * m2 / mass;
            let w = TAU * f_r;
            let zeta = uni(rng, 0.02, 0.1);
            bandwidth_hz = bandwidth_hz.min(f_r / 3.0).min(60.0 * frac);
            PlantSpec::Compliant {
                m1,
                m2,
                k: w * w * mu,
                c: 2.0 * zeta * w * mu,
                resonance_hz: f_r,
            }
        }
    };

    let f_targets: f64 = targets.iter().sum::<f64>() * noise_std;
    let (gains, vgains) = Context::gains_for(mass, bandwidth_hz);
    let ctx = Context {
        mass,
        fc,
        fs,
        v_s,
        z_max,
        q,
        duration,
        u_max: 4.0 * fs + 3.0 * f_targets,
        gains,
        vgains,
    };
    Ok(Draw {
        seed,
        attempt,
        family,
        plant,
        spec,
        model,
        hidden,
        targets,
        stribeck_absent,
        q,
        noise_std,
        duration,
        bandwidth_hz,
        ctx,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_are_in_range_and_deterministic() {
        for seed in 0..200 {
            let d = draw(seed, 0, Kind::Mixed, &Overrides::default()).unwrap();
            let d2 = draw(seed, 0, Kind::Mixed, &Overrides::default()).unwrap();
            assert_eq!(d.model, d2.model);
            let p = d.model.p;
            assert!((0.5..=50.0).contains(&p.mass));
            assert!((0.5..=50.0).contains(&p.fc));
            if !d.stribeck_absent {
                assert!(p.fs >= 1.1 * p.fc * 0.999999 && p.fs <= 1.8 * p.fc * 1.000001);
            }
            assert!((0.1e-6..=2e-6).contains(&d.q));
            let c = p.z_max / d.q;
            assert!((6.0..=100.0 + 1e-9).contains(&c));
            assert!((0.5..=15.0 + 1e-9).contains(&d.pi()), "Π {}", d.pi());
            assert!(d.hidden.len() <= 2);
            assert!((20.0..=40.0).contains(&d.duration));
            assert!(d.noise_std >= 0.001 * p.fc && d.noise_std <= 0.006 * p.fc);
            for t in &d.targets {
                assert!((3.0..=100.0).contains(t));
            }
        }
    }
}
