//! Command-line parsing (hand-written so that every error is one line naming
//! the argument, see [`crate::Error`]).
//!
//! Number lists (`--k`, `--masses`) are comma-separated items, each either a
//! number or an inclusive range `START:STOP:STEP` (`0.01,0.1,1:30:1`). A range
//! runs `START, START+STEP, …` and includes `STOP` when `STOP` lies on the grid
//! within rounding (1e-9 of a step); `0.01:30:2` is the paper's grid
//! "k ∈ [0.01 … 30] with an increment 2" and ends at 28.01.

use crate::reference::Variant;
use crate::Error;
use std::path::PathBuf;

/// The text of `--help`.
pub const USAGE: &str = "\
breakaway-lab: command-line front of the breakaway f64 reference model (MODEL.md)

USAGE:
  breakaway-lab breakaway --model FILE --k LIST [--variant V] [--wb W] [--dynamic] [--json|--markdown]
  breakaway-lab validity-map --model FILE [--masses LIST] [--k LIST] [--variant V] [--wb W]
                             [--json|--markdown]

  breakaway     quasi-static break-away force F_ba(k) under the ramp u = k*t (MODEL.md §4);
                --dynamic adds the full-dynamics simulation (F_ba_sim, t_ba_sim)
  validity-map  quasi-static vs full dynamics over masses x force rates, with the inertia
                number Λ = m*k^2*z_max/(F̂^3*w_b*|ln w_b|^3) (F̂ = (Fc+Fs)/2, MODEL.md §4)
                and Π = sqrt(2*Fs*z_max/m)/V (MODEL.md §8)
  diagnose, fit, validate, synth, static-curve
                the discrepancy workflow: see `breakaway-lab diagnose --help`

OPTIONS:
  --model FILE    model file, TOML as in MODEL.md §7
  --k LIST        force rates [N/s] > 0: comma-separated numbers and ranges START:STOP:STEP
                  (STOP included when on the grid), e.g. 0.01,0.1,1:30:1
                  (validity-map default: 0.01,0.03,0.1,0.3,1,3,10,30)
  --masses LIST   masses [kg] > 0, same syntax (default 0.1,1,10)
  --variant V     coulomb|stiction|mean|consistent|all, or a comma list
                  (default: all for breakaway, mean,consistent for validity-map)
  --wb W          presliding boundary w_b in (0, 1) (default 0.95)
  --dynamic       breakaway: also simulate the full dynamics, once per k
  --json          JSON array of objects instead of a table
  --markdown      markdown instead of a text table: breakaway gives one row per k with
                  F_ba per variant (and F_ba_sim); validity-map gives one drift table per
                  variant, k down and m across
  -h, --help      this text
";

/// Default `--k` of `validity-map`.
pub const DEFAULT_VALIDITY_K: &str = "0.01,0.03,0.1,0.3,1,3,10,30";
/// Default `--masses` of `validity-map`.
pub const DEFAULT_MASSES: &str = "0.1,1,10";
/// Default presliding boundary `w_b` (MODEL.md §4, the paper's `z_0.95`).
pub const DEFAULT_WB: f64 = 0.95;
/// Most points a number list may expand to.
pub const MAX_POINTS: usize = 100_000;

/// Arguments of `breakaway`.
#[derive(Clone, Debug, PartialEq)]
pub struct BreakawayArgs {
    /// Model file.
    pub model: PathBuf,
    /// Force rates [N/s], in the order given.
    pub k: Vec<f64>,
    /// Variants, in the order given (`all` = MODEL.md order).
    pub variants: Vec<Variant>,
    /// Presliding boundary `w_b`.
    pub w_b: f64,
    /// Also run the full dynamics.
    pub dynamic: bool,
    /// Output format.
    pub format: Format,
}

/// Output format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Aligned text table (default).
    Table,
    /// `--json`.
    Json,
    /// `--markdown`.
    Markdown,
}

/// Arguments of `validity-map`.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidityArgs {
    /// Model file (its mass is replaced by each of `masses`).
    pub model: PathBuf,
    /// Masses [kg].
    pub masses: Vec<f64>,
    /// Force rates [N/s].
    pub k: Vec<f64>,
    /// Variants compared with the dynamics.
    pub variants: Vec<Variant>,
    /// Presliding boundary `w_b`.
    pub w_b: f64,
    /// Output format.
    pub format: Format,
}

/// A parsed command line.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// `--help` / `-h` (anywhere).
    Help,
    /// `breakaway …`.
    Breakaway(BreakawayArgs),
    /// `validity-map …`.
    ValidityMap(ValidityArgs),
}

fn usage(msg: impl Into<String>) -> Error {
    Error::Usage(msg.into())
}

/// Raw options: values of `--name VALUE` / `--name=VALUE` and flags.
#[derive(Default)]
struct Raw {
    model: Option<String>,
    k: Option<String>,
    masses: Option<String>,
    variant: Option<String>,
    wb: Option<String>,
    dynamic: bool,
    json: bool,
    markdown: bool,
}

/// Parses the arguments after the program name.
pub fn parse(args: &[String]) -> Result<Command, Error> {
    if args.iter().any(|a| a == "-h" || a == "--help") {
        return Ok(Command::Help);
    }
    let Some((sub, rest)) = args.split_first() else {
        return Err(usage(
            "missing sub-command (breakaway or validity-map); see --help",
        ));
    };
    let validity = match sub.as_str() {
        "breakaway" => false,
        "validity-map" => true,
        other => {
            return Err(usage(format!(
                "unknown sub-command `{other}` (expected breakaway or validity-map)"
            )))
        }
    };
    let raw = parse_raw(rest, validity)?;
    let model = PathBuf::from(
        raw.model
            .ok_or_else(|| usage(format!("{sub}: missing --model FILE")))?,
    );
    let format = match (raw.json, raw.markdown) {
        (true, true) => return Err(usage("--json and --markdown exclude each other")),
        (true, false) => Format::Json,
        (false, true) => Format::Markdown,
        (false, false) => Format::Table,
    };
    let w_b = match &raw.wb {
        Some(s) => parse_wb(s)?,
        None => DEFAULT_WB,
    };
    if validity {
        let k = parse_list(raw.k.as_deref().unwrap_or(DEFAULT_VALIDITY_K))
            .map_err(|e| usage(format!("--k: {e}")))?;
        let masses = parse_list(raw.masses.as_deref().unwrap_or(DEFAULT_MASSES))
            .map_err(|e| usage(format!("--masses: {e}")))?;
        let variants = parse_variants(raw.variant.as_deref().unwrap_or("mean,consistent"))?;
        Ok(Command::ValidityMap(ValidityArgs {
            model,
            masses,
            k,
            variants,
            w_b,
            format,
        }))
    } else {
        let k = raw
            .k
            .ok_or_else(|| usage("breakaway: missing --k LIST"))
            .and_then(|s| parse_list(&s).map_err(|e| usage(format!("--k: {e}"))))?;
        let variants = parse_variants(raw.variant.as_deref().unwrap_or("all"))?;
        Ok(Command::Breakaway(BreakawayArgs {
            model,
            k,
            variants,
            w_b,
            dynamic: raw.dynamic,
            format,
        }))
    }
}

fn parse_raw(rest: &[String], validity: bool) -> Result<Raw, Error> {
    let mut raw = Raw::default();
    let mut it = rest.iter();
    while let Some(arg) = it.next() {
        let (name, inline) = match arg.split_once('=') {
            Some((n, v)) if n.starts_with("--") => (n, Some(v.to_string())),
            _ => (arg.as_str(), None),
        };
        let flag = |set: &mut bool| -> Result<(), Error> {
            if inline.is_some() {
                return Err(usage(format!("{name} takes no value")));
            }
            if *set {
                return Err(usage(format!("{name} given twice")));
            }
            *set = true;
            Ok(())
        };
        let slot = match name {
            "--json" => {
                flag(&mut raw.json)?;
                continue;
            }
            "--markdown" => {
                flag(&mut raw.markdown)?;
                continue;
            }
            "--dynamic" if !validity => {
                flag(&mut raw.dynamic)?;
                continue;
            }
            "--model" => &mut raw.model,
            "--k" => &mut raw.k,
            "--masses" if validity => &mut raw.masses,
            "--variant" => &mut raw.variant,
            "--wb" => &mut raw.wb,
            _ if name.starts_with('-') && name.len() > 1 => {
                let sub = if validity {
                    "validity-map"
                } else {
                    "breakaway"
                };
                return Err(usage(format!("{sub}: unknown option `{name}`; see --help")));
            }
            _ => return Err(usage(format!("unexpected argument `{arg}`; see --help"))),
        };
        if slot.is_some() {
            return Err(usage(format!("{name} given twice")));
        }
        let value = match inline {
            Some(v) => v,
            None => it
                .next()
                .cloned()
                .ok_or_else(|| usage(format!("{name}: missing value")))?,
        };
        if value.is_empty() {
            return Err(usage(format!("{name}: empty value")));
        }
        *slot = Some(value);
    }
    Ok(raw)
}

fn parse_wb(s: &str) -> Result<f64, Error> {
    let w: f64 = s
        .trim()
        .parse()
        .map_err(|_| usage(format!("--wb: `{s}` is not a number")))?;
    if w > 0.0 && w < 1.0 {
        Ok(w)
    } else {
        Err(usage(format!("--wb: {s} is outside (0, 1)")))
    }
}

/// Parses `--variant`: `all` or a comma list of variant names.
pub fn parse_variants(s: &str) -> Result<Vec<Variant>, Error> {
    if s.trim() == "all" {
        return Ok(Variant::ALL.to_vec());
    }
    let mut out = Vec::new();
    for item in s.split(',').map(str::trim) {
        let v = Variant::parse(item).ok_or_else(|| {
            usage(format!(
                "--variant: unknown variant `{item}` (expected coulomb, stiction, mean, consistent or all)"
            ))
        })?;
        if !out.contains(&v) {
            out.push(v);
        }
    }
    Ok(out)
}

fn number(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{}` is not a number", s.trim()))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("`{}` is not finite", s.trim()))
    }
}

/// Parses a list of positive numbers: comma-separated numbers and inclusive
/// ranges `START:STOP:STEP` (see the module documentation). The error text
/// names the offending item; the caller prefixes the option name.
pub fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    let mut out: Vec<f64> = Vec::new();
    for item in s.split(',') {
        let item = item.trim();
        if item.is_empty() {
            return Err(format!("empty item in `{s}`"));
        }
        let parts: Vec<&str> = item.split(':').collect();
        match parts.as_slice() {
            [x] => out.push(number(x)?),
            [a, b, c] => {
                let (start, stop, step) = (number(a)?, number(b)?, number(c)?);
                if step <= 0.0 {
                    return Err(format!("range `{item}`: STEP must be > 0"));
                }
                if stop < start {
                    return Err(format!("range `{item}`: STOP is below START"));
                }
                let n = ((stop - start) / step + 1e-9).floor();
                if n >= MAX_POINTS as f64 || out.len() + n as usize >= MAX_POINTS {
                    return Err(format!("range `{item}`: more than {MAX_POINTS} points"));
                }
                let n = n as usize;
                for i in 0..=n {
                    let x = start + i as f64 * step;
                    // The last point snaps to STOP when it lies on the grid.
                    let x = if i == n && (stop - x).abs() <= 1e-9 * step {
                        stop
                    } else {
                        x
                    };
                    out.push(x);
                }
            }
            _ => {
                return Err(format!(
                    "`{item}` is neither a number nor a range START:STOP:STEP"
                ))
            }
        }
        if out.len() > MAX_POINTS {
            return Err(format!("more than {MAX_POINTS} points"));
        }
    }
    if let Some(bad) = out.iter().find(|x| **x <= 0.0) {
        return Err(format!("values must be > 0, got {bad}"));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn argv(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn list_forms() {
        assert_eq!(parse_list("1").unwrap(), vec![1.0]);
        assert_eq!(parse_list("0.01, 0.1 ,1").unwrap(), vec![0.01, 0.1, 1.0]);
        assert_eq!(parse_list("1:3:1").unwrap(), vec![1.0, 2.0, 3.0]);
        assert_eq!(
            parse_list("0.01,0.1,1:3:1").unwrap(),
            vec![0.01, 0.1, 1.0, 2.0, 3.0]
        );
        // STOP included when on the grid within rounding, and exactly STOP.
        let g = parse_list("0.1:0.3:0.1").unwrap();
        assert_eq!(g.len(), 3);
        assert_eq!(g[2], 0.3);
        let g = parse_list("0.01:30:0.01").unwrap();
        assert_eq!(g.len(), 3000);
        assert_eq!(*g.last().unwrap(), 30.0);
        // The paper's grid: STOP not on the grid.
        let g = parse_list("0.01:30:2").unwrap();
        assert_eq!(g.len(), 15);
        assert!((g[14] - 28.01).abs() < 1e-12);
        // A one-point range and ranges mixed with numbers.
        assert_eq!(parse_list("5:5:1,1e-3").unwrap(), vec![5.0, 0.001]);
    }

    #[test]
    fn bad_lists() {
        for bad in [
            "",
            "1,",
            ",1",
            "a",
            "1:2",
            "1:2:3:4",
            "1:2:0",
            "1:2:-1",
            "3:1:1",
            "0",
            "-1",
            "0:1:0.5",
            "inf",
            "nan",
            "1e400",
            "1:1e9:1e-3",
        ] {
            assert!(parse_list(bad).is_err(), "accepted `{bad}`");
        }
        assert!(parse_list("0.5,x")
            .unwrap_err()
            .contains("`x` is not a number"));
    }

    #[test]
    fn commands() {
        let c = parse(&argv("breakaway --model m.toml --k 1,2")).unwrap();
        let Command::Breakaway(a) = c else { panic!() };
        assert_eq!(a.k, vec![1.0, 2.0]);
        assert_eq!(a.variants, Variant::ALL.to_vec());
        assert_eq!(a.w_b, 0.95);
        assert!(!a.dynamic);
        assert_eq!(a.format, Format::Table);
        let c = parse(&argv(
            "breakaway --json --k=3 --variant consistent,mean --wb=0.9 --dynamic --model=m.toml",
        ))
        .unwrap();
        let Command::Breakaway(a) = c else { panic!() };
        assert_eq!(a.variants, vec![Variant::Consistent, Variant::Mean]);
        assert_eq!((a.w_b, a.dynamic, a.format), (0.9, true, Format::Json));
        let c = parse(&argv("validity-map --model m.toml")).unwrap();
        let Command::ValidityMap(a) = c else { panic!() };
        assert_eq!(a.masses, vec![0.1, 1.0, 10.0]);
        assert_eq!(a.k.len(), 8);
        assert_eq!(a.variants, vec![Variant::Mean, Variant::Consistent]);
        assert_eq!(parse(&argv("breakaway --help")).unwrap(), Command::Help);
    }

    #[test]
    fn bad_commands_are_usage_errors() {
        for (line, needle) in [
            ("", "sub-command"),
            ("simulate --model m", "simulate"),
            ("breakaway --k 1", "--model"),
            ("breakaway --model m.toml", "--k"),
            ("breakaway --model m.toml --k", "--k"),
            ("breakaway --model m.toml --k 0", "--k"),
            ("breakaway --model m.toml --k 1 --k 2", "twice"),
            ("breakaway --model m.toml --k 1 --wb 1", "--wb"),
            ("breakaway --model m.toml --k 1 --wb 0", "--wb"),
            ("breakaway --model m.toml --k 1 --wb x", "--wb"),
            ("breakaway --model m.toml --k 1 --variant fast", "fast"),
            ("breakaway --model m.toml --k 1 --masses 1", "--masses"),
            ("breakaway --model m.toml --k 1 --json=yes", "--json"),
            ("breakaway --model m.toml --k 1 extra", "extra"),
            ("validity-map --model m.toml --dynamic", "--dynamic"),
            (
                "validity-map --model m.toml --json --markdown",
                "--markdown",
            ),
            ("validity-map --model m.toml --masses 0,1", "--masses"),
        ] {
            let e = parse(&argv(line)).unwrap_err();
            assert_eq!(e.exit_code(), 2, "{line}");
            let msg = e.to_string();
            assert!(msg.contains(needle), "`{line}` -> `{msg}`");
            assert!(!msg.contains('\n'));
        }
    }
}
