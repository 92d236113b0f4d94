//! Model parameters, their validation and the TOML model file (MODEL.md §2, §3,
//! §5 and §7).
//!
//! A [`Model`] holds the parameters of the Stribeck curve (§2), of presliding
//! (§3), the moving mass of the plant (§1) and the optional effects of the
//! catalogue (§5). [`Model::validate`] enforces every rule of those sections;
//! [`Model::from_toml_str`] / [`Model::to_toml_string`] read and write the model
//! file of §7. Reading is `serde` on the parsed TOML and strict: unknown
//! keys, missing keys, wrong types and invalid values are errors that name
//! the key path (for example `effects.asymmetry.a`). The rules and the
//! writer share one list of the model's numbers with their keys and
//! comments; writing uses Rust's shortest round-trip float formatting, so a
//! written file reads back bit-exact.

use crate::effect::Effect;
use serde::Deserialize;
use std::fmt;
use std::path::{Path, PathBuf};

/// The friction model with the plant mass (MODEL.md §1–§3, §5, §7).
///
/// In a model file `fs == fc` marks a model without `stribeck` and
/// `z_max == 0` a model without `presliding`; `sigma > 0` is the effect
/// `viscous`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Moving mass `m` [kg] (rotary: kg·m²), `> 0`.
    pub mass: f64,
    /// Coulomb level `Fc` [N], `> 0`.
    pub fc: f64,
    /// Stiction level `Fs` [N], `>= fc`.
    pub fs: f64,
    /// Stribeck velocity `V` [m/s], `> 0`.
    pub v_stribeck: f64,
    /// Stribeck shape exponent `δ` [-], `> 0`.
    pub delta: f64,
    /// Viscous coefficient `σ` [N·s/m], `>= 0`.
    pub sigma: f64,
    /// Presliding distance `z_max` [m], `>= 0` (0 = no presliding).
    pub z_max: f64,
    /// Turning-point deadband `ε` [m], `>= 0`.
    pub epsilon: f64,
    /// Optional effects of the catalogue (§5).
    #[serde(default)]
    pub effects: Effects,
}

/// The optional effects of MODEL.md §5; an effect is present when `Some`.
#[derive(Clone, Debug, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Effects {
    /// `offset`: `F += f0`.
    pub offset: Option<Offset>,
    /// `asymmetry`: `Fc`, `Fs` scaled by `1 + a·d`.
    pub asymmetry: Option<Asymmetry>,
    /// `position_ripple`: `F += A·sin(2π·x/λ + φ)`.
    pub position_ripple: Option<PositionRipple>,
    /// `dwell_stiction`: `Fs` raised by `ΔFs·t_d/(t_d + γ)`.
    pub dwell_stiction: Option<DwellStiction>,
    /// `frictional_lag`: `S` evaluated at the lagged velocity `v_l`.
    pub frictional_lag: Option<FrictionalLag>,
    /// `drift`: `Fc`, `Fs` scaled by `1 + β·t`.
    pub drift: Option<Drift>,
    /// `nonlinear_viscous`: `F += σ_n·sgn(v)·|v|^n`.
    pub nonlinear_viscous: Option<NonlinearViscous>,
}

/// Effect `offset` (§5): a constant force added at rest and in motion alike.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Offset {
    /// `F0` [N], signed, finite.
    pub f0: f64,
}

/// Effect `asymmetry` (§5): `Fc`, `Fs` scaled by `(1 + a)` while `d = +1`
/// and `(1 − a)` while `d = −1`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Asymmetry {
    /// `a` [-], `−1 < a < 1`.
    pub a: f64,
}

/// Effect `position_ripple` (§5): `F += A·sin(2π·x/λ + φ)`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionRipple {
    /// Amplitude `A` [N], finite.
    pub amplitude: f64,
    /// Wavelength `λ` [m], `> 0`.
    pub wavelength: f64,
    /// Phase `φ` [rad], finite.
    pub phase: f64,
}

/// Effect `dwell_stiction` (§5): `Fs` raised by `ΔFs·t_d/(t_d + γ)`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DwellStiction {
    /// `ΔFs` [N], `>= 0`.
    pub delta_fs: f64,
    /// Time constant `γ` [s], `> 0`.
    pub gamma: f64,
    /// Rest threshold `v_rest` [m/s], `> 0`: at rest while `|v| <= v_rest`.
    pub v_rest: f64,
}

/// Effect `frictional_lag` (§5): `τ_L·dv_l/dt = v − v_l`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionalLag {
    /// Lag time constant `τ_L` [s], `> 0`.
    pub tau_l: f64,
}

/// Effect `drift` (§5): `Fc`, `Fs` scaled by `(1 + β·t)`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Drift {
    /// `β` [1/s], finite.
    pub beta: f64,
}

/// Effect `nonlinear_viscous` (§5): `F += σ_n·sgn(v)·|v|^n`, velocity
/// strengthening that is not proportional to speed (gear and seal friction);
/// `n = 1` would be `viscous`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NonlinearViscous {
    /// `σ_n` [N·(s/m)^n], `>= 0` (rotary: N·m·(s/rad)^n).
    pub sigma_n: f64,
    /// Exponent `n` [-], `0 < n <= 2`.
    pub n: f64,
}

/// Error reading, validating or writing a model; names the offending key.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelError {
    /// Key path, e.g. `fs` or `effects.asymmetry.a`; empty when the error is
    /// not about one key (I/O, TOML syntax).
    pub key: String,
    /// What is wrong, one line.
    pub message: String,
    /// The file, when the error came from [`Model::load`] / [`Model::save`].
    pub path: Option<PathBuf>,
}

impl ModelError {
    /// An error about `key`.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        ModelError {
            key: key.into(),
            message: message.into(),
            path: None,
        }
    }

    fn with_path(mut self, path: &Path) -> Self {
        self.path = Some(path.to_path_buf());
        self
    }
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(p) = &self.path {
            write!(f, "{}: ", p.display())?;
        }
        if self.key.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{}: {}", self.key, self.message)
        }
    }
}

impl std::error::Error for ModelError {}

/// An argument of a computation out of range (or a model number it needs
/// beyond [`Model::validate`], such as `z_max > 0`); the error of the
/// predictor and of the simulator alike.
#[derive(Clone, Debug, PartialEq)]
pub struct ArgumentError {
    /// Name of the argument (`k`, `w_b`, `z_max`, `t_end`, ...).
    pub name: &'static str,
    /// The value given.
    pub value: f64,
    /// The requirement, e.g. `0 < w_b < 1`.
    pub requirement: &'static str,
}

impl ArgumentError {
    /// `name` = `value` fails `requirement`.
    pub fn new(name: &'static str, value: f64, requirement: &'static str) -> Self {
        ArgumentError {
            name,
            value,
            requirement,
        }
    }
}

impl fmt::Display for ArgumentError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ArgumentError {
            name,
            value,
            requirement,
        } = self;
        write!(f, "{name}: requires {requirement}, got {value:?}")
    }
}

impl std::error::Error for ArgumentError {}

/// One numeric rule of §2/§3/§5.
#[derive(Clone, Copy)]
enum Rule {
    Finite,
    Positive,
    NonNegative,
    /// `-1 < x < 1`.
    OpenUnit,
    /// `0 < x <= 2`.
    Exponent,
    /// `x >=` the named key's value.
    AtLeast(&'static str, f64),
}

fn check(key: &str, value: f64, rule: Rule) -> Result<(), ModelError> {
    if !value.is_finite() {
        return Err(ModelError::new(
            key,
            format!("must be finite, got {value:?}"),
        ));
    }
    let what = match rule {
        Rule::Finite => None,
        Rule::Positive | Rule::Exponent if value <= 0.0 => Some("must be > 0".to_string()),
        Rule::Positive => None,
        Rule::Exponent => (value > 2.0).then(|| "must be in (0, 2]".to_string()),
        Rule::NonNegative => (value < 0.0).then(|| "must be >= 0".to_string()),
        Rule::OpenUnit => {
            (value <= -1.0 || value >= 1.0).then(|| "must satisfy -1 < a < 1".to_string())
        }
        Rule::AtLeast(name, bound) => {
            (value < bound).then(|| format!("must be >= {name} ({bound:?})"))
        }
    };
    match what {
        None => Ok(()),
        Some(what) => Err(ModelError::new(key, format!("{what}, got {value:?}"))),
    }
}

/// One number of a model: the effect whose table holds it (none for the
/// top level), its key, value, rule and the comment the file gives it.
struct Entry {
    effect: Option<Effect>,
    key: &'static str,
    value: f64,
    rule: Rule,
    comment: &'static str,
}

impl Entry {
    /// The key path, e.g. `fs` or `effects.asymmetry.a`.
    fn path(&self) -> String {
        match self.effect {
            None => self.key.to_string(),
            Some(effect) => format!("effects.{}.{}", effect.name(), self.key),
        }
    }
}

impl Model {
    /// Checks every rule of MODEL.md §2, §3 and §5 (plus `mass > 0`).
    /// `z_max = 0` is allowed (a model without presliding, as in files).
    /// The error names the first offending key.
    pub fn validate(&self) -> Result<(), ModelError> {
        self.entries()
            .iter()
            .try_for_each(|e| check(&e.path(), e.value, e.rule))
    }

    /// Every number of the model in the order of the file (§7): the top
    /// level, then the present effects in the order of the catalogue.
    fn entries(&self) -> Vec<Entry> {
        use Rule::{AtLeast, Exponent, Finite, NonNegative, OpenUnit, Positive};
        let top = |key, value, rule, comment| Entry {
            effect: None,
            key,
            value,
            rule,
            comment,
        };
        let mut entries = vec![
            top("mass", self.mass, Positive, "m [kg]"),
            top("fc", self.fc, Positive, "Fc [N]"),
            top("fs", self.fs, AtLeast("fc", self.fc), "Fs [N]"),
            top("v_stribeck", self.v_stribeck, Positive, "V [m/s]"),
            top("delta", self.delta, Positive, "shape exponent"),
            top("sigma", self.sigma, NonNegative, "viscous [N*s/m]"),
            top("z_max", self.z_max, NonNegative, "presliding distance [m]"),
            top(
                "epsilon",
                self.epsilon,
                NonNegative,
                "turning-point deadband [m]",
            ),
        ];
        let e = &self.effects;
        let effects: [(Effect, Option<Vec<_>>); 7] = [
            (
                Effect::Offset,
                e.offset.map(|o| vec![("f0", o.f0, Finite, "[N]")]),
            ),
            (
                Effect::Asymmetry,
                e.asymmetry.map(|a| vec![("a", a.a, OpenUnit, "")]),
            ),
            (
                Effect::PositionRipple,
                e.position_ripple.map(|r| {
                    vec![
                        ("amplitude", r.amplitude, Finite, "[N]"),
                        ("wavelength", r.wavelength, Positive, "[m]"),
                        ("phase", r.phase, Finite, "[rad]"),
                    ]
                }),
            ),
            (
                Effect::DwellStiction,
                e.dwell_stiction.map(|d| {
                    vec![
                        ("delta_fs", d.delta_fs, NonNegative, "[N]"),
                        ("gamma", d.gamma, Positive, "[s]"),
                        ("v_rest", d.v_rest, Positive, "[m/s]"),
                    ]
                }),
            ),
            (
                Effect::FrictionalLag,
                e.frictional_lag
                    .map(|l| vec![("tau_l", l.tau_l, Positive, "[s]")]),
            ),
            (
                Effect::Drift,
                e.drift.map(|d| vec![("beta", d.beta, Finite, "[1/s]")]),
            ),
            (
                Effect::NonlinearViscous,
                e.nonlinear_viscous.map(|nv| {
                    vec![
                        ("sigma_n", nv.sigma_n, NonNegative, "[N*(s/m)^n]"),
                        ("n", nv.n, Exponent, ""),
                    ]
                }),
            ),
        ];
        for (effect, numbers) in effects {
            for (key, value, rule, comment) in numbers.into_iter().flatten() {
                entries.push(Entry {
                    effect: Some(effect),
                    key,
                    value,
                    rule,
                    comment,
                });
            }
        }
        entries
    }

    /// Reads a model file (§7) from TOML text and validates it.
    ///
    /// Unknown keys, missing keys, wrong types (a TOML integer is accepted as
    /// a float) and invalid values are errors naming the key path.
    pub fn from_toml_str(s: &str) -> Result<Model, ModelError> {
        let table: toml::Table = toml::from_str(s).map_err(|e| {
            let mut msg = format!("TOML syntax error: {}", e.message().trim());
            if let Some(span) = e.span() {
                let line = s[..span.start.min(s.len())].matches('\n').count() + 1;
                msg = format!("line {line}: {msg}");
            }
            ModelError::new("", msg.replace('\n', " "))
        })?;
        let model: Model = serde_path_to_error::deserialize(toml::Value::Table(table))
            .map_err(|e| read_error(&e))?;
        model.validate()?;
        Ok(model)
    }

    /// Writes the model file (§7). Floats use the shortest representation that
    /// reads back to the same bits (`1.0`, `1e-5`, `-0.0`, ...), so
    /// `Model::from_toml_str(&m.to_toml_string())` returns `m` bit-exact for
    /// every valid `m`.
    pub fn to_toml_string(&self) -> String {
        let mut s = String::new();
        let mut table = None;
        for e in self.entries() {
            if let Some(effect) = e.effect.filter(|_| e.effect != table) {
                s.push_str(&format!("\n[effects.{}]\n", effect.name()));
                table = e.effect;
            }
            let value = fmt_float(e.value);
            if e.comment.is_empty() {
                s.push_str(&format!("{} = {value}\n", e.key));
            } else {
                s.push_str(&format!("{} = {value}  # {}\n", e.key, e.comment));
            }
        }
        s
    }

    /// Reads and validates a model file; the error names the file.
    pub fn load(path: &Path) -> Result<Model, ModelError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| ModelError::new("", format!("cannot read: {e}")).with_path(path))?;
        Model::from_toml_str(&text).map_err(|e| e.with_path(path))
    }

    /// Validates and writes the model file; the error names the file.
    pub fn save(&self, path: &Path) -> Result<(), ModelError> {
        self.validate().map_err(|e| e.with_path(path))?;
        std::fs::write(path, self.to_toml_string())
            .map_err(|e| ModelError::new("", format!("cannot write: {e}")).with_path(path))
    }
}

/// Shortest round-trip float text that TOML reads as a float.
///
/// Rust's `{:?}` for `f64` is the shortest representation that parses back
/// to the same bits and always contains `.` or `e` (`1.0`, `1e-5`, `1e16`,
/// `-0.0`, `2.2250738585072014e-308`), all valid TOML floats. Non-finite
/// values (never valid in a model) are written in TOML's spelling.
pub(crate) fn fmt_float(v: f64) -> String {
    if v.is_nan() {
        "nan".to_string()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        let s = format!("{v:?}");
        debug_assert!(s.contains('.') || s.contains('e'));
        s
    }
}

/// The error of reading a TOML table as a model file, naming the key
/// path: an unknown or missing key, or a value of the wrong type.
fn read_error(e: &serde_path_to_error::Error<toml::de::Error>) -> ModelError {
    let mut path: Vec<String> = e.path().iter().map(ToString::to_string).collect();
    let message = e.inner().message().trim().replace('\n', " ");
    let quoted = |prefix: &str| {
        let rest = message.strip_prefix(prefix)?.strip_prefix('`')?;
        rest.split_once('`').map(|(key, _)| key.to_string())
    };
    let message = if let Some(key) = quoted("missing field ") {
        path.push(key);
        "missing required key".to_string()
    } else if let Some(key) = quoted("unknown field ") {
        if path.last() != Some(&key) {
            path.push(key);
        }
        "unknown key".to_string()
    } else if let Some((got, wanted)) = message
        .strip_prefix("invalid type: ")
        .and_then(|m| m.rsplit_once(", expected "))
    {
        let wanted = if wanted.starts_with("struct") {
            "a table"
        } else {
            "a number"
        };
        format!("expected {wanted}, got {got}")
    } else {
        message
    };
    ModelError::new(path.join("."), message)
}
