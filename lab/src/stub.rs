//! TEMPORARY stand-in for `breakaway_reference` (deleted once the real crate lands).
#![allow(dead_code, missing_docs)]
use std::fmt;

#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub mass: f64,
    pub fc: f64,
    pub fs: f64,
    pub v_stribeck: f64,
    pub delta: f64,
    pub sigma: f64,
    pub z_max: f64,
    pub epsilon: f64,
}
#[derive(Debug)]
pub struct ModelError(String);
impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for ModelError {}
impl Model {
    pub fn load(path: &std::path::Path) -> Result<Model, ModelError> {
        let s = std::fs::read_to_string(path)
            .map_err(|e| ModelError(format!("{}: {e}", path.display())))?;
        let mut m = Model {
            mass: 1.0,
            fc: 1.0,
            fs: 1.5,
            v_stribeck: 1e-3,
            delta: 1.0,
            sigma: 0.0,
            z_max: 1e-5,
            epsilon: 0.0,
        };
        for line in s.lines() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() || line.starts_with('[') {
                continue;
            }
            let (k, v) = line
                .split_once('=')
                .ok_or_else(|| ModelError(format!("{}: bad line", path.display())))?;
            let v: f64 = v.trim().parse().map_err(|_| {
                ModelError(format!(
                    "{}: key `{}`: not a number",
                    path.display(),
                    k.trim()
                ))
            })?;
            match k.trim() {
                "mass" => m.mass = v,
                "fc" => m.fc = v,
                "fs" => m.fs = v,
                "v_stribeck" => m.v_stribeck = v,
                "delta" => m.delta = v,
                "sigma" => m.sigma = v,
                "z_max" => m.z_max = v,
                "epsilon" => m.epsilon = v,
                other => {
                    return Err(ModelError(format!(
                        "{}: unknown key `{other}`",
                        path.display()
                    )))
                }
            }
        }
        Ok(m)
    }
}
pub fn stribeck(m: &Model, v: f64) -> f64 {
    m.fc + (m.fs - m.fc) * (-(v.abs() / m.v_stribeck).powf(m.delta)).exp()
}
pub fn shape(w: f64) -> f64 {
    let w = w.clamp(0.0, 1.0);
    if w == 0.0 {
        0.0
    } else {
        w * (1.0 - w.ln())
    }
}
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    Coulomb,
    Stiction,
    Mean,
    Consistent,
}
impl Variant {
    pub const ALL: [Variant; 4] = [
        Variant::Coulomb,
        Variant::Stiction,
        Variant::Mean,
        Variant::Consistent,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Variant::Coulomb => "coulomb",
            Variant::Stiction => "stiction",
            Variant::Mean => "mean",
            Variant::Consistent => "consistent",
        }
    }
    pub fn parse(s: &str) -> Option<Variant> {
        Self::ALL.into_iter().find(|v| v.name() == s)
    }
}
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BreakAway {
    pub v_b: f64,
    pub f_ba: f64,
    pub t_ba: f64,
}
#[derive(Debug)]
pub struct PredictError(String);
impl fmt::Display for PredictError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
pub type SimError = PredictError;
pub fn predict_break_away(
    m: &Model,
    variant: Variant,
    k: f64,
    w_b: f64,
) -> Result<BreakAway, PredictError> {
    let c = -k * m.z_max / w_b.ln();
    let v_b = match variant {
        Variant::Coulomb => c / m.fc,
        Variant::Stiction => c / m.fs,
        Variant::Mean => c / (0.5 * (m.fc + m.fs)),
        Variant::Consistent => {
            let (mut lo, mut hi) = (c / m.fs, c / m.fc);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid * stribeck(m, mid) < c {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            0.5 * (lo + hi)
        }
    };
    let s = stribeck(m, v_b);
    Ok(BreakAway {
        v_b,
        f_ba: s + m.sigma * v_b,
        t_ba: (s * shape(w_b) + m.sigma * v_b) / k,
    })
}
pub struct DynamicBreakAway {
    pub f_ba: f64,
    pub t_ba: f64,
    pub v_b: f64,
}
pub fn simulate_break_away(m: &Model, k: f64, w_b: f64) -> Result<DynamicBreakAway, SimError> {
    let p = predict_break_away(m, Variant::Consistent, k, w_b)?;
    Ok(DynamicBreakAway {
        f_ba: p.f_ba * (1.0 + 1e-3 * m.mass * k),
        t_ba: p.t_ba,
        v_b: p.v_b,
    })
}
