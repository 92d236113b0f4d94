//! The names of the effect catalogue (MODEL.md §5): the identifiers that
//! reports and configuration files use as written.
//!
//! [`Effect`] names an effect; which of them a [`crate::Model`] has lives in
//! its fields (`sigma > 0` is `viscous`, `fs > fc` is `stribeck`,
//! `z_max > 0` is `presliding`, the others are in [`crate::Effects`]).

use std::fmt;
use std::str::FromStr;

/// One effect of the catalogue of MODEL.md §5.
///
/// `stribeck` and `presliding` are parts of the base model of §2–§3 that a
/// model may lack; the others are additions to it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Effect {
    /// `viscous`: `F += σ·v`.
    Viscous,
    /// `nonlinear_viscous`: `F += σ_n·sgn(v)·|v|^n`, `n ≠ 1`.
    NonlinearViscous,
    /// `offset`: `F += F0`, at rest and in motion alike.
    Offset,
    /// `asymmetry`: `Fc`, `Fs` scaled by `1 + a·d`.
    Asymmetry,
    /// `position_ripple`: `F += A·sin(2π·x/λ + φ)`.
    PositionRipple,
    /// `dwell_stiction`: `Fs` raised by `ΔFs·t_d/(t_d + γ)`.
    DwellStiction,
    /// `frictional_lag`: `S` evaluated at the lagged velocity `v_l`.
    FrictionalLag,
    /// `drift`: `Fc`, `Fs` scaled by `1 + β·t`.
    Drift,
    /// `stribeck`: the velocity weakening `Fs > Fc` of §2.
    Stribeck,
    /// `presliding`: the rate-independent hysteresis of §3 (`z_max > 0`).
    Presliding,
}

impl Effect {
    /// The whole catalogue, in the order in which the discrepancy workflow
    /// tries candidates (the order breaks ties between them).
    pub const ALL: [Effect; 10] = [
        Effect::Viscous,
        Effect::NonlinearViscous,
        Effect::Offset,
        Effect::Asymmetry,
        Effect::PositionRipple,
        Effect::DwellStiction,
        Effect::FrictionalLag,
        Effect::Drift,
        Effect::Stribeck,
        Effect::Presliding,
    ];

    /// Whether the effect is a table under `[effects]` of a model file
    /// (MODEL.md §7): the additions of §5. `viscous`, `stribeck` and
    /// `presliding` are keys of the §2–§3 model itself (`sigma`, `fs`,
    /// `z_max`).
    pub fn has_table(self) -> bool {
        match self {
            Effect::Viscous | Effect::Stribeck | Effect::Presliding => false,
            Effect::NonlinearViscous
            | Effect::Offset
            | Effect::Asymmetry
            | Effect::PositionRipple
            | Effect::DwellStiction
            | Effect::FrictionalLag
            | Effect::Drift => true,
        }
    }

    /// The identifier of MODEL.md §5 (`viscous`, `nonlinear_viscous`, …),
    /// also the table name under `[effects]` in a model file (§7).
    pub fn name(self) -> &'static str {
        match self {
            Effect::Viscous => "viscous",
            Effect::NonlinearViscous => "nonlinear_viscous",
            Effect::Offset => "offset",
            Effect::Asymmetry => "asymmetry",
            Effect::PositionRipple => "position_ripple",
            Effect::DwellStiction => "dwell_stiction",
            Effect::FrictionalLag => "frictional_lag",
            Effect::Drift => "drift",
            Effect::Stribeck => "stribeck",
            Effect::Presliding => "presliding",
        }
    }
}

impl fmt::Display for Effect {
    /// The identifier, as [`Effect::name`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Effect {
    type Err = UnknownEffect;

    /// The effect named exactly `s` (the identifiers of MODEL.md §5).
    fn from_str(s: &str) -> Result<Effect, UnknownEffect> {
        Effect::ALL
            .into_iter()
            .find(|e| e.name() == s)
            .ok_or_else(|| UnknownEffect {
                name: s.to_string(),
            })
    }
}

/// A name that is not in the catalogue of MODEL.md §5.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownEffect {
    /// The name given.
    pub name: String,
}

impl fmt::Display for UnknownEffect {
    /// `unknown effect `NAME` (expected viscous, …, presliding)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown effect `{}` (expected ", self.name)?;
        for (i, e) in Effect::ALL.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(e.name())?;
        }
        f.write_str(")")
    }
}

impl std::error::Error for UnknownEffect {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for e in Effect::ALL {
            assert_eq!(e.name().parse::<Effect>(), Ok(e));
            assert_eq!(e.to_string(), e.name());
        }
    }

    #[test]
    fn unknown_names_the_name_and_the_catalogue() {
        let err = "viscus".parse::<Effect>().unwrap_err();
        let msg = err.to_string();
        assert!(msg.starts_with("unknown effect `viscus` (expected viscous, "));
        assert!(msg.ends_with("stribeck, presliding)"));
        assert!("Viscous".parse::<Effect>().is_err());
        assert!(" viscous".parse::<Effect>().is_err());
    }
}
