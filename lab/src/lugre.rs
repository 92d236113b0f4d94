//! The LuGre friction model (C. Canudas de Wit, H. Olsson, K. J. Åström,
//! P. Lischinsky, "A new model for control of systems with friction", IEEE
//! Trans. Automatic Control 40(3), 1995) in `f64`: a plant whose friction is
//! *not* the MODEL.md model, for the closed-loop benchmark, and the fit of
//! the library's break-away predictor (MODEL.md §4) to its break-away curve.
//!
//! ```text
//! ż = v − σ0·|v|·z / g(v),   g(v) = Fc + (Fs − Fc)·exp(−(v/vs)²)
//! F = σ0·z + σ1·ż + σ2·v,    m·ẍ = u − F
//! ```
//!
//! Integrated by classical RK4 on (x, v, z) with a fixed step (the bristle
//! mode √(σ0/m) = 316 rad/s and the relaxation σ0·|v|/g stay far below
//! 1/h for the steps used here; the tests halve the step to show it).

/// LuGre parameters (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LuGre {
    /// Bristle stiffness σ0 [N/m].
    pub sigma0: f64,
    /// Bristle damping σ1 [N·s/m].
    pub sigma1: f64,
    /// Viscous coefficient σ2 [N·s/m].
    pub sigma2: f64,
    /// Coulomb level Fc [N].
    pub fc: f64,
    /// Stiction level Fs [N].
    pub fs: f64,
    /// Stribeck velocity vs [m/s].
    pub vs: f64,
    /// Moving mass m [kg].
    pub mass: f64,
}

impl LuGre {
    /// The parameter set of Canudas de Wit et al. (1995), whose break-away
    /// force falls with the force rate (their Fig. 4).
    pub const CANUDAS_1995: LuGre = LuGre {
        sigma0: 1e5,
        sigma1: 316.227_766_016_837_9, // √1e5
        sigma2: 0.4,
        fc: 1.0,
        fs: 1.5,
        vs: 1e-3,
        mass: 1.0,
    };

    /// g(v) [N].
    pub fn level(&self, v: f64) -> f64 {
        self.fc + (self.fs - self.fc) * (-(v / self.vs).powi(2)).exp()
    }

    /// ż [m/s] at bristle deflection `z` [m] and velocity `v` [m/s].
    pub fn z_rate(&self, z: f64, v: f64) -> f64 {
        v - self.sigma0 * v.abs() * z / self.level(v)
    }

    /// Friction F [N].
    pub fn friction(&self, z: f64, v: f64) -> f64 {
        self.sigma0 * z + self.sigma1 * self.z_rate(z, v) + self.sigma2 * v
    }
}

/// The state of a LuGre plant m·ẍ = u − F.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plant {
    /// The model.
    pub model: LuGre,
    /// Position x [m].
    pub x: f64,
    /// Velocity v [m/s].
    pub v: f64,
    /// Bristle deflection z [m].
    pub z: f64,
}

impl Plant {
    /// At rest at x = 0 with relaxed bristles.
    pub fn new(model: LuGre) -> Self {
        Plant {
            model,
            x: 0.0,
            v: 0.0,
            z: 0.0,
        }
    }

    fn rate(&self, u: f64, s: [f64; 3]) -> [f64; 3] {
        let [_, v, z] = s;
        let f = self.model.friction(z, v);
        [v, (u - f) / self.model.mass, self.model.z_rate(z, v)]
    }

    /// One RK4 step of `h` [s] under the force `u(t)` [N] (`t` the time at
    /// the start of the step).
    pub fn step(&mut self, u: &dyn Fn(f64) -> f64, t: f64, h: f64) {
        let s0 = [self.x, self.v, self.z];
        let add =
            |s: [f64; 3], k: [f64; 3], a: f64| [s[0] + a * k[0], s[1] + a * k[1], s[2] + a * k[2]];
        let k1 = self.rate(u(t), s0);
        let k2 = self.rate(u(t + h / 2.0), add(s0, k1, h / 2.0));
        let k3 = self.rate(u(t + h / 2.0), add(s0, k2, h / 2.0));
        let k4 = self.rate(u(t + h), add(s0, k3, h));
        let mut s = s0;
        for i in 0..3 {
            s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        [self.x, self.v, self.z] = s;
    }

    /// Friction F [N] in the current state.
    pub fn friction(&self) -> f64 {
        self.model.friction(self.z, self.v)
    }
}

/// The published break-away curve of the LuGre parameter set
/// [`LuGre::CANUDAS_1995`]: (k [N/s], F_ba [N]), read ±0.02 N.
pub const PUBLISHED_BREAK_AWAY: [(f64, f64); 5] = [
    (1.0, 1.43),
    (5.0, 1.31),
    (10.0, 1.22),
    (20.0, 1.10),
    (30.0, 1.02),
];

/// Break-away force [N] of a LuGre plant under u = k·t from rest: the peak
/// of the friction force F(t) without its viscous part, σ0·z + σ1·ż,
/// integrated with the step `h` [s].
///
/// The viscous part is left out because with it the "peak" at large k is
/// not the break-away: σ2·v keeps rising as the mass accelerates after
/// break-away (at k = 30 N/s the peak of F including σ2·v is 1.08 N, set
/// by v ≈ 0.14 m/s). Without it the curve is the published one (1.43, 1.31,
/// 1.22, 1.10, 1.02 N at k = 1, 5, 10, 20, 30 N/s), and at small k the two
/// agree (v is small at the peak).
pub fn break_away(model: LuGre, k: f64, h: f64) -> f64 {
    let mut plant = Plant::new(model);
    let u = move |t: f64| k * t;
    let t_end = 3.0 * model.fs / k;
    let (mut t, mut peak) = (0.0, 0.0f64);
    while t < t_end {
        plant.step(&u, t, h);
        t += h;
        let f = plant.friction() - model.sigma2 * plant.v;
        peak = peak.max(f);
        // Past the peak and sliding: friction has fallen towards Fc.
        if f < peak - 0.2 * (model.fs - model.fc) && plant.v > 10.0 * model.vs {
            break;
        }
    }
    peak
}

/// The library's predictor parameters fitted to a break-away curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PredictorFit {
    /// Stribeck velocity V [m/s].
    pub v_stribeck: f64,
    /// Shape exponent δ.
    pub delta: f64,
    /// Presliding distance z_max [m].
    pub z_max: f64,
    /// Largest |F_ba(fit) − F_ba(data)| [N] over the points.
    pub max_error: f64,
    /// RMS of the same [N].
    pub rms_error: f64,
}

/// The library (`breakaway`, f32) predictor's F_ba(k) [N] for the levels
/// `fc`, `fs`, `sigma` of `base` with (V, δ, z_max), variant `Consistent`,
/// w_b = 0.95; `None` where the parameters are invalid or it fails.
pub fn predicted(base: &breakaway::Params, v: f64, delta: f64, z_max: f64, k: f64) -> Option<f64> {
    let params = breakaway::Params {
        v_stribeck: v as f32,
        delta: delta as f32,
        z_max: z_max as f32,
        ..*base
    };
    let model = breakaway::Model::<f32>::new(params).ok()?;
    let predictor = breakaway::BreakAwayPredictor::new(&model, breakaway::DEFAULT_BOUNDARY).ok()?;
    let ba = predictor
        .predict(&model, breakaway::Variant::Consistent, k as f32)
        .ok()?;
    Some(f64::from(ba.f_ba))
}

/// Least-squares fit of (V, δ, z_max) of the library's predictor to the
/// (k [N/s], F_ba [N]) points, with Fc, Fs, σ taken from `base`.
///
/// Only V/z_max and δ are identifiable from F_ba(k): the predictor's
/// F_ba = S(v_b) + σ·v_b with v_b ∝ k·z_max depends on z_max and V through
/// v_b/V ∝ k·z_max/V, up to σ·v_b, which is a few mN here. z_max is
/// therefore held at `base.z_max` (for a LuGre plant its presliding
/// deflection Fs/σ0) and (V, δ) fitted: Nelder–Mead on (ln V, ln δ) from
/// `base`'s values, restarted twice.
pub fn fit_predictor(base: &breakaway::Params, points: &[(f64, f64)]) -> PredictorFit {
    let z = f64::from(base.z_max);
    let cost = |p: &[f64; 3]| -> f64 {
        let (v, d) = (p[0].exp(), p[1].exp());
        points
            .iter()
            .map(|&(k, f)| predicted(base, v, d, z, k).map_or(1e6, |g| (g - f).powi(2)))
            .sum()
    };
    let mut best = [
        f64::from(base.v_stribeck).ln(),
        f64::from(base.delta).ln(),
        0.0,
    ];
    for _ in 0..3 {
        best = nelder_mead(&cost, best, 0.5, 2000);
    }
    let (v, d) = (best[0].exp(), best[1].exp());
    let errors: Vec<f64> = points
        .iter()
        .map(|&(k, f)| predicted(base, v, d, z, k).map_or(f64::INFINITY, |g| g - f))
        .collect();
    let n = errors.len().max(1) as f64;
    PredictorFit {
        v_stribeck: v,
        delta: d,
        z_max: z,
        max_error: errors.iter().fold(0.0f64, |m, e| m.max(e.abs())),
        rms_error: (errors.iter().map(|e| e * e).sum::<f64>() / n).sqrt(),
    }
}

/// The predictor parameters of the LuGre benchmark plant: Fc, Fs, σ = σ2
/// of [`LuGre::CANUDAS_1995`], z_max = Fs/σ0 (the bristle deflection at
/// stiction), V and δ as starting values of [`fit_predictor`].
pub fn lugre_base() -> breakaway::Params {
    let m = LuGre::CANUDAS_1995;
    breakaway::Params {
        fc: m.fc as f32,
        fs: m.fs as f32,
        v_stribeck: m.vs as f32,
        delta: 2.0,
        sigma: m.sigma2 as f32,
        z_max: (m.fs / m.sigma0) as f32,
        epsilon: 0.0,
    }
}

/// The force rates [N/s] at which the fit is also compared with the
/// simulated LuGre curve.
pub const FIT_RATES: [f64; 9] = [0.5, 1.0, 2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0];

/// Nelder–Mead minimisation in three dimensions from `start` with initial
/// simplex size `scale`.
fn nelder_mead(
    f: &dyn Fn(&[f64; 3]) -> f64,
    start: [f64; 3],
    scale: f64,
    iterations: usize,
) -> [f64; 3] {
    let mut simplex: Vec<([f64; 3], f64)> = (0..4)
        .map(|i| {
            let mut p = start;
            if i > 0 {
                p[i - 1] += scale;
            }
            (p, f(&p))
        })
        .collect();
    let lerp = |a: &[f64; 3], b: &[f64; 3], t: f64| {
        [
            a[0] + t * (b[0] - a[0]),
            a[1] + t * (b[1] - a[1]),
            a[2] + t * (b[2] - a[2]),
        ]
    };
    for _ in 0..iterations {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let mut centroid = [0.0; 3];
        for (p, _) in &simplex[..3] {
            for i in 0..3 {
                centroid[i] += p[i] / 3.0;
            }
        }
        let worst = simplex[3];
        let reflected = lerp(&centroid, &worst.0, -1.0);
        let fr = f(&reflected);
        if fr < simplex[0].1 {
            let expanded = lerp(&centroid, &worst.0, -2.0);
            let fe = f(&expanded);
            simplex[3] = if fe < fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr < simplex[2].1 {
            simplex[3] = (reflected, fr);
        } else {
            let contracted = lerp(&centroid, &worst.0, 0.5);
            let fc = f(&contracted);
            if fc < worst.1 {
                simplex[3] = (contracted, fc);
            } else {
                let best = simplex[0].0;
                for entry in simplex.iter_mut().skip(1) {
                    let p = lerp(&best, &entry.0, 0.5);
                    *entry = (p, f(&p));
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex[0].0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lugre_break_away_matches_the_published_curve() {
        for (k, published) in PUBLISHED_BREAK_AWAY {
            let f = break_away(LuGre::CANUDAS_1995, k, 1e-5);
            let finer = break_away(LuGre::CANUDAS_1995, k, 5e-6);
            println!("k = {k:>4} N/s: F_ba = {f:.4} N (h/2: {finer:.4}), published {published}");
            assert!((f - finer).abs() < 1e-4, "step dependence at k = {k}");
            assert!(
                (f - published).abs() <= 0.02,
                "k = {k}: F_ba {f:.4} N, published {published} ± 0.02"
            );
        }
    }

    #[test]
    fn predictor_fit_follows_the_lugre_curve() {
        let fit = fit_predictor(&lugre_base(), &PUBLISHED_BREAK_AWAY);
        println!("fit to the published points: {fit:?}");
        // Against the simulated LuGre curve, also between the points.
        let mut worst = 0.0f64;
        for k in FIT_RATES {
            let lugre = break_away(LuGre::CANUDAS_1995, k, 1e-5);
            let p = predicted(&lugre_base(), fit.v_stribeck, fit.delta, fit.z_max, k).unwrap();
            println!("k = {k:>4}: LuGre {lugre:.4} N, fitted predictor {p:.4} N");
            worst = worst.max((p - lugre).abs());
        }
        println!("worst |predictor − LuGre| over {FIT_RATES:?}: {worst:.4} N");
        // The quasi-static predictor's F_ba(k) = S(v_b) with v_b ∝ k follows
        // the LuGre curve to about the reading accuracy of the published
        // figure (±0.02 N): measured max 0.025 N, RMS 0.015 N at the points,
        // 0.021 N against the simulated curve. The residual is structural:
        // S(v_b) flattens towards Fc faster than the LuGre curve at large k.
        assert!(fit.max_error < 0.03 && fit.rms_error < 0.02, "{fit:?}");
        assert!(worst < 0.03, "{worst}");
    }
}
