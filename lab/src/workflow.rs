//! Command line of the discrepancy workflow: `synth`, `fit`, `validate`,
//! `diagnose` and `static-curve`. Parsing is hand-written like
//! [`crate::args`], every error one line naming the argument.

use crate::data::{self, Record};
use crate::diagnose::{self, Options};
use crate::fit::{self, FitOptions, Prepared};
use crate::progress::Progress;
use crate::reference::{Effect, Model};
use crate::synth::{self, Noise, SynthSpec};
use crate::{emit, Error};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The text of `--help` for these sub-commands.
pub const USAGE: &str = "\
breakaway-lab: the discrepancy workflow (manual: lab/README.md)

USAGE:
  breakaway-lab diagnose DATA [--model MODEL.toml] [--json REPORT.json] [--svg PLOT.svg]
                              [--model-out FITTED.toml] [--candidates LIST] [--window K]
  breakaway-lab fit DATA [--model MODEL.toml] [--model-out FITTED.toml] [--json] [--window K]
  breakaway-lab validate DATA --model MODEL.toml [--json] [--window K]
  breakaway-lab synth [--effect NAME[,NAME...]|none] [--seed S] [--noise low|high] [--set 0|1]
                      --out DATA.csv [--truth TRUTH.toml]
  breakaway-lab static-curve FILE [--json] [--svg PLOT.svg]

  diagnose      where model and data disagree (regimes, time windows, signals), which effect of
                MODEL.md §5 is missing (each candidate added, refitted, scored by BIC on held-out
                time blocks; accepted only if it also lowers the held-out rms by 5 %), repeated
                until none helps. Without --model it starts from the base model (Coulomb +
                Stribeck + presliding, σ = 0) identified from the data.
  fit           the parameters of a model structure (the given model's, or the base model)
  validate      the metric of a fixed model on other data (all samples, per regime)
  synth         synthetic measurements with hidden effects (closed-loop plateaus both ways,
                rests of varied length, force-ramp break-away tests, slow reversals; encoder
                quantisation and force noise)
  static-curve  Stribeck + viscous fit per direction of a steady-state friction file (Indy7 layout:
                `desired vel, real vel, tau` in deg/s and N·m)

DATA may also be a steady-state record (the Indy7 layout, or CSV columns v, u): diagnose then
fits the steady-state curve and tries the effects visible in it (viscous, nonlinear_viscous,
offset, asymmetry).
Reports give the gap as model error above the measurement floor (force noise and encoder
resolution); samples where the position stays within one count are the measured friction,
re-anchor the presliding memory and are not scored.

DATA: CSV with columns t, u, x (optional v), MODEL.md §6, or a .mat file in the EMPS layout.
The residual is the force along the measured motion (MODEL.md §8: compared locally).

OPTIONS:
  --model FILE       start / fixed model, TOML as in MODEL.md §7
  --model-out FILE   write the fitted model (TOML, MODEL.md §7)
  --json [FILE]      diagnose: write the JSON report to FILE; fit/validate/static-curve: JSON on stdout
  --svg FILE         residual before/after over time and against each localising signal
  --candidates LIST  diagnose: only these catalogue effects (comma list)
  --window K         Savitzky-Golay half-width in samples, 2..50 (default: chosen from the data)
  --effect LIST      synth: hidden effects (viscous, nonlinear_viscous, offset, asymmetry,
                     position_ripple, dwell_stiction, frictional_lag, drift) or none (default none)
  --seed S           synth: seed (default 1)
  --noise L          synth: low or high (default low)
  --set N            synth: base parameter set 0 or 1 (default 0)
  --out FILE         synth: the CSV to write
  --truth FILE       synth: also write the truth model
";

/// A parsed command of this module.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// `--help`.
    Help,
    /// `diagnose`.
    Diagnose {
        /// Data file.
        data: PathBuf,
        /// Start model.
        model: Option<PathBuf>,
        /// JSON report file.
        json: Option<PathBuf>,
        /// SVG plot.
        svg: Option<PathBuf>,
        /// Fitted model output.
        model_out: Option<PathBuf>,
        /// Candidate filter.
        candidates: Vec<Effect>,
        /// SG half-width (`None`: chosen from the data, [`fit::auto_window`]).
        window: Option<usize>,
    },
    /// `fit`.
    Fit {
        /// Data file.
        data: PathBuf,
        /// Structure / start.
        model: Option<PathBuf>,
        /// Output model.
        model_out: Option<PathBuf>,
        /// JSON on stdout.
        json: bool,
        /// SG half-width (`None`: chosen from the data, [`fit::auto_window`]).
        window: Option<usize>,
    },
    /// `validate`.
    Validate {
        /// Data file.
        data: PathBuf,
        /// Fixed model.
        model: PathBuf,
        /// JSON on stdout.
        json: bool,
        /// SG half-width (`None`: chosen from the data, [`fit::auto_window`]).
        window: Option<usize>,
    },
    /// `synth`.
    Synth {
        /// What to generate.
        spec: SynthSpec,
        /// CSV output.
        out: PathBuf,
        /// Truth model output.
        truth: Option<PathBuf>,
    },
    /// `static-curve`.
    StaticCurve {
        /// Indy7-layout file.
        file: PathBuf,
        /// JSON on stdout.
        json: bool,
        /// SVG plot.
        svg: Option<PathBuf>,
    },
}

const SUBS: [&str; 5] = ["diagnose", "fit", "validate", "synth", "static-curve"];

fn usage(msg: impl Into<String>) -> Error {
    Error::Usage(msg.into())
}

/// Runs `args` if its sub-command belongs to this module; `None` otherwise.
pub fn dispatch(args: &[String], out: &mut dyn Write) -> Option<Result<(), Error>> {
    let sub = args.first()?;
    if !SUBS.contains(&sub.as_str()) {
        return None;
    }
    Some(parse(args).and_then(|c| run(c, out)))
}

/// Parses a command line whose first word is one of this module's
/// sub-commands.
pub fn parse(args: &[String]) -> Result<Command, Error> {
    if args.iter().any(|a| a == "-h" || a == "--help") {
        return Ok(Command::Help);
    }
    let Some((sub, rest)) = args.split_first() else {
        return Err(usage("missing sub-command"));
    };
    let sub = sub.as_str();
    let mut positional: Vec<String> = Vec::new();
    let mut opts: Vec<(String, Option<String>)> = Vec::new();
    let takes_value = |name: &str| -> bool {
        match name {
            "--model" | "--model-out" | "--svg" | "--candidates" | "--window" | "--effect"
            | "--seed" | "--noise" | "--set" | "--out" | "--truth" => true,
            // diagnose writes the report to a file; the others print JSON.
            "--json" => sub == "diagnose",
            _ => false,
        }
    };
    let known: &[&str] = match sub {
        "diagnose" => &[
            "--model",
            "--json",
            "--svg",
            "--model-out",
            "--candidates",
            "--window",
        ],
        "fit" => &["--model", "--model-out", "--json", "--window"],
        "validate" => &["--model", "--json", "--window"],
        "synth" => &["--effect", "--seed", "--noise", "--set", "--out", "--truth"],
        _ => &["--json", "--svg"],
    };
    let mut it = rest.iter();
    while let Some(arg) = it.next() {
        if !arg.starts_with("--") {
            positional.push(arg.clone());
            continue;
        }
        let (name, inline) = match arg.split_once('=') {
            Some((n, v)) => (n.to_string(), Some(v.to_string())),
            None => (arg.clone(), None),
        };
        if !known.contains(&name.as_str()) {
            return Err(usage(format!("{sub}: unknown option `{name}`; see --help")));
        }
        if opts.iter().any(|(n, _)| *n == name) {
            return Err(usage(format!("{name} given twice")));
        }
        let value = if takes_value(&name) {
            let v = match inline {
                Some(v) => v,
                None => it
                    .next()
                    .cloned()
                    .ok_or_else(|| usage(format!("{name}: missing value")))?,
            };
            if v.is_empty() {
                return Err(usage(format!("{name}: empty value")));
            }
            Some(v)
        } else {
            if inline.is_some() {
                return Err(usage(format!("{name} takes no value")));
            }
            None
        };
        opts.push((name, value));
    }
    let get = |name: &str| -> Option<String> {
        opts.iter()
            .find(|(n, _)| n == name)
            .and_then(|(_, v)| v.clone())
    };
    let flag = |name: &str| opts.iter().any(|(n, _)| n == name);
    let path = |name: &str| get(name).map(PathBuf::from);
    let window = match get("--window") {
        None => None,
        Some(s) => match s.parse::<usize>() {
            Ok(k) if (2..=50).contains(&k) => Some(k),
            _ => return Err(usage(format!("--window: `{s}` is not an integer in 2..50"))),
        },
    };
    let one_data = |positional: &[String]| -> Result<PathBuf, Error> {
        match positional {
            [d] => Ok(PathBuf::from(d)),
            [] => Err(usage(format!("{sub}: missing DATA file; see --help"))),
            [_, extra, ..] => Err(usage(format!("unexpected argument `{extra}`; see --help"))),
        }
    };
    match sub {
        "diagnose" => {
            let candidates: Vec<Effect> = match get("--candidates") {
                None => Vec::new(),
                Some(s) => s
                    .split(',')
                    .map(|c| c.trim().parse::<Effect>())
                    .collect::<Result<_, _>>()
                    .map_err(|e| usage(format!("--candidates: {e}")))?,
            };
            Ok(Command::Diagnose {
                data: one_data(&positional)?,
                model: path("--model"),
                json: path("--json"),
                svg: path("--svg"),
                model_out: path("--model-out"),
                candidates,
                window,
            })
        }
        "fit" => Ok(Command::Fit {
            data: one_data(&positional)?,
            model: path("--model"),
            model_out: path("--model-out"),
            json: flag("--json"),
            window,
        }),
        "validate" => Ok(Command::Validate {
            data: one_data(&positional)?,
            model: path("--model").ok_or_else(|| usage("validate: missing --model FILE"))?,
            json: flag("--json"),
            window,
        }),
        "synth" => {
            if let Some(p) = positional.first() {
                return Err(usage(format!("unexpected argument `{p}`; see --help")));
            }
            let effects = match get("--effect") {
                None => Vec::new(),
                Some(s) => synth::parse_hidden(&s).map_err(|e| usage(format!("--effect: {e}")))?,
            };
            let seed = match get("--seed") {
                None => 1,
                Some(s) => s
                    .parse::<u64>()
                    .map_err(|_| usage(format!("--seed: `{s}` is not a non-negative integer")))?,
            };
            let noise = match get("--noise") {
                None => Noise::Low,
                Some(s) => Noise::parse(&s)
                    .ok_or_else(|| usage(format!("--noise: `{s}` is not low or high")))?,
            };
            let set = match get("--set").as_deref() {
                None | Some("0") => 0,
                Some("1") => 1,
                Some(s) => return Err(usage(format!("--set: `{s}` is not 0 or 1"))),
            };
            Ok(Command::Synth {
                spec: SynthSpec {
                    effects,
                    seed,
                    noise,
                    set,
                },
                out: path("--out").ok_or_else(|| usage("synth: missing --out FILE"))?,
                truth: path("--truth"),
            })
        }
        _ => Ok(Command::StaticCurve {
            file: one_data(&positional)?,
            json: flag("--json"),
            svg: path("--svg"),
        }),
    }
}

/// Loads a model file for the workflow (`z_max = 0` allowed: a model without
/// presliding). The error names the file.
pub fn load_model(path: &Path) -> Result<Model, Error> {
    Model::load(path).map_err(|e| {
        let msg = e.to_string();
        let shown = path.display().to_string();
        if msg.contains(&shown) {
            Error::Runtime(msg)
        } else {
            Error::Runtime(format!("{shown}: {msg}"))
        }
    })
}

fn save_model(path: &Path, m: &Model) -> Result<(), Error> {
    m.save(path)
        .map_err(|e| Error::Runtime(format!("{}: {e}", path.display())))
}

fn write_file(path: &Path, text: &str) -> Result<(), Error> {
    std::fs::write(path, text)
        .map_err(|e| Error::Runtime(format!("{}: cannot write: {e}", path.display())))
}

/// Refuses to write over an input file.
fn not_input(out: &Path, inputs: &[&Path]) -> Result<(), Error> {
    let canon = |p: &Path| std::fs::canonicalize(p).ok();
    if let Some(o) = canon(out) {
        if inputs.iter().any(|i| canon(i).as_ref() == Some(&o)) {
            return Err(Error::Usage(format!(
                "{}: refusing to overwrite an input file",
                out.display()
            )));
        }
    }
    Ok(())
}

fn load_data(path: &Path, window: Option<usize>) -> Result<(Record, usize), Error> {
    let rec = data::load(path)?;
    let enough = |k: usize| {
        if rec.len() < 20 * k + 20 {
            Err(Error::Runtime(format!(
                "{}: too few samples: {} for a window of {k} (need at least {})",
                path.display(),
                rec.len(),
                20 * k + 20
            )))
        } else {
            Ok(k)
        }
    };
    let min_window = enough(window.unwrap_or(fit::DEFAULT_HALF_WIDTH))?;
    let window = window.unwrap_or_else(|| {
        fit::auto_window(&rec).min((rec.len().saturating_sub(20) / 20).max(min_window))
    });
    enough(window)?;
    Ok((rec, window))
}

/// Runs a parsed command.
pub fn run(cmd: Command, out: &mut dyn Write) -> Result<(), Error> {
    match cmd {
        Command::Help => emit(out, USAGE),
        Command::Synth {
            spec,
            out: path,
            truth,
        } => {
            let (rec, model) = synth::generate(&spec)?;
            let comments = vec![
                format!(
                    "breakaway-lab synth --effect {} --seed {} --noise {} --set {}",
                    if spec.effects.is_empty() {
                        "none".to_string()
                    } else {
                        let names: Vec<&str> = spec.effects.iter().map(|e| e.name()).collect();
                        names.join(",")
                    },
                    spec.seed,
                    spec.noise.name(),
                    spec.set
                ),
                "columns: t [s], u [N] (held to the next sample), x [m] (encoder counts)".into(),
            ];
            data::write_csv(&path, &rec, &comments)?;
            if let Some(t) = truth {
                save_model(&t, &model)?;
            }
            emit(
                out,
                &format!("{}: {} samples written\n", path.display(), rec.len()),
            )
        }
        Command::Fit {
            data,
            model,
            model_out,
            json,
            window,
        } => {
            let (rec, window) = load_data(&data, window)?;
            let start = model.as_deref().map(load_model).transpose()?;
            if let Some(o) = &model_out {
                let mut inputs = vec![data.as_path()];
                if let Some(m) = &model {
                    inputs.push(m.as_path());
                }
                not_input(o, &inputs)?;
            }
            let mut progress = Progress::stderr();
            let mut p = Prepared::new(&rec, window);
            let m0 = match &start {
                Some(m) => m.clone(),
                None => diagnose::initial_base(&p, &mut |s| progress.show(s)),
            };
            let r0 = p.residual(&m0);
            p.set_error_weights(&m0, &r0);
            progress.show("fitting");
            let params = fit::params_of(&m0);
            let res = fit::fit(&p, &m0, &params, &FitOptions::default(), &mut |_| {});
            progress.finish();
            let r = p.residual(&res.model);
            let (train, held) = (p.rms(&r, Some(false)), p.rms(&r, Some(true)));
            if let Some(o) = &model_out {
                save_model(o, &res.model)?;
            }
            let text = if json {
                let v = serde_json::json!({
                    "metric": diagnose::METRIC,
                    "rms_train": train,
                    "rms_held_out": held,
                    "effects": fit::effects_of(&res.model).iter().map(|e| e.name()).collect::<Vec<_>>(),
                    "model": diagnose::model_json(&res.model),
                });
                format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
            } else {
                format!(
                    "{}: fitted {} parameters ({} passes); rms train {} N, held-out {} N\n{}",
                    data.display(),
                    params.len(),
                    res.passes,
                    crate::format::short(train, 4),
                    crate::format::short(held, 4),
                    res.model.to_toml_string()
                )
            };
            emit(out, &text)
        }
        Command::Validate {
            data,
            model,
            json,
            window,
        } => {
            let (rec, window) = load_data(&data, window)?;
            let m = load_model(&model)?;
            let mut p = Prepared::new(&rec, window);
            // The weights come from the data's base model, not from the
            // model under test: two models validated on one record are
            // compared with the same weights.
            let mut progress = Progress::stderr();
            diagnose::base_weights(&mut p, &mut |s| progress.show(s));
            progress.finish();
            let r = p.residual(&m);
            let all = p.rms(&r, None);
            let floor = p.floor(None);
            let gap = fit::model_error(all, floor);
            let labels = diagnose::regimes(&p, &m);
            let stats = diagnose::regime_stats(&p, &r, &labels);
            let text = if json {
                let v = serde_json::json!({
                    "metric": "weighted RMS [N] of the force residual along the measured motion over all samples (see diagnose)",
                    "rms": all,
                    "floor": floor,
                    "model_error": gap,
                    "regimes": stats.iter().map(|s| serde_json::json!({"regime": s.regime, "n": s.n, "rms": s.rms})).collect::<Vec<_>>(),
                });
                format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
            } else {
                let mut s = format!(
                    "{} with {}: rms {} N (weighted, all samples); noise and resolution {} N; model error {} N\n",
                    data.display(),
                    model.display(),
                    crate::format::short(all, 4),
                    crate::format::short(floor, 4),
                    crate::format::short(gap, 4)
                );
                let rows: Vec<Vec<String>> = stats
                    .iter()
                    .map(|s| {
                        vec![
                            s.regime.clone(),
                            s.n.to_string(),
                            crate::format::short(s.rms, 4),
                        ]
                    })
                    .collect();
                s.push_str(&crate::format::table(
                    &["regime", "samples", "rms [N]"],
                    &rows,
                ));
                s
            };
            emit(out, &text)
        }
        Command::Diagnose {
            data,
            model,
            json,
            svg,
            model_out,
            candidates,
            window,
        } => {
            let mut inputs = vec![data.as_path()];
            if let Some(m) = &model {
                inputs.push(m.as_path());
            }
            for o in [&json, &svg, &model_out].into_iter().flatten() {
                not_input(o, &inputs)?;
            }
            if crate::steady::is_steady(&data) {
                let rec = crate::steady::SteadyRecord::new(crate::steady::read(&data)?);
                let rep = crate::steady::diagnose_steady(&rec);
                if let Some(j) = &json {
                    write_file(j, &crate::steady::report_json(&rep))?;
                }
                if let Some(m) = &model_out {
                    save_model(m, &rep.model)?;
                }
                return emit(
                    out,
                    &crate::steady::report_text(&rep, &data.display().to_string()),
                );
            }
            let (rec, window) = load_data(&data, window)?;
            let start = model.as_deref().map(load_model).transpose()?;
            let opts = Options {
                half_width: window,
                candidates,
            };
            let mut progress = Progress::stderr();
            let rep = diagnose::diagnose(&rec, start.as_ref(), &opts, &mut progress);
            if let Some(j) = &json {
                write_file(j, &diagnose::report_json(&rep))?;
            }
            if let Some(s) = &svg {
                write_file(s, &crate::svg::diagnose_svg(&rep))?;
            }
            if let Some(m) = &model_out {
                save_model(m, &rep.model)?;
            }
            emit(
                out,
                &diagnose::report_text(&rep, &data.display().to_string()),
            )
        }
        Command::StaticCurve { file, json, svg } => {
            let fitres = crate::static_curve::run(&file)?;
            if let Some(s) = &svg {
                not_input(s, &[file.as_path()])?;
                write_file(s, &crate::static_curve::svg(&fitres))?;
            }
            let text = if json {
                crate::static_curve::json(&fitres)
            } else {
                crate::static_curve::text(&fitres, &file.display().to_string())
            };
            emit(out, &text)
        }
    }
}
