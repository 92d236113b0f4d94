//! Model parameters, their validation and the TOML model file (MODEL.md §2, §3,
//! §5 and §7).
//!
//! A [`Model`] holds the parameters of the Stribeck curve (§2), of presliding
//! (§3), the moving mass of the plant (§1) and the optional effects of the
//! catalogue (§5). [`Model::validate`] enforces every rule of those sections;
//! [`Model::from_toml_str`] / [`Model::to_toml_string`] read and write the model
//! file of §7. Reading is strict: unknown keys, missing keys, wrong types and
//! invalid values are errors that name the key path (for example
//! `effects.asymmetry.a`). Writing uses Rust's shortest round-trip float
//! formatting, so a written file reads back bit-exact.

use crate::effect::Effect;
use std::fmt;
use std::path::{Path, PathBuf};

/// The friction model with the plant mass (MODEL.md §1–§3, §5, §7).
///
/// In a model file `fs == fc` marks a model without `stribeck` and
/// `z_max == 0` a model without `presliding`; `sigma > 0` is the effect
/// `viscous`.
#[derive(Clone, Debug, PartialEq)]
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
    pub effects: Effects,
}

/// The optional effects of MODEL.md §5; an effect is present when `Some`.
#[derive(Clone, Debug, PartialEq, Default)]
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Offset {
    /// `F0` [N], signed, finite.
    pub f0: f64,
}

/// Effect `asymmetry` (§5): `Fc`, `Fs` scaled by `(1 + a)` while `d = +1`
/// and `(1 − a)` while `d = −1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Asymmetry {
    /// `a` [-], `−1 < a < 1`.
    pub a: f64,
}

/// Effect `position_ripple` (§5): `F += A·sin(2π·x/λ + φ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PositionRipple {
    /// Amplitude `A` [N], finite.
    pub amplitude: f64,
    /// Wavelength `λ` [m], `> 0`.
    pub wavelength: f64,
    /// Phase `φ` [rad], finite.
    pub phase: f64,
}

/// Effect `dwell_stiction` (§5): `Fs` raised by `ΔFs·t_d/(t_d + γ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DwellStiction {
    /// `ΔFs` [N], `>= 0`.
    pub delta_fs: f64,
    /// Time constant `γ` [s], `> 0`.
    pub gamma: f64,
    /// Rest threshold `v_rest` [m/s], `> 0`: at rest while `|v| <= v_rest`.
    pub v_rest: f64,
}

/// Effect `frictional_lag` (§5): `τ_L·dv_l/dt = v − v_l`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionalLag {
    /// Lag time constant `τ_L` [s], `> 0`.
    pub tau_l: f64,
}

/// Effect `drift` (§5): `Fc`, `Fs` scaled by `(1 + β·t)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drift {
    /// `β` [1/s], finite.
    pub beta: f64,
}

/// Effect `nonlinear_viscous` (§5): `F += σ_n·sgn(v)·|v|^n`, velocity
/// strengthening that is not proportional to speed (gear and seal friction);
/// `n = 1` would be `viscous`.
#[derive(Clone, Copy, Debug, PartialEq)]
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

/// One numeric rule of §2/§3/§5.
#[derive(Clone, Copy)]
enum Rule {
    Finite,
    Positive,
    NonNegative,
    OpenUnit, // -1 < x < 1
}

fn check(key: &str, value: f64, rule: Rule) -> Result<(), ModelError> {
    if !value.is_finite() {
        return Err(ModelError::new(
            key,
            format!("must be finite, got {value:?}"),
        ));
    }
    let (ok, what) = match rule {
        Rule::Finite => (true, ""),
        Rule::Positive => (value > 0.0, "must be > 0"),
        Rule::NonNegative => (value >= 0.0, "must be >= 0"),
        Rule::OpenUnit => (value > -1.0 && value < 1.0, "must satisfy -1 < a < 1"),
    };
    if ok {
        Ok(())
    } else {
        Err(ModelError::new(key, format!("{what}, got {value:?}")))
    }
}

impl Model {
    /// Checks every rule of MODEL.md §2, §3 and §5 (plus `mass > 0`).
    /// `z_max = 0` is allowed (a model without presliding, as in files).
    /// The error names the first offending key.
    pub fn validate(&self) -> Result<(), ModelError> {
        check("mass", self.mass, Rule::Positive)?;
        check("fc", self.fc, Rule::Positive)?;
        check("fs", self.fs, Rule::Finite)?;
        if self.fs < self.fc {
            return Err(ModelError::new(
                "fs",
                format!("must be >= fc ({:?}), got {:?}", self.fc, self.fs),
            ));
        }
        check("v_stribeck", self.v_stribeck, Rule::Positive)?;
        check("delta", self.delta, Rule::Positive)?;
        check("sigma", self.sigma, Rule::NonNegative)?;
        check("z_max", self.z_max, Rule::NonNegative)?;
        check("epsilon", self.epsilon, Rule::NonNegative)?;
        let e = &self.effects;
        if let Some(o) = &e.offset {
            check("effects.offset.f0", o.f0, Rule::Finite)?;
        }
        if let Some(a) = &e.asymmetry {
            check("effects.asymmetry.a", a.a, Rule::OpenUnit)?;
        }
        if let Some(r) = &e.position_ripple {
            check(
                "effects.position_ripple.amplitude",
                r.amplitude,
                Rule::Finite,
            )?;
            check(
                "effects.position_ripple.wavelength",
                r.wavelength,
                Rule::Positive,
            )?;
            check("effects.position_ripple.phase", r.phase, Rule::Finite)?;
        }
        if let Some(d) = &e.dwell_stiction {
            check(
                "effects.dwell_stiction.delta_fs",
                d.delta_fs,
                Rule::NonNegative,
            )?;
            check("effects.dwell_stiction.gamma", d.gamma, Rule::Positive)?;
            check("effects.dwell_stiction.v_rest", d.v_rest, Rule::Positive)?;
        }
        if let Some(l) = &e.frictional_lag {
            check("effects.frictional_lag.tau_l", l.tau_l, Rule::Positive)?;
        }
        if let Some(d) = &e.drift {
            check("effects.drift.beta", d.beta, Rule::Finite)?;
        }
        if let Some(nv) = &e.nonlinear_viscous {
            check(
                "effects.nonlinear_viscous.sigma_n",
                nv.sigma_n,
                Rule::NonNegative,
            )?;
            check("effects.nonlinear_viscous.n", nv.n, Rule::Positive)?;
            if nv.n > 2.0 {
                return Err(ModelError::new(
                    "effects.nonlinear_viscous.n",
                    format!("must be in (0, 2], got {:?}", nv.n),
                ));
            }
        }
        Ok(())
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
        let mut top = Reader::new("", &table);
        let mut model = Model {
            mass: top.float("mass")?,
            fc: top.float("fc")?,
            fs: top.float("fs")?,
            v_stribeck: top.float("v_stribeck")?,
            delta: top.float("delta")?,
            sigma: top.float("sigma")?,
            z_max: top.float("z_max")?,
            epsilon: top.float("epsilon")?,
            effects: Effects::default(),
        };
        if let Some(effects) = top.table("effects")? {
            let mut er = Reader::new("effects.", effects);
            if let Some(mut r) = er.effect(Effect::Offset)? {
                model.effects.offset = Some(Offset { f0: r.float("f0")? });
                r.finish()?;
            }
            if let Some(mut r) = er.effect(Effect::Asymmetry)? {
                model.effects.asymmetry = Some(Asymmetry { a: r.float("a")? });
                r.finish()?;
            }
            if let Some(mut r) = er.effect(Effect::PositionRipple)? {
                model.effects.position_ripple = Some(PositionRipple {
                    amplitude: r.float("amplitude")?,
                    wavelength: r.float("wavelength")?,
                    phase: r.float("phase")?,
                });
                r.finish()?;
            }
            if let Some(mut r) = er.effect(Effect::DwellStiction)? {
                model.effects.dwell_stiction = Some(DwellStiction {
                    delta_fs: r.float("delta_fs")?,
                    gamma: r.float("gamma")?,
                    v_rest: r.float("v_rest")?,
                });
                r.finish()?;
            }
            if let Some(mut r) = er.effect(Effect::FrictionalLag)? {
                model.effects.frictional_lag = Some(FrictionalLag {
                    tau_l: r.float("tau_l")?,
                });
                r.finish()?;
            }
            if let Some(mut r) = er.effect(Effect::Drift)? {
                model.effects.drift = Some(Drift {
                    beta: r.float("beta")?,
                });
                r.finish()?;
            }
            if let Some(mut r) = er.effect(Effect::NonlinearViscous)? {
                model.effects.nonlinear_viscous = Some(NonlinearViscous {
                    sigma_n: r.float("sigma_n")?,
                    n: r.float("n")?,
                });
                r.finish()?;
            }
            er.finish()?;
        }
        top.finish()?;
        model.validate()?;
        Ok(model)
    }

    /// Writes the model file (§7). Floats use the shortest representation that
    /// reads back to the same bits (`1.0`, `1e-5`, `-0.0`, ...), so
    /// `Model::from_toml_str(&m.to_toml_string())` returns `m` bit-exact for
    /// every valid `m`.
    pub fn to_toml_string(&self) -> String {
        let mut s = String::new();
        let header = |s: &mut String, effect: Effect| {
            s.push_str(&format!("\n[effects.{}]\n", effect.name()));
        };
        let kv = |s: &mut String, key: &str, v: f64, comment: &str| {
            let val = fmt_float(v);
            if comment.is_empty() {
                s.push_str(&format!("{key} = {val}\n"));
            } else {
                s.push_str(&format!("{key} = {val}  # {comment}\n"));
            }
        };
        kv(&mut s, "mass", self.mass, "m [kg]");
        kv(&mut s, "fc", self.fc, "Fc [N]");
        kv(&mut s, "fs", self.fs, "Fs [N]");
        kv(&mut s, "v_stribeck", self.v_stribeck, "V [m/s]");
        kv(&mut s, "delta", self.delta, "shape exponent");
        kv(&mut s, "sigma", self.sigma, "viscous [N*s/m]");
        kv(&mut s, "z_max", self.z_max, "presliding distance [m]");
        kv(
            &mut s,
            "epsilon",
            self.epsilon,
            "turning-point deadband [m]",
        );
        let e = &self.effects;
        if let Some(o) = &e.offset {
            header(&mut s, Effect::Offset);
            kv(&mut s, "f0", o.f0, "[N]");
        }
        if let Some(a) = &e.asymmetry {
            header(&mut s, Effect::Asymmetry);
            kv(&mut s, "a", a.a, "");
        }
        if let Some(r) = &e.position_ripple {
            header(&mut s, Effect::PositionRipple);
            kv(&mut s, "amplitude", r.amplitude, "[N]");
            kv(&mut s, "wavelength", r.wavelength, "[m]");
            kv(&mut s, "phase", r.phase, "[rad]");
        }
        if let Some(d) = &e.dwell_stiction {
            header(&mut s, Effect::DwellStiction);
            kv(&mut s, "delta_fs", d.delta_fs, "[N]");
            kv(&mut s, "gamma", d.gamma, "[s]");
            kv(&mut s, "v_rest", d.v_rest, "[m/s]");
        }
        if let Some(l) = &e.frictional_lag {
            header(&mut s, Effect::FrictionalLag);
            kv(&mut s, "tau_l", l.tau_l, "[s]");
        }
        if let Some(d) = &e.drift {
            header(&mut s, Effect::Drift);
            kv(&mut s, "beta", d.beta, "[1/s]");
        }
        if let Some(nv) = &e.nonlinear_viscous {
            header(&mut s, Effect::NonlinearViscous);
            kv(&mut s, "sigma_n", nv.sigma_n, "[N*(s/m)^n]");
            kv(&mut s, "n", nv.n, "");
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

/// Strict reader of one TOML table: tracks the keys used.
struct Reader<'a> {
    prefix: String,
    table: &'a toml::Table,
    used: Vec<&'static str>,
}

impl<'a> Reader<'a> {
    fn new(prefix: impl Into<String>, table: &'a toml::Table) -> Self {
        Reader {
            prefix: prefix.into(),
            table,
            used: Vec::new(),
        }
    }

    fn path(&self, key: &str) -> String {
        format!("{}{}", self.prefix, key)
    }

    fn float(&mut self, key: &'static str) -> Result<f64, ModelError> {
        self.used.push(key);
        match self.table.get(key) {
            None => Err(ModelError::new(self.path(key), "missing required key")),
            Some(toml::Value::Float(f)) => Ok(*f),
            // Integers are accepted as floats (`mass = 1`). i64 -> f64 rounds
            // to nearest for huge values, which is the natural reading.
            #[allow(clippy::cast_precision_loss)]
            Some(toml::Value::Integer(i)) => Ok(*i as f64),
            Some(other) => Err(ModelError::new(
                self.path(key),
                format!("expected a number, got {}", other.type_str()),
            )),
        }
    }

    fn table(&mut self, key: &'static str) -> Result<Option<&'a toml::Table>, ModelError> {
        self.used.push(key);
        match self.table.get(key) {
            None => Ok(None),
            Some(toml::Value::Table(t)) => Ok(Some(t)),
            Some(other) => Err(ModelError::new(
                self.path(key),
                format!("expected a table, got {}", other.type_str()),
            )),
        }
    }

    /// The reader of the table of `effect` under `[effects]` (§7), if present.
    fn effect(&mut self, effect: Effect) -> Result<Option<Reader<'a>>, ModelError> {
        let prefix = format!("{}{}.", self.prefix, effect.name());
        Ok(self.table(effect.name())?.map(|t| Reader::new(prefix, t)))
    }

    /// Error on the first key that was not read.
    fn finish(&self) -> Result<(), ModelError> {
        for key in self.table.keys() {
            if !self.used.iter().any(|u| u == key) {
                return Err(ModelError::new(self.path(key), "unknown key"));
            }
        }
        Ok(())
    }
}
