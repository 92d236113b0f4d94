//! The command line: one [`clap`] parser for every sub-command, with its
//! options, defaults, value ranges and `--help` text.
//!
//! Values are checked here, at the boundary: a bad value is a parse error
//! naming the option (exit code 2), so that the commands only meet valid
//! arguments. Number lists (`--k`, `--masses`) are comma-separated items,
//! each either a number or an inclusive range `START:STOP:STEP`
//! (`0.01,0.1,1:30:1`). A range runs `START, START+STEP, …` and includes
//! `STOP` when `STOP` lies on the grid within rounding (1e-9 of a step);
//! `0.01:30:2` is the paper's grid "k ∈ [0.01 … 30] with an increment 2" and
//! ends at 28.01.

use crate::reference::{Effect, Variant};
use crate::synth::{self, Noise};
use clap::builder::RangedU64ValueParser;
use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// Default `--k` of `validity-map`.
pub const DEFAULT_VALIDITY_K: &str = "0.01,0.03,0.1,0.3,1,3,10,30";
/// Default `--masses` of `validity-map`.
pub const DEFAULT_MASSES: &str = "0.1,1,10";
/// Default presliding boundary `w_b` (the break-away predictor's, the paper's `z_0.95`).
pub const DEFAULT_WB: f64 = 0.95;
/// Most points a number list may expand to.
pub const MAX_POINTS: usize = 100_000;
/// The range of `--window` (Savitzky–Golay half-width, samples).
pub const WINDOW_RANGE: std::ops::RangeInclusive<u64> = 2..=64;

/// The command line of `breakaway-lab`.
#[derive(Clone, Debug, Parser)]
#[command(
    name = "breakaway-lab",
    version = crate::diagnose::VERSION_LINE,
    about = "Command-line front of the breakaway f64 reference model",
    after_help = "The discrepancy workflow (diagnose, fit, validate, synth, static-curve): \
                  see `breakaway-lab diagnose --help` and lab/README.md (also the data and \
                  model file formats). The equations: the `model_overview` page of the \
                  breakaway crate's documentation.",
    arg_required_else_help = false,
    disable_help_subcommand = true
)]
pub struct Cli {
    /// The sub-command.
    #[command(subcommand)]
    pub command: Command,
}

/// A sub-command with its arguments.
#[derive(Clone, Debug, Subcommand)]
pub enum Command {
    /// Quasi-static break-away force F_ba(k) under the ramp u = k*t.
    ///
    /// For each F̂ variant and force rate k: the break-away velocity v_b,
    /// force F_ba and time t_ba; --dynamic adds the full-dynamics simulation
    /// (F_ba_sim, t_ba_sim). --markdown gives one row per k with F_ba per
    /// variant (and F_ba_sim).
    Breakaway(BreakawayArgs),
    /// Quasi-static vs full dynamics over masses x force rates.
    ///
    /// With the inertia number Λ = m*k^2*z_max/(F̂^3*w_b*|ln w_b|^3)
    /// (F̂ = (Fc+Fs)/2) and Π = sqrt(2*Fs*z_max/m)/V (rests are quiet below
    /// about 5).
    /// The model's mass is replaced by each of --masses. --markdown gives one
    /// drift table per variant, k down and m across.
    ValidityMap(ValidityArgs),
    /// PID position loop with nine friction compensators on two plants,
    /// measured through an encoder.
    ///
    /// Tracks x_ref = A*(1 - cos 2*pi*f*t) (A = 1 mm, f = 1 Hz) on a LuGre
    /// plant and on a plant with the crate's friction model, its parameters
    /// 20-30 % off the compensator's; position from encoder counts (ideal,
    /// 1 um, 0.1 um per count), velocity from the library's
    /// VelocityEstimator. Compensators none, coulomb,
    /// stribeck, presliding, each also +observer, and
    /// presliding+observer+adaptation; figures over t in [5 s, 8 s]:
    /// rms_error [m], peak_reversal_error [m] (peak |e| within 50 ms after
    /// each reversal), rms_effort [N]. Also the drift runs (plant Fc, or Fc
    /// and Fs, +20 % at t = 2 s; 1 um encoder).
    ClosedLoop(ClosedLoopArgs),
    /// Where model and data disagree, and which effect of the catalogue is missing.
    ///
    /// Localises the disagreement (regimes, time windows, signals) and names
    /// the missing effect: each candidate added, refitted, scored by BIC on
    /// held-out blocks; accepted only if it also lowers the held-out
    /// rms by 5 % above the measurement floor; repeated until none helps. Without --model it starts from
    /// the base model (Coulomb + Stribeck + presliding, σ = 0) identified
    /// from the data.
    ///
    /// DATA: CSV with columns t, u, x (optional v), or a .mat file in the
    /// EMPS layout (lab/README.md, "Input files"). The residual is the force
    /// along the measured motion (compared locally). DATA may also be a
    /// steady-state record (the Indy7 layout, or CSV columns v, u): diagnose
    /// then fits the steady-state curve and tries the effects visible in it
    /// (viscous, nonlinear_viscous, offset, asymmetry).
    ///
    /// Reports give the gap as model error above the measurement floor
    /// (force noise and encoder resolution); samples where the position
    /// stays within one count are the measured friction, re-anchor the
    /// presliding memory and are not scored. Manual: lab/README.md.
    Diagnose(DiagnoseArgs),
    /// The parameters of a model structure (the given model's, or the base model).
    ///
    /// The residual is weighted with the data's base model's weights, as in
    /// validate, whatever the start: the figures of two fits of one record
    /// compare like with like.
    ///
    /// DATA: CSV with columns t, u, x (optional v: the velocity of x in m/s,
    /// used in place of the differentiated position), or a .mat file in the
    /// EMPS layout (lab/README.md, "Input files"). A steady-state record is
    /// refused: diagnose fits its curve.
    Fit(FitArgs),
    /// The metric of a fixed model on other data (all samples, per regime).
    ///
    /// DATA: CSV with columns t, u, x (optional v: the velocity of x in m/s,
    /// used in place of the differentiated position), or a .mat file in the
    /// EMPS layout (lab/README.md, "Input files"). A steady-state record is
    /// refused: diagnose fits its curve.
    Validate(ValidateArgs),
    /// Synthetic measurements with hidden effects.
    ///
    /// Closed-loop plateaus both ways, rests of varied length, force-ramp
    /// break-away tests, slow reversals; encoder quantisation and force
    /// noise.
    Synth(SynthArgs),
    /// Stribeck + viscous fit per direction of a steady-state friction file.
    ///
    /// Indy7 layout only: `desired vel, real vel, tau` in deg/s and N·m (a
    /// CSV with columns v, u goes to diagnose).
    StaticCurve(StaticCurveArgs),
}

/// Output format of `breakaway` and `validity-map`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Aligned text table (default).
    Table,
    /// `--json`.
    Json,
    /// `--markdown`.
    Markdown,
}

/// `--json` and `--markdown` of `breakaway` and `validity-map`.
#[derive(Clone, Debug, Args)]
pub struct FormatArgs {
    /// JSON array of objects instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Markdown instead of a text table.
    #[arg(long, conflicts_with = "json")]
    pub markdown: bool,
}

impl FormatArgs {
    /// The output format.
    pub fn format(&self) -> Format {
        if self.json {
            Format::Json
        } else if self.markdown {
            Format::Markdown
        } else {
            Format::Table
        }
    }
}

/// `--wb W` of `breakaway` and `validity-map`.
#[derive(Clone, Debug, Args)]
pub struct BoundaryArg {
    /// Presliding boundary w_b in (0, 1).
    #[arg(
        long = "wb",
        value_name = "W",
        default_value_t = DEFAULT_WB,
        value_parser = parse_wb,
        allow_negative_numbers = true
    )]
    pub w_b: f64,
}

/// Arguments of `breakaway`.
#[derive(Clone, Debug, Args)]
pub struct BreakawayArgs {
    /// Model file (TOML, lab/README.md, "Input files").
    #[arg(long, value_name = "FILE")]
    pub model: PathBuf,
    /// Force rates [N/s] > 0: comma-separated numbers and ranges
    /// START:STOP:STEP (STOP included when on the grid), e.g. 0.01,0.1,1:30:1.
    #[arg(long, value_name = "LIST", value_parser = parse_list, allow_hyphen_values = true)]
    pub k: ::std::vec::Vec<f64>,
    /// coulomb|stiction|mean|consistent|all, or a comma list.
    #[arg(long = "variant", value_name = "V", default_value = "all", value_parser = parse_variants)]
    pub variants: ::std::vec::Vec<Variant>,
    /// `--wb W`.
    #[command(flatten)]
    pub boundary: BoundaryArg,
    /// Also simulate the full dynamics, once per k.
    #[arg(long)]
    pub dynamic: bool,
    /// `--json`, `--markdown`.
    #[command(flatten)]
    pub output: FormatArgs,
}

/// Arguments of `validity-map`.
#[derive(Clone, Debug, Args)]
pub struct ValidityArgs {
    /// Model file (TOML, lab/README.md, "Input files"); its mass is replaced
    /// by each of --masses.
    #[arg(long, value_name = "FILE")]
    pub model: PathBuf,
    /// Masses [kg] > 0: comma-separated numbers and ranges START:STOP:STEP.
    #[arg(
        long,
        value_name = "LIST",
        default_value = DEFAULT_MASSES,
        value_parser = parse_list,
        allow_hyphen_values = true
    )]
    pub masses: ::std::vec::Vec<f64>,
    /// Force rates [N/s] > 0: comma-separated numbers and ranges
    /// START:STOP:STEP (STOP included when on the grid).
    #[arg(
        long,
        value_name = "LIST",
        default_value = DEFAULT_VALIDITY_K,
        value_parser = parse_list,
        allow_hyphen_values = true
    )]
    pub k: ::std::vec::Vec<f64>,
    /// Variants compared with the dynamics:
    /// coulomb|stiction|mean|consistent|all, or a comma list.
    #[arg(
        long = "variant",
        value_name = "V",
        default_value = "mean,consistent",
        value_parser = parse_variants
    )]
    pub variants: ::std::vec::Vec<Variant>,
    /// `--wb W`.
    #[command(flatten)]
    pub boundary: BoundaryArg,
    /// `--json`, `--markdown`.
    #[command(flatten)]
    pub output: FormatArgs,
}

/// Arguments of `closed-loop`.
#[derive(Clone, Debug, Args)]
pub struct ClosedLoopArgs {
    /// JSON array of objects {plant, drift, encoder, compensator, rms_error,
    /// peak_reversal_error, rms_effort} instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write the tracking error around the reversal at t = 6 s as an
    /// SVG plot (`-`: to standard output, instead of the table).
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// Standard deviation [N] of Gaussian noise on the force the plant
    /// receives (the controller knows only its command).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 0.0,
        value_parser = parse_non_negative,
        allow_hyphen_values = true
    )]
    pub force_noise: f64,
    /// Bandwidth [rad/s] of the disturbance observer (every +observer row).
    #[arg(
        long,
        value_name = "RAD_S",
        default_value_t = crate::closed_loop::OBSERVER_BANDWIDTH,
        value_parser = parse_positive,
        allow_hyphen_values = true
    )]
    pub observer_bandwidth: f64,
    /// Bandwidth [rad/s] of the velocity estimator on the encoder counts.
    #[arg(
        long,
        value_name = "RAD_S",
        default_value_t = crate::closed_loop::VELOCITY_BANDWIDTH,
        value_parser = parse_positive,
        allow_hyphen_values = true
    )]
    pub velocity_bandwidth: f64,
    /// Shift [counts], in [0, 1), of the encoder's zero: the count
    /// boundaries move by P counts, the reading stays unbiased (how much
    /// the 1 µm figures depend on where the counts fall).
    #[arg(
        long,
        value_name = "P",
        default_value_t = 0.0,
        value_parser = parse_non_negative,
        allow_hyphen_values = true
    )]
    pub count_phase: f64,
    /// The adaptive row adapts the single level scale θ (`LevelAdaptation`)
    /// instead of the Coulomb and stiction scales (`StictionAdaptation`).
    #[arg(long)]
    pub single_scale: bool,
}

/// Parses a finite number > 0.
fn parse_positive(s: &str) -> Result<f64, String> {
    let x = number(s)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{x} is not > 0"))
    }
}

/// Parses a finite number >= 0.
fn parse_non_negative(s: &str) -> Result<f64, String> {
    let x = number(s)?;
    if x >= 0.0 {
        Ok(x)
    } else {
        Err(format!("{x} is negative"))
    }
}

/// `--window K`: the Savitzky–Golay half-width of the differentiator (both
/// the velocity estimate and the force kernel).
#[derive(Clone, Debug, Args)]
pub struct WindowArg {
    /// Savitzky-Golay half-width in samples, 2..64, for the velocity and the
    /// force kernel alike (default: velocity 4, force kernel chosen from the
    /// data).
    #[arg(
        long = "window",
        value_name = "K",
        value_parser = RangedU64ValueParser::<usize>::new().range(WINDOW_RANGE),
        allow_negative_numbers = true
    )]
    pub half_width: Option<usize>,
}

/// Arguments of `diagnose`.
#[derive(Clone, Debug, Args)]
pub struct DiagnoseArgs {
    /// The measurement (see above).
    #[arg(value_name = "DATA")]
    pub data: PathBuf,
    /// Start model (TOML, lab/README.md, "Input files").
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// Write the JSON report to FILE (`-`: to standard output, instead of
    /// the text report; so for each output below).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Residual before/after over time and against each localising signal.
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// Write the fitted model (TOML).
    #[arg(long, value_name = "FILE")]
    pub model_out: Option<PathBuf>,
    /// Only these catalogue effects, a comma list of: viscous,
    /// nonlinear_viscous, offset, asymmetry, position_ripple, dwell_stiction,
    /// frictional_lag, drift, stribeck, presliding.
    #[arg(long, value_name = "LIST", value_parser = parse_candidates)]
    pub candidates: Option<::std::vec::Vec<Effect>>,
    /// `--window K`.
    #[command(flatten)]
    pub window: WindowArg,
}

/// Arguments of `fit`.
#[derive(Clone, Debug, Args)]
pub struct FitArgs {
    /// The measurement.
    #[arg(value_name = "DATA")]
    pub data: PathBuf,
    /// Start model and structure (TOML; default: the base model identified
    /// from the data).
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// Write the fitted model (TOML; `-`: to standard output, instead of
    /// the report).
    #[arg(long, value_name = "FILE")]
    pub model_out: Option<PathBuf>,
    /// JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// `--window K`.
    #[command(flatten)]
    pub window: WindowArg,
}

/// Arguments of `validate`.
#[derive(Clone, Debug, Args)]
pub struct ValidateArgs {
    /// The measurement.
    #[arg(value_name = "DATA")]
    pub data: PathBuf,
    /// The fixed model (TOML, lab/README.md, "Input files").
    #[arg(long, value_name = "FILE")]
    pub model: PathBuf,
    /// JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Give no weight to the samples within the kernel of a burst (stick-slip
    /// faster than the sampling), as the second pass of `diagnose` does.
    #[arg(long)]
    pub unweigh_bursts: bool,
    /// `--window K`.
    #[command(flatten)]
    pub window: WindowArg,
}

/// Arguments of `synth`.
#[derive(Clone, Debug, Args)]
pub struct SynthArgs {
    /// Hidden effects (viscous, nonlinear_viscous, offset, asymmetry,
    /// position_ripple, dwell_stiction, frictional_lag, drift; comma list)
    /// or none.
    #[arg(
        long = "effect",
        value_name = "LIST",
        default_value = "none",
        value_parser = synth::parse_hidden
    )]
    pub effects: ::std::vec::Vec<Effect>,
    /// Seed of every random choice.
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1,
        allow_negative_numbers = true
    )]
    pub seed: u64,
    /// Noise level: low or high.
    #[arg(long, value_name = "L", default_value = "low", value_parser = parse_noise)]
    pub noise: Noise,
    /// Base parameter set, 0 or 1.
    #[arg(
        long,
        value_name = "N",
        default_value_t = 0,
        value_parser = RangedU64ValueParser::<usize>::new().range(0..=1),
        allow_negative_numbers = true
    )]
    pub set: usize,
    /// The CSV to write (`-`: standard output, instead of the message).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Also write the truth model (TOML; `-` as for the CSV).
    #[arg(long, value_name = "FILE")]
    pub truth: Option<PathBuf>,
}

/// Arguments of `static-curve`.
#[derive(Clone, Debug, Args)]
pub struct StaticCurveArgs {
    /// The steady-state friction file (Indy7 layout).
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// Also write the points and the fitted curves, torque against velocity,
    /// as an SVG plot (`-`: to standard output, instead of the report).
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
}

/// Parses `--wb`: a number in (0, 1).
fn parse_wb(s: &str) -> Result<f64, String> {
    let w: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number"))?;
    if w > 0.0 && w < 1.0 {
        Ok(w)
    } else {
        Err(format!("{s} is outside (0, 1)"))
    }
}

/// Parses `--variant`: `all` or a comma list of variant names (repeats
/// count once).
pub fn parse_variants(s: &str) -> Result<Vec<Variant>, String> {
    if s.trim() == "all" {
        return Ok(Variant::ALL.to_vec());
    }
    let mut out = Vec::new();
    for item in s.split(',').map(str::trim) {
        let v = Variant::parse(item).ok_or_else(|| {
            format!(
                "unknown variant `{item}` (expected coulomb, stiction, mean, consistent or all)"
            )
        })?;
        if !out.contains(&v) {
            out.push(v);
        }
    }
    Ok(out)
}

/// Parses `--candidates`: a comma list of catalogue names ([`Effect::name`]).
pub fn parse_candidates(s: &str) -> Result<Vec<Effect>, String> {
    s.split(',')
        .map(|c| c.trim().parse::<Effect>().map_err(|e| e.to_string()))
        .collect()
}

/// Parses `--noise`: `low` or `high`.
fn parse_noise(s: &str) -> Result<Noise, String> {
    Noise::parse(s).ok_or_else(|| format!("`{s}` is not low or high"))
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
/// names the offending item.
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

/// Parses the command line `args` (without the program name). A parse
/// error, `--help` included, is clap's.
pub fn parse(args: &[String]) -> Result<Cli, clap::Error> {
    Cli::try_parse_from(std::iter::once("breakaway-lab").chain(args.iter().map(String::as_str)))
}

/// A clap error (other than `--help`) as one line: its message without
/// the usage and the pointer to `--help` that follow it.
pub fn one_line_error(e: &clap::Error) -> String {
    let text = e.to_string();
    let mut line = String::new();
    for l in text
        .lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .filter(|l| !l.is_empty())
    {
        let l = l.strip_prefix("error: ").unwrap_or(l);
        if !line.is_empty() {
            line.push_str(if line.ends_with(':') { " " } else { "; " });
        }
        line.push_str(l);
    }
    line
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
        let Command::Breakaway(a) = c.command else {
            panic!()
        };
        assert_eq!(a.k, vec![1.0, 2.0]);
        assert_eq!(a.variants, Variant::ALL.to_vec());
        assert_eq!(a.boundary.w_b, 0.95);
        assert!(!a.dynamic);
        assert_eq!(a.output.format(), Format::Table);
        let c = parse(&argv(
            "breakaway --json --k=3 --variant consistent,mean --wb=0.9 --dynamic --model=m.toml",
        ))
        .unwrap();
        let Command::Breakaway(a) = c.command else {
            panic!()
        };
        assert_eq!(a.variants, vec![Variant::Consistent, Variant::Mean]);
        assert_eq!(
            (a.boundary.w_b, a.dynamic, a.output.format()),
            (0.9, true, Format::Json)
        );
        let c = parse(&argv("validity-map --model m.toml")).unwrap();
        let Command::ValidityMap(a) = c.command else {
            panic!()
        };
        assert_eq!(a.masses, vec![0.1, 1.0, 10.0]);
        assert_eq!(a.k.len(), 8);
        assert_eq!(a.variants, vec![Variant::Mean, Variant::Consistent]);
        let help = parse(&argv("breakaway --help")).unwrap_err();
        assert_eq!(help.kind(), clap::error::ErrorKind::DisplayHelp);
    }

    #[test]
    fn workflow_commands() {
        let c = parse(&argv("diagnose d.csv --candidates offset,drift --window 7")).unwrap();
        let Command::Diagnose(a) = c.command else {
            panic!()
        };
        assert_eq!(a.candidates, Some(vec![Effect::Offset, Effect::Drift]));
        assert_eq!(a.window.half_width, Some(7));
        assert_eq!(a.json, None);
        let c = parse(&argv("synth --out s.csv --effect drift,offset,drift")).unwrap();
        let Command::Synth(a) = c.command else {
            panic!()
        };
        assert_eq!(a.effects, vec![Effect::Drift, Effect::Offset]);
        assert_eq!((a.seed, a.noise, a.set), (1, Noise::Low, 0));
        let c = parse(&argv(
            "synth --out s.csv --effect none --noise high --set 1",
        ))
        .unwrap();
        let Command::Synth(a) = c.command else {
            panic!()
        };
        assert!(a.effects.is_empty());
        assert_eq!((a.noise, a.set), (Noise::High, 1));
    }

    #[test]
    fn bad_commands_name_the_argument() {
        for (line, needle) in [
            ("", "subcommand"),
            ("simulate --model m", "simulate"),
            ("breakaway --k 1", "--model"),
            ("breakaway --model m.toml", "--k"),
            ("breakaway --model m.toml --k", "--k"),
            ("breakaway --model m.toml --k 0", "--k"),
            ("breakaway --model m.toml --k -1", "--k"),
            ("breakaway --model m.toml --k 1 --k 2", "--k"),
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
            ("diagnose d.csv --candidates offset,viscus", "viscus"),
            ("diagnose d.csv --window 1", "--window"),
            ("diagnose d.csv --window 65", "--window"),
            ("diagnose", "DATA"),
            ("fit d.csv e.csv", "e.csv"),
            ("validate d.csv", "--model"),
            ("synth --out s.csv --effect stribeck", "stribeck"),
            ("synth --out s.csv --noise loud", "loud"),
            ("synth --out s.csv --set 2", "--set"),
            ("synth --out s.csv --seed -1", "--seed"),
            ("synth --out s.csv --set -1", "--set"),
            ("diagnose d.csv --window -3", "--window"),
            ("breakaway --model m.toml --k 1 --wb -0.5", "--wb"),
            ("synth --effect offset", "--out"),
            ("static-curve f.csv --window 5", "--window"),
            ("closed-loop --svg", "--svg"),
            ("closed-loop --force-noise -1", "--force-noise"),
            ("closed-loop --observer-bandwidth 0", "--observer-bandwidth"),
            (
                "closed-loop --velocity-bandwidth nan",
                "--velocity-bandwidth",
            ),
        ] {
            let e = parse(&argv(line)).unwrap_err();
            assert_eq!(e.exit_code(), 2, "{line}");
            let msg = one_line_error(&e);
            assert!(msg.contains(needle), "`{line}` -> `{msg}`");
            assert!(!msg.contains('\n'));
        }
    }

    /// Every `--help` text (the tool's and each sub-command's) points only
    /// to what the repository holds: no spec file outside it, no internal
    /// issue numbers; and `--candidates` lists the whole catalogue.
    #[test]
    fn help_texts_point_inside_the_repository() {
        use clap::CommandFactory;
        let mut cli = Cli::command();
        cli.build();
        let mut texts = vec![(
            "breakaway-lab".to_string(),
            cli.render_long_help().to_string(),
        )];
        for sub in cli.get_subcommands_mut() {
            texts.push((
                sub.get_name().to_string(),
                sub.render_long_help().to_string(),
            ));
        }
        assert_eq!(texts.len(), 9);
        for (name, text) in &texts {
            assert!(!text.contains("MODEL.md"), "{name} --help cites MODEL.md");
            assert!(
                !text.contains("DIAGNOSE.md"),
                "{name} --help cites DIAGNOSE.md"
            );
            let issue = text
                .match_indices('#')
                .any(|(i, _)| text[i + 1..].starts_with(|c: char| c.is_ascii_digit()));
            assert!(!issue, "{name} --help names an issue number");
        }
        let (_, diagnose) = texts.iter().find(|(n, _)| n == "diagnose").unwrap();
        for effect in Effect::ALL {
            assert!(diagnose.contains(effect.name()), "{effect} missing");
        }
    }
}
