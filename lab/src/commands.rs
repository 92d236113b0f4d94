//! The computations behind the sub-commands.
//!
//! * [`breakaway_rows`]: MODEL.md §4 quasi-static break-away per variant and
//!   `k`, plus optionally the full dynamics (computed once per `k`: it does not
//!   depend on the variant).
//! * [`validity_map`]: the same against the full dynamics over masses, with
//!   the inertia number [`inertia_number`] (MODEL.md §4) and [`pi_number`]
//!   (MODEL.md §8).

use crate::reference::{self, Model, Variant};
use crate::Error;
use std::path::Path;

/// Loads and checks a model file (MODEL.md §7) as the workflow does
/// ([`crate::workflow::load_model`]). The break-away analysis needs
/// presliding, so `z_max = 0` (allowed in files) is refused here; it covers
/// the model of §2–§4 alone, so a table of §5's additions is refused too: a
/// prediction that left out the file's `offset` or `drift` would be a
/// number for another model.
pub fn load_model(path: &Path) -> Result<Model, Error> {
    let model = crate::workflow::load_model(path)?;
    if model.z_max.is_nan() || model.z_max <= 0.0 {
        return Err(Error::Runtime(format!(
            "model file {}: key `z_max`: break-away needs presliding, z_max > 0, got {}",
            path.display(),
            model.z_max
        )));
    }
    // The prediction is of the §2–§3 model: the additions of §5 (the
    // effect tables) are beyond it.
    let beyond: Vec<&str> = crate::fit::effects_of(&model)
        .into_iter()
        .filter(|e| e.has_table())
        .map(|e| e.name())
        .collect();
    if !beyond.is_empty() {
        return Err(Error::Runtime(format!(
            "model file {}: [effects.{}]: the break-away prediction (MODEL.md §4) covers the \
             Coulomb, Stribeck, viscous and presliding friction of §2–§3 only",
            path.display(),
            beyond.join("], [effects.")
        )));
    }
    Ok(model)
}

/// The full-dynamics break-away (MODEL.md §4, last paragraph).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dynamic {
    /// Actuation force `k·t` when `w` reaches `w_b` [N].
    pub f_ba: f64,
    /// That instant [s].
    pub t_ba: f64,
}

/// One row of `breakaway`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BreakawayRow {
    /// The `F̂` variant.
    pub variant: Variant,
    /// Force rate [N/s].
    pub k: f64,
    /// Break-away velocity [m/s].
    pub v_b: f64,
    /// Break-away force [N].
    pub f_ba: f64,
    /// Predicted time of break-away [s].
    pub t_ba: f64,
    /// Full dynamics, with `--dynamic`.
    pub dynamic: Option<Dynamic>,
}

fn predict(m: &Model, v: Variant, k: f64, w_b: f64) -> Result<reference::BreakAway, Error> {
    let ba = reference::predict_break_away(m, v, k, w_b)
        .map_err(|e| Error::Runtime(format!("{} at k = {k:?}: {e}", v.name())))?;
    // A rate so small that the time to break away overflows (k = 1e-320
    // N/s: t_ba = ∞) has no prediction to print.
    if [ba.v_b, ba.f_ba, ba.t_ba].iter().all(|x| x.is_finite()) {
        Ok(ba)
    } else {
        Err(Error::Runtime(format!(
            "{} at k = {k:?}: the prediction is not finite (v_b {}, F_ba {}, t_ba {}): k is out of the range it can be computed for",
            v.name(),
            ba.v_b,
            ba.f_ba,
            ba.t_ba
        )))
    }
}

fn simulate(m: &Model, k: f64, w_b: f64) -> Result<Dynamic, Error> {
    let d = reference::simulate_break_away(m, k, w_b).map_err(|e| {
        Error::Runtime(format!(
            "full-dynamics simulation at m = {:?}, k = {k:?}: {e}",
            m.mass
        ))
    })?;
    Ok(Dynamic {
        f_ba: d.f_ba,
        t_ba: d.t_ba,
    })
}

/// The rows of `breakaway`, grouped by variant (in the order given), then by
/// `k` (in the order given).
pub fn breakaway_rows(
    model: &Model,
    ks: &[f64],
    variants: &[Variant],
    w_b: f64,
    dynamic: bool,
) -> Result<Vec<BreakawayRow>, Error> {
    let sims = if dynamic {
        ks.iter()
            .map(|&k| simulate(model, k, w_b).map(Some))
            .collect::<Result<Vec<_>, _>>()?
    } else {
        vec![None; ks.len()]
    };
    let mut rows = Vec::with_capacity(variants.len() * ks.len());
    for &variant in variants {
        for (&k, &dynamic) in ks.iter().zip(&sims) {
            let p = predict(model, variant, k, w_b)?;
            rows.push(BreakawayRow {
                variant,
                k,
                v_b: p.v_b,
                f_ba: p.f_ba,
                t_ba: p.t_ba,
                dynamic,
            });
        }
    }
    Ok(rows)
}

/// `F̂ = (Fc + Fs)/2`, the paper's `F̂_ss`.
fn f_mean(m: &Model) -> f64 {
    0.5 * (m.fc + m.fs)
}

/// The inertia number of MODEL.md §4,
/// `Λ = m·k²·z_max / (F̂³·w_b·|ln w_b|³)` with `F̂ = (Fc + Fs)/2`: the
/// quasi-static step needs `Λ ≪ 1`.
pub fn inertia_number(m: &Model, k: f64, w_b: f64) -> f64 {
    m.mass * k * k * m.z_max / (f_mean(m).powi(3) * w_b * w_b.ln().abs().powi(3))
}

/// The force rate at which [`inertia_number`] is 1.
pub fn k_unit_inertia(m: &Model, w_b: f64) -> f64 {
    (f_mean(m).powi(3) * w_b * w_b.ln().abs().powi(3) / (m.mass * m.z_max)).sqrt()
}

/// MODEL.md §8: `Π = √(2·Fs·z_max/m)/V`; rests are quiet below about 5,
/// self-excited presliding may appear from about 10.
pub fn pi_number(m: &Model) -> f64 {
    (2.0 * m.fs * m.z_max / m.mass).sqrt() / m.v_stribeck
}

/// One quasi-static prediction against the dynamics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compared {
    /// The `F̂` variant.
    pub variant: Variant,
    /// Quasi-static break-away force [N].
    pub f_ba: f64,
    /// Relative drift `(f_ba − f_ba_sim)/f_ba_sim`.
    pub drift: f64,
}

/// One `(m, k)` point of the validity map.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidityPoint {
    /// Force rate [N/s].
    pub k: f64,
    /// Inertia number `Λ` (MODEL.md §4).
    pub lambda: f64,
    /// Full dynamics.
    pub sim: Dynamic,
    /// The quasi-static predictions, in the order of the variants asked for.
    pub compared: Vec<Compared>,
}

impl ValidityPoint {
    /// The largest `|drift|` over the variants compared.
    pub fn worst_drift(&self) -> f64 {
        self.compared
            .iter()
            .map(|c| c.drift.abs())
            .fold(0.0, f64::max)
    }
}

/// All `k` points of one mass.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidityBlock {
    /// Mass [kg].
    pub mass: f64,
    /// `Π` of MODEL.md §8 for this mass.
    pub pi: f64,
    /// `k` at which `Λ = 1`.
    pub k_unit_inertia: f64,
    /// The points, in the order of the `k` given.
    pub points: Vec<ValidityPoint>,
}

/// Sweeps masses × force rates: the model's `mass` is replaced by each mass.
pub fn validity_map(
    model: &Model,
    masses: &[f64],
    ks: &[f64],
    variants: &[Variant],
    w_b: f64,
) -> Result<Vec<ValidityBlock>, Error> {
    let mut blocks = Vec::with_capacity(masses.len());
    for &mass in masses {
        let mut m = model.clone();
        m.mass = mass;
        let mut points = Vec::with_capacity(ks.len());
        for &k in ks {
            let sim = simulate(&m, k, w_b)?;
            let compared = variants
                .iter()
                .map(|&variant| {
                    predict(&m, variant, k, w_b).map(|p| Compared {
                        variant,
                        f_ba: p.f_ba,
                        drift: (p.f_ba - sim.f_ba) / sim.f_ba,
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            points.push(ValidityPoint {
                k,
                lambda: inertia_number(&m, k, w_b),
                sim,
                compared,
            });
        }
        blocks.push(ValidityBlock {
            mass,
            pi: pi_number(&m),
            k_unit_inertia: k_unit_inertia(&m, w_b),
            points,
        });
    }
    Ok(blocks)
}
