//! One record from its seed: draw, simulate, fit the hidden effects' sizes
//! to their visibility targets, add the force noise.
//!
//! Visibility of an effect = RMS over the record's samples of
//! (friction with the effect − friction without it), both evaluated along
//! the simulated motion (true position and velocity), divided by the force
//! noise std. Effect sizes start at a pilot estimate; after each simulation
//! the effects whose force is linear in a parameter are rescaled by
//! target/measured, `frictional_lag`'s `τ_L` by a log-secant step; the
//! record is re-simulated until every visibility is within 10 % of its
//! target (at most 3 simulations, 4 with `frictional_lag` or
//! `dwell_stiction`). Parameters held
//! at a bound (|a| ≤ 0.5, drift ≤ 30 % over the record, τ_L ∈ [1, 200] ms,
//! ΔFs ≤ Fs) are reported as clamped; a draw left with a visibility below 3
//! is redrawn with the next sub-seed.

use crate::draw::{self, Draw, Kind, Overrides, Purpose};
use crate::excite::{self, Family, Jitter, SimOut, Unstable};
use crate::friction::{Effect, Model};
use crate::plants::{self, PlantSpec};
use rand::Rng;
use rand_distr::{Distribution, Normal};

/// Attempts (sub-seeds) before a seed is given up.
pub const MAX_ATTEMPTS: u32 = 8;
/// Smallest acceptable visibility; a draw whose effect stays below it (its
/// parameter at a bound) is redrawn.
pub const MIN_VISIBILITY: f64 = 3.0;
/// Relative visibility error that triggers another simulation.
pub const TOL: f64 = 0.1;

/// The samples of a record.
#[derive(Clone, Debug, PartialEq)]
pub enum Data {
    /// Time record (MODEL.md §6): `t = k·1 ms`, logged `u` (with noise),
    /// quantised `x`.
    Time {
        /// Logged force [N] (applied force + Gaussian noise).
        u: Vec<f64>,
        /// Applied force [N].
        u_clean: Vec<f64>,
        /// Logged position [m].
        x: Vec<f64>,
    },
    /// Steady-state record: speed [m/s] and mean force [N] per run.
    Steady {
        /// Speeds [m/s].
        v: Vec<f64>,
        /// Mean forces [N] (with noise).
        u: Vec<f64>,
    },
}

/// A generated record.
#[derive(Clone, Debug)]
pub struct Generated {
    /// The draw that gave the record.
    pub draw: Draw,
    /// The true model with the fitted effect sizes.
    pub model: Model,
    /// Measured visibility per hidden effect (effect RMS / noise std).
    pub visibility: Vec<f64>,
    /// Whether each hidden effect's parameter was held at a bound.
    pub clamped: Vec<bool>,
    /// Simulations run for the final attempt.
    pub sims: u32,
    /// Why earlier attempts were redrawn.
    pub redraws: Vec<String>,
    /// The samples.
    pub data: Data,
    /// With `dwell_stiction` hidden, the changes of the plant's dwell clock
    /// in the record's simulation: (time [s], whether a rest begins).
    pub rest_log: Vec<(f64, bool)>,
}

impl Generated {
    /// `effect=visibility` per hidden effect joined by `sep`; `None` when
    /// no effect is hidden.
    pub fn visibilities(&self, sep: &str) -> Option<String> {
        let d = &self.draw;
        (!d.hidden.is_empty()).then(|| {
            d.hidden
                .iter()
                .zip(&self.visibility)
                .map(|(e, v)| format!("{}={:.1}", e.name(), v))
                .collect::<Vec<_>>()
                .join(sep)
        })
    }

    /// Record name `s<seed>_<family>[_<plant>]_<effects|null>`.
    pub fn name(&self) -> String {
        let d = &self.draw;
        let mut parts: Vec<String> = d.hidden.iter().map(|e| e.name().to_string()).collect();
        if d.stribeck_absent {
            parts.push("stribeck-absent".into());
        }
        let eff = if parts.is_empty() {
            "null".to_string()
        } else {
            parts.join("+")
        };
        let plant = if d.plant == plants::PlantKind::Model {
            String::new()
        } else {
            format!("_{}", d.plant.name())
        };
        format!("s{:06}_{}{}_{}", d.seed, d.family.name(), plant, eff)
    }
}

/// The parameter of `e` that its force is (about) linear in, or `τ_L`;
/// `None` when the effect is absent.
fn param_mut(m: &mut Model, e: Effect) -> Option<&mut f64> {
    let t = &mut m.e;
    match e {
        Effect::Viscous => Some(&mut m.p.sigma),
        Effect::Offset => t.offset.as_mut().map(|o| &mut o.f0),
        Effect::Asymmetry => t.asymmetry.as_mut().map(|a| &mut a.a),
        Effect::PositionRipple => t.position_ripple.as_mut().map(|r| &mut r.amplitude),
        Effect::DwellStiction => t.dwell_stiction.as_mut().map(|d| &mut d.delta_fs),
        Effect::FrictionalLag => t.frictional_lag.as_mut().map(|l| &mut l.tau_l),
        Effect::Drift => t.drift.as_mut().map(|d| &mut d.beta),
        Effect::NonlinearViscous => t.nonlinear_viscous.as_mut().map(|n| &mut n.sigma_n),
    }
}

/// The parameter of `e` that its force is (about) linear in, or `τ_L`
/// (0 when the effect is absent).
pub fn param(m: &Model, e: Effect) -> f64 {
    param_mut(&mut m.clone(), e).map_or(0.0, |x| *x)
}

/// Sets the parameter of [`param`] (nothing when the effect is absent).
pub fn set_param(m: &mut Model, e: Effect, v: f64) {
    if let Some(x) = param_mut(m, e) {
        *x = v;
    }
}

/// Holds `v` within the bounds of `e`; returns the value and whether it
/// was held.
fn bound(e: Effect, v: f64, m: &Model, duration: f64) -> (f64, bool) {
    let lim = |v: f64, hi: f64| {
        if v.abs() > hi {
            (hi * v.signum(), true)
        } else {
            (v, false)
        }
    };
    match e {
        Effect::Asymmetry => lim(v, draw::ASYM_MAX),
        Effect::Drift => lim(v, draw::DRIFT_MAX / duration),
        Effect::DwellStiction => lim(v, m.p.fs),
        Effect::FrictionalLag => {
            let (lo, hi) = draw::LAG_RANGE;
            if v < lo {
                (lo, true)
            } else if v > hi {
                (hi, true)
            } else {
                (v, false)
            }
        }
        _ => (v, false),
    }
}

fn simulate(d: &Draw, model: Model) -> Result<SimOut, Unstable> {
    let mut plant = plants::build(&d.spec, model, &d.hidden);
    let jitter = match d.spec {
        PlantSpec::NoisyVelocity { jitter_prob } => Some(Jitter {
            prob: jitter_prob,
            rng: draw::stream(d.seed, Purpose::Jitter, d.attempt),
        }),
        _ => None,
    };
    excite::run(
        d.family,
        d.ctx,
        draw::stream(d.seed, Purpose::Schedule, d.attempt),
        plant.as_mut(),
        d.hidden.len(),
        jitter,
    )
}

/// The next parameter for effect `e` from its history of
/// `(parameter, visibility)` pairs.
fn next_param(e: Effect, hist: &[(f64, f64)], target: f64) -> f64 {
    let (p, vis) = hist[hist.len() - 1];
    if vis.is_nan() || vis <= 0.0 {
        return p * 10.0;
    }
    if e == Effect::FrictionalLag {
        let mut slope = 1.0;
        if hist.len() >= 2 {
            let (p1, v1) = hist[hist.len() - 2];
            if v1 > 0.0 && p1 != p && v1 != vis {
                slope = ((vis / v1).ln() / (p / p1).ln()).clamp(0.2, 3.0);
            }
        }
        p * (target / vis).powf(1.0 / slope)
    } else {
        p * target / vis
    }
}

fn generate_dynamic(d: &Draw) -> Result<Generated, Unstable> {
    let n = d.hidden.len();
    let mut model = d.model;
    let mut hist: Vec<Vec<(f64, f64)>> = vec![Vec::new(); n];
    let mut clamped = vec![false; n];
    let max_sims = if d
        .hidden
        .iter()
        .any(|e| matches!(e, Effect::FrictionalLag | Effect::DwellStiction))
    {
        4
    } else {
        3
    };
    let mut sims = 0;
    let (out, vis) = loop {
        let out = simulate(d, model)?;
        sims += 1;
        let vis: Vec<f64> = out.effect_rms.iter().map(|r| r / d.noise_std).collect();
        let mut changed = false;
        if sims == 1 {
            if let Some(r) = model.e.position_ripple.as_mut() {
                // At least 3 wavelengths over the travelled range.
                if out.x_range < 3.0 * r.wavelength {
                    r.wavelength = (out.x_range / 3.0).max(20.0 * d.q);
                    changed = true;
                }
            }
        }
        let ok: Vec<bool> = (0..n)
            .map(|j| clamped[j] || (vis[j] / d.targets[j] - 1.0).abs() <= TOL)
            .collect();
        if (ok.iter().all(|&b| b) && !changed) || sims >= max_sims {
            break (out, vis);
        }
        for j in 0..n {
            let e = d.hidden[j];
            if ok[j] && !(changed && e == Effect::PositionRipple) {
                continue;
            }
            hist[j].push((param(&model, e), vis[j]));
            let p = next_param(e, &hist[j], d.targets[j]);
            let (p, c) = bound(e, p, &model, d.duration);
            clamped[j] = c;
            set_param(&mut model, e, p);
        }
    };
    let mut noise_rng = draw::stream(d.seed, Purpose::Noise, d.attempt);
    let normal = Normal::new(0.0, d.noise_std).map_err(|e| Unstable(e.to_string()))?;
    let u: Vec<f64> = out
        .u
        .iter()
        .map(|u| u + normal.sample(&mut noise_rng))
        .collect();
    Ok(Generated {
        draw: d.clone(),
        model,
        visibility: vis,
        clamped,
        sims,
        redraws: Vec::new(),
        rest_log: out.rest_log,
        data: Data::Time {
            u,
            u_clean: out.u,
            x: out.x,
        },
    })
}

fn steady_vis(model: &Model, hidden: &[Effect], v: &[f64], noise: f64) -> Vec<f64> {
    hidden
        .iter()
        .map(|&e| {
            let w = model.without(e);
            let ss: f64 = v
                .iter()
                .map(|&s| (model.steady(s) - w.steady(s)).powi(2))
                .sum();
            (ss / v.len() as f64).sqrt() / noise
        })
        .collect()
}

fn generate_steady(d: &Draw) -> Generated {
    let mut rng = draw::stream(d.seed, Purpose::Schedule, d.attempt);
    let v_s = d.model.p.v_stribeck;
    let v_lo = v_s * (rng.gen_range((0.03f64).ln()..=(0.3f64).ln())).exp();
    let decades = rng.gen_range(3.0..=4.0);
    let n = rng.gen_range(12..=25);
    let mut v = Vec::with_capacity(2 * n);
    for dir in [1.0, -1.0] {
        for i in 0..n {
            v.push(dir * v_lo * 10f64.powf(decades * i as f64 / (n - 1) as f64));
        }
    }
    let mut model = d.model;
    let mut clamped = vec![false; d.hidden.len()];
    let vis0 = steady_vis(&model, &d.hidden, &v, d.noise_std);
    for (j, &e) in d.hidden.iter().enumerate() {
        if vis0[j] > 0.0 {
            let p = param(&model, e) * d.targets[j] / vis0[j];
            let (p, c) = bound(e, p, &model, d.duration);
            clamped[j] = c;
            set_param(&mut model, e, p);
        }
    }
    let vis = steady_vis(&model, &d.hidden, &v, d.noise_std);
    let mut noise_rng = draw::stream(d.seed, Purpose::Noise, d.attempt);
    let normal = Normal::new(0.0, d.noise_std).ok();
    let u = v
        .iter()
        .map(|&s| model.steady(s) + normal.map_or(0.0, |n| n.sample(&mut noise_rng)))
        .collect();
    Generated {
        draw: d.clone(),
        model,
        visibility: vis,
        clamped,
        sims: 0,
        redraws: Vec::new(),
        rest_log: Vec::new(),
        data: Data::Steady { v, u },
    }
}

/// Generates record `seed` of `kind` with the overrides `ov`. A draw whose
/// simulation runs away is redrawn with the next sub-seed (recorded in
/// [`Generated::redraws`]). Errors: an inconsistent override, or no stable
/// draw within [`MAX_ATTEMPTS`].
pub fn generate(seed: u64, kind: Kind, ov: &Overrides) -> Result<Generated, String> {
    let mut redraws = Vec::new();
    let mut fallback: Option<Generated> = None;
    for attempt in 0..MAX_ATTEMPTS {
        let d = draw::draw(seed, attempt, kind, ov)?;
        if d.family == Family::Steady {
            let mut g = generate_steady(&d);
            g.redraws = redraws;
            return Ok(g);
        }
        match generate_dynamic(&d) {
            Ok(mut g) => {
                let faint: Vec<String> = d
                    .hidden
                    .iter()
                    .zip(&g.visibility)
                    .filter(|(_, v)| **v < MIN_VISIBILITY)
                    .map(|(e, v)| format!("{} visibility {v:.2}", e.name()))
                    .collect();
                if faint.is_empty() {
                    g.redraws = redraws;
                    return Ok(g);
                }
                redraws.push(format!(
                    "attempt {attempt}: {} (below {MIN_VISIBILITY} at its bound)",
                    faint.join(", ")
                ));
                if fallback.is_none() {
                    fallback = Some(g);
                }
            }
            Err(Unstable(why)) => redraws.push(format!("attempt {attempt}: {why}")),
        }
    }
    match fallback {
        Some(mut g) => {
            g.redraws = redraws;
            Ok(g)
        }
        None => Err(format!(
            "seed {seed}: no stable draw in {MAX_ATTEMPTS} attempts: {}",
            redraws.join("; ")
        )),
    }
}
