//! The sub-commands of the discrepancy workflow: `synth`, `fit`,
//! `validate`, `diagnose` and `static-curve` (arguments parsed by
//! [`crate::cli`]). Errors are one line naming the file at fault.

use crate::cli::{DiagnoseArgs, FitArgs, StaticCurveArgs, SynthArgs, ValidateArgs, WindowArg};
use crate::data::{self, Record};
use crate::diagnose::{self, Options};
use crate::fit::{self, FitOptions};
use crate::progress::Progress;
use crate::reference::Model;
use crate::residual::{self, Prepared, Window};
use crate::synth::{self, SynthSpec};
use crate::{emit, Error};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Loads a model file for the workflow (`z_max = 0` allowed: a model without
/// presliding). The error names the file (the reference's message starts
/// with it).
pub fn load_model(path: &Path) -> Result<Model, Error> {
    Model::load(path).map_err(|e| Error::Runtime(e.to_string()))
}

/// Whether the output path is `-`: standard output, where the output is
/// written in place of the command's text report (`diagnose DATA --json -
/// | jq …`).
fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Whether `output` is `-` ([`is_stdout`]); refused beside a flag
/// (`json`, the `--json` of `fit`, `static-curve` and `closed-loop`) that
/// prints to standard output already.
pub(crate) fn stdout_beside_flag(
    output: Option<&Path>,
    option: &str,
    json: bool,
) -> Result<bool, Error> {
    let to_stdout = output.is_some_and(is_stdout);
    if to_stdout && json {
        return Err(Error::Usage(format!(
            "`{option} -` and `--json` both print to standard output: give one"
        )));
    }
    Ok(to_stdout)
}

/// Whether one of a run's outputs is `-` ([`is_stdout`]); two are refused
/// (standard output would hold both, one after the other).
fn stdout_output(outputs: &[&Path]) -> Result<bool, Error> {
    match outputs.iter().filter(|o| is_stdout(o)).count() {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(Error::Usage(
            "`-` (standard output) given to two outputs of one run".into(),
        )),
    }
}

/// Writes the model file of `m` (MODEL.md §7) to `path` ([`write_file`]),
/// the comment lines `header` first.
fn save_model(path: &Path, m: &Model, header: &str, out: &mut dyn Write) -> Result<(), Error> {
    m.validate().map_err(|e| {
        let name = if is_stdout(path) {
            "standard output".into()
        } else {
            path.display().to_string()
        };
        Error::Runtime(format!("{name}: {e}"))
    })?;
    write_file(path, &format!("{header}{}", m.to_toml_string()), out)
}

pub(crate) fn write_file(path: &Path, text: &str, out: &mut dyn Write) -> Result<(), Error> {
    if is_stdout(path) {
        return emit(out, text);
    }
    std::fs::write(path, text)
        .map_err(|e| Error::Runtime(format!("{}: cannot write: {e}", path.display())))
}

/// Whether `a` and `b` name one file: the same path once the directory is
/// resolved (for a file not written yet), or, on Unix, the same device and
/// inode (a hard or symbolic link to it).
fn same_file(a: &Path, b: &Path) -> bool {
    let resolved = |p: &Path| -> Option<PathBuf> {
        let dir = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        Some(std::fs::canonicalize(dir).ok()?.join(p.file_name()?))
    };
    if resolved(a).is_some_and(|x| resolved(b) == Some(x)) {
        return true;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    false
}

/// Refuses, before any work, an output that would write over an input file
/// or that goes to a directory that does not exist (found only after the
/// analysis, that would lose its result).
pub(crate) fn not_input(out: &Path, inputs: &[&Path]) -> Result<(), Error> {
    if is_stdout(out) {
        return Ok(());
    }
    if inputs.iter().any(|i| same_file(out, i)) {
        return Err(Error::Usage(format!(
            "{}: refusing to overwrite an input file",
            out.display()
        )));
    }
    output_dir(out)
}

/// The directory an output goes to exists.
fn output_dir(out: &Path) -> Result<(), Error> {
    let dir = out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let problem = if dir.is_dir() {
        return Ok(());
    } else if dir.exists() {
        "is not a directory"
    } else {
        "does not exist"
    };
    Err(Error::Usage(format!(
        "{}: the directory {} {problem}",
        out.display(),
        dir.display()
    )))
}

/// Refuses two outputs of one run that name the same file: the second
/// would replace the first. Returns whether one of them is `-`
/// ([`stdout_output`]).
fn distinct_outputs(outputs: &[&Path]) -> Result<bool, Error> {
    let to_stdout = stdout_output(outputs)?;
    let files: Vec<&&Path> = outputs.iter().filter(|o| !is_stdout(o)).collect();
    let outputs = files.as_slice();
    for (k, a) in outputs.iter().enumerate() {
        if let Some(b) = outputs[k + 1..].iter().find(|b| same_file(a, b)) {
            return Err(Error::Usage(format!(
                "{} and {}: two outputs of one run name the same file",
                a.display(),
                b.display()
            )));
        }
    }
    Ok(to_stdout)
}

fn load_data(path: &Path, window: Option<usize>) -> Result<(Record, Window), Error> {
    if crate::steady::is_steady(path) {
        return Err(Error::Usage(format!(
            "{}: a steady-state record (one force per speed): `fit` and `validate` take \
             time records (t, u, x); `diagnose` fits a steady-state curve, `static-curve` \
             an Indy7-layout file",
            path.display()
        )));
    }
    let rec = data::load(path)?;
    // Friction shows where the axis moves; a record whose position never
    // changes leaves the residual nothing to weigh (its rms 0/0).
    if !rec.x.windows(2).any(|w| w[0] != w[1]) {
        return Err(Error::Runtime(format!(
            "{}: the position never changes ({} samples at x = {}): there is no motion to compare a model with",
            path.display(),
            rec.len(),
            rec.x.first().copied().unwrap_or(0.0)
        )));
    }
    energy_in(&rec, path)?;
    if let Some(v) = &rec.v {
        measured_velocity(&rec.x, &rec.t, v, path)?;
    }
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
    let min_window = enough(window.unwrap_or(residual::DEFAULT_HALF_WIDTH))?;
    let window = match window {
        Some(k) => Window::both(k),
        None => {
            let w = residual::auto_window(&rec);
            let most = (rec.len().saturating_sub(20) / 20).max(min_window);
            Window {
                velocity: w.velocity.min(most),
                force: w.force.min(most),
            }
        }
    };
    enough(window.velocity.max(window.force))?;
    Ok((rec, window))
}

/// Friction takes energy from the axis, so the actuation force does
/// positive work over a record, `Σ u·Δx > 0`, but for the kinetic energy it
/// held at the start. A record whose force does mostly negative work has
/// `u` or `x` of the wrong sign (a model fitted to it runs `Fc` to zero and
/// names nothing): refused where the negative work is more than half of
/// all the work done, `Σ u·Δx < −½·Σ |u·Δx|`.
fn energy_in(rec: &Record, path: &Path) -> Result<(), Error> {
    let (mut work, mut total) = (0.0, 0.0);
    for (w, u) in rec.x.windows(2).zip(&rec.u) {
        let dw = u * (w[1] - w[0]);
        work += dw;
        total += dw.abs();
    }
    if work < -0.5 * total {
        return Err(Error::Runtime(format!(
            "{}: the force does negative work on the axis (Σ u·Δx = {} J of {} J in all): \
             friction cannot, so `u` or `x` has the wrong sign",
            path.display(),
            crate::format::short(work, 4),
            crate::format::short(total, 4)
        )));
    }
    Ok(())
}

/// Least correlation, and largest ratio either way of the scales, of a
/// record's `v` column against the position's differences
/// ([`measured_velocity`]).
const VELOCITY_MIN_CORRELATION: f64 = 0.5;
const VELOCITY_MAX_SCALE: f64 = 3.0;

/// The `v` column replaces the velocity differentiated from `x`
/// everywhere; it must be that velocity, measured: over a window of ±5
/// samples its least-squares scale against `(x_{i+5} − x_{i−5})/(t_{i+5} −
/// t_{i−5})` within a factor of [`VELOCITY_MAX_SCALE`] of 1, and their
/// correlation at least [`VELOCITY_MIN_CORRELATION`]. A column of zeros,
/// one in mm/s or of another axis is refused, not used.
fn measured_velocity(x: &[f64], t: &[f64], v: &[f64], path: &Path) -> Result<(), Error> {
    const K: usize = 5;
    let (mut vv, mut dd, mut vd) = (0.0, 0.0, 0.0);
    for i in K..x.len().saturating_sub(K) {
        let d = (x[i + K] - x[i - K]) / (t[i + K] - t[i - K]);
        vv += v[i] * v[i];
        dd += d * d;
        vd += v[i] * d;
    }
    let scale = vd / dd;
    let correlation = vd / (vv * dd).sqrt();
    let ok = correlation >= VELOCITY_MIN_CORRELATION
        && (1.0 / VELOCITY_MAX_SCALE..=VELOCITY_MAX_SCALE).contains(&scale);
    if ok {
        return Ok(());
    }
    Err(Error::Runtime(format!(
        "{}: column `v` is not the velocity of `x` [m/s]: against the differences of `x` \
         its scale is {scale:.3} and its correlation {correlation:.3} (needed: within a factor \
         of {VELOCITY_MAX_SCALE} of 1, and {VELOCITY_MIN_CORRELATION} at least); leave the \
         column out to have `x` differentiated",
        path.display()
    )))
}

/// Moving samples of `p` (not still: the position leaves its count
/// within the velocity window) on the blocks of `side` (`None`: all).
fn moving_on(p: &Prepared, side: Option<bool>) -> usize {
    p.valid()
        .filter(|&i| !p.still[i] && side.is_none_or(|s| p.held_out[i] == s))
        .count()
}

/// An error where none of the samples a figure is formed on moves
/// (`scored` of the record's `moving` ones): the residual weighs only
/// moving samples, and at rest the friction is the applied force, so a
/// record whose axis creeps by a count now and then (a force below the
/// stiction level throughout) holds no motion to compare a model with.
/// Named here, before the figures come out as 0/0.
fn no_motion(
    path: &Path,
    rec: &Record,
    resolution: f64,
    moving: usize,
    scored: usize,
) -> Result<(), Error> {
    if scored > 0 {
        return Ok(());
    }
    let (lo, hi) = rec
        .x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    Err(Error::Runtime(format!(
        "{}: the axis hardly moves: {moving} of {} samples move (the position leaves its \
         count within the velocity window), none where the figures are scored, and the \
         position spans {:.0} counts of {resolution:.3e}: at rest the friction is the applied \
         force, so there is no motion to compare a model with",
        path.display(),
        rec.len(),
        (hi - lo) / resolution,
    )))
}

/// An error naming the first of `figures` [N] that is not finite: a
/// residual that overflowed (forces or speeds near the `f64` range) or that
/// weighed nothing is not a figure to print as a result.
fn finite_figures(path: &Path, figures: &[(&str, f64)]) -> Result<(), Error> {
    match figures.iter().find(|(_, x)| !x.is_finite()) {
        Some((what, x)) => Err(Error::Runtime(format!(
            "{}: the {what} is {x}: the data's forces, positions or times are out of the range \
             the residual can be formed in",
            path.display()
        ))),
        None => Ok(()),
    }
}

/// `synth`: writes the record (and the truth model).
pub fn synth(args: SynthArgs, out: &mut dyn Write) -> Result<(), Error> {
    let SynthArgs {
        effects,
        seed,
        noise,
        set,
        out: path,
        truth,
    } = args;
    let spec = SynthSpec {
        effects,
        seed,
        noise,
        set,
    };
    let outputs: Vec<&Path> = [Some(&path), truth.as_ref()]
        .into_iter()
        .flatten()
        .map(PathBuf::as_path)
        .collect();
    let to_stdout = distinct_outputs(&outputs)?;
    for o in &outputs {
        not_input(o, &[])?;
    }
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
    write_file(&path, &data::csv_text(&rec, &comments), out)?;
    if let Some(t) = truth {
        save_model(&t, &model, "", out)?;
    }
    if to_stdout {
        return Ok(());
    }
    emit(
        out,
        &format!("{}: {} samples written\n", path.display(), rec.len()),
    )
}

/// `fit`: the parameters of the given model's structure (or the base
/// model's) on the data.
pub fn fit(args: FitArgs, out: &mut dyn Write) -> Result<(), Error> {
    let FitArgs {
        data,
        model,
        model_out,
        json,
        window: WindowArg { half_width: window },
    } = args;
    let (rec, window) = load_data(&data, window)?;
    let start = model.as_deref().map(load_model).transpose()?;
    let to_stdout = stdout_beside_flag(model_out.as_deref(), "--model-out", json)?;
    if let Some(o) = &model_out {
        let mut inputs = vec![data.as_path()];
        if let Some(m) = &model {
            inputs.push(m.as_path());
        }
        not_input(o, &inputs)?;
    }
    let mut progress = Progress::stderr();
    let mut p = Prepared::with_window(&rec, window);
    // The weights come from the data's base model whatever the start, as
    // in `validate` and `diagnose`: the figures of two fits of one record
    // (and `validate` of the fitted model) compare like with like.
    let base = diagnose::base_weights(&mut p, &mut |s| progress.show(s));
    let scored = moving_on(&p, Some(false)).min(moving_on(&p, Some(true)));
    no_motion(&data, &rec, p.resolution, moving_on(&p, None), scored)?;
    let m0 = start.unwrap_or(base);
    progress.show("fitting");
    let params = fit::params_of(&m0);
    let res = fit::fit(&p, &m0, &params, &FitOptions::default(), &mut |_| {});
    progress.finish();
    let r = p.residual(&res.model);
    let (train, held) = (p.rms(&r, Some(false)), p.rms(&r, Some(true)));
    finite_figures(&data, &[("training rms", train), ("held-out rms", held)])?;
    let flags = fit_flags(&p, &res.model, &rec);
    if let Some(o) = &model_out {
        save_model(o, &res.model, "", out)?;
    }
    if to_stdout {
        return Ok(());
    }
    let text = if json {
        let v = serde_json::json!({
            "metric": "weighted RMS [N] of the force residual along the measured motion, on the training and on the held-out blocks (the residual, weights and blocks of diagnose; raw rms, not model error: diagnose and validate give the floor)",
            "rms_train": train,
            "rms_held_out": held,
            "effects": fit::effects_of(&res.model).iter().map(|e| e.name()).collect::<Vec<_>>(),
            "not_identified": flags,
            "model": diagnose::model_json(&res.model),
        });
        format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
    } else {
        let notes: String = flags
            .iter()
            .map(|f| format!("not identified here: {f}\n"))
            .collect();
        format!(
            "{}: fitted {} parameters ({} passes); rms train {} N, held-out {} N\n{notes}{}",
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

/// What of the fitted `m` the record `rec` did not identify: the parts and
/// effects `diagnose` would drop as degenerate ([`diagnose::degenerate`]),
/// a mass at its lower limit, a Coulomb level run to nothing. `fit` writes
/// the model as fitted and says so, rather than pass such values for the
/// axis's.
fn fit_flags(p: &Prepared, m: &Model, rec: &Record) -> Vec<String> {
    let mut flags: Vec<String> = fit::effects_of(m)
        .into_iter()
        .filter_map(|e| diagnose::degenerate(p, m, e).map(|why| format!("`{e}`: {why}")))
        .collect();
    if fit::mass_at_bound(m) {
        flags.push(format!(
            "the mass ran to its lower limit ({:e} kg)",
            fit::MASS_MIN
        ));
    }
    let largest_force = rec.u.iter().fold(0.0f64, |a, u| a.max(u.abs()));
    if m.fc < 1e-9 * largest_force {
        flags.push(format!(
            "Fc = {:.3e} N, nothing against forces up to {largest_force:.3e} N",
            m.fc
        ));
    }
    flags
}

/// `validate`: the metric of a fixed model on the data.
pub fn validate(args: ValidateArgs, out: &mut dyn Write) -> Result<(), Error> {
    let (rec, window) = load_data(&args.data, args.window.half_width)?;
    let m = load_model(&args.model)?;
    let mut p = Prepared::with_window(&rec, window);
    if args.unweigh_bursts {
        p.unweigh_bursts();
    }
    // The weights come from the data's base model, not from the
    // model under test: two models validated on one record are
    // compared with the same weights.
    let mut progress = Progress::stderr();
    diagnose::base_weights(&mut p, &mut |s| progress.show(s));
    progress.finish();
    let moving = moving_on(&p, None);
    no_motion(&args.data, &rec, p.resolution, moving, moving)?;
    let r = p.residual(&m);
    let all = p.rms(&r, None);
    let floor = p.floor(None);
    finite_figures(&args.data, &[("rms", all), ("measurement floor", floor)])?;
    let gap = residual::model_error(all, floor);
    let labels = diagnose::regimes(&p, &m);
    let stats = diagnose::regime_stats(&p, &r, &labels);
    let text = if args.json {
        let v = serde_json::json!({
            "metric": "weighted RMS [N] of the force residual along the measured motion over all samples (see diagnose)",
            "rms": all,
            "floor": floor,
            "model_error": gap,
            "bursts": {"samples": p.burst_count(), "unweighted": p.bursts_unweighted()},
            "regimes": stats.iter().map(|s| serde_json::json!({"regime": s.regime, "n": s.n, "rms": s.rms})).collect::<Vec<_>>(),
        });
        format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
    } else {
        let mut s = format!(
            "{} with {}: rms {} N (weighted, all samples); noise and resolution {} N (over all samples: diagnose's floor is over its held-out blocks); model error {} N\n",
            args.data.display(),
            args.model.display(),
            crate::format::short(all, 4),
            crate::format::short(floor, 4),
            crate::format::short(gap, 4)
        );
        let bursts = p.burst_count();
        if bursts > 0 {
            let how = if p.bursts_unweighted() {
                "not weighed (--unweigh-bursts)"
            } else {
                "weighed (--unweigh-bursts takes them out)"
            };
            s.push_str(&format!(
                "{bursts} moving samples lie within the kernel of a burst: {how}\n"
            ));
        }
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

/// `diagnose`: the discrepancy workflow on the data (steady-state records
/// included).
pub fn diagnose(args: DiagnoseArgs, out: &mut dyn Write) -> Result<(), Error> {
    let DiagnoseArgs {
        data,
        model,
        json,
        svg,
        model_out,
        candidates,
        window: WindowArg { half_width: window },
    } = args;
    let candidates = candidates.unwrap_or_default();
    let mut inputs = vec![data.as_path()];
    if let Some(m) = &model {
        inputs.push(m.as_path());
    }
    let outputs: Vec<&Path> = [&json, &svg, &model_out]
        .into_iter()
        .flatten()
        .map(PathBuf::as_path)
        .collect();
    for o in &outputs {
        not_input(o, &inputs)?;
    }
    let to_stdout = distinct_outputs(&outputs)?;
    if crate::steady::is_steady(&data) {
        // A steady-state record has no dynamics to window, no start model
        // to refine the same way and no time plot: an option given for them
        // is refused, not ignored.
        let given = [
            (model.is_some(), "--model"),
            (svg.is_some(), "--svg"),
            (window.is_some(), "--window"),
        ];
        if let Some((_, option)) = given.iter().find(|(on, _)| *on) {
            return Err(Error::Usage(format!(
                "{}: a steady-state record: `{option}` applies to time records only",
                data.display()
            )));
        }
        // Likewise an effect asked for that a curve cannot show.
        let steady = crate::steady::STEADY_CANDIDATES;
        if let Some(e) = candidates.iter().find(|e| !steady.contains(e)) {
            let shown: Vec<&str> = steady.iter().map(|e| e.name()).collect();
            return Err(Error::Usage(format!(
                "{}: a steady-state record: `{}` cannot show in it (--candidates from: {})",
                data.display(),
                e.name(),
                shown.join(", ")
            )));
        }
        let rec = crate::steady::read(&data)?;
        let rep = crate::steady::diagnose_steady(&rec, &candidates);
        if let Some(j) = &json {
            write_file(j, &crate::steady::report_json(&rep), out)?;
        }
        if let Some(m) = &model_out {
            let header = rep.units.model_header().unwrap_or_default();
            save_model(m, &rep.model, header, out)?;
        }
        if to_stdout {
            return Ok(());
        }
        return emit(
            out,
            &crate::steady::report_text(&rep, &data.display().to_string()),
        );
    }
    let (rec, window) = load_data(&data, window)?;
    let start = model.as_deref().map(load_model).transpose()?;
    let opts = Options { window, candidates };
    let mut progress = Progress::stderr();
    let rep = diagnose::diagnose(&rec, start.as_ref(), &opts, &mut progress);
    no_motion(&data, &rec, rep.resolution, rep.moving, rep.moving_held_out)?;
    finite_figures(
        &data,
        &[
            ("held-out rms before", rep.raw_before),
            ("held-out rms after", rep.raw_after),
            ("measurement floor", rep.floor),
        ],
    )?;
    if let Some(j) = &json {
        write_file(j, &diagnose::report_json(&rep), out)?;
    }
    if let Some(s) = &svg {
        write_file(s, &crate::svg::diagnose_svg(&rep), out)?;
    }
    if let Some(m) = &model_out {
        save_model(m, &rep.model, "", out)?;
    }
    if to_stdout {
        return Ok(());
    }
    emit(
        out,
        &diagnose::report_text(&rep, &data.display().to_string()),
    )
}

/// `static-curve`: the steady-state curve fit of an Indy7-layout file.
pub fn static_curve(args: StaticCurveArgs, out: &mut dyn Write) -> Result<(), Error> {
    let StaticCurveArgs { file, json, svg } = args;
    let to_stdout = stdout_beside_flag(svg.as_deref(), "--svg", json)?;
    let fitres = crate::static_curve::run(&file)?;
    if let Some(s) = &svg {
        not_input(s, &[file.as_path()])?;
        write_file(s, &crate::static_curve::svg(&fitres), out)?;
    }
    if to_stdout {
        return Ok(());
    }
    let text = if json {
        crate::static_curve::json(&fitres)
    } else {
        crate::static_curve::text(&fitres, &file.display().to_string())
    };
    emit(out, &text)
}
