//! `cargo xtask sweep`: the discrepancy workflow scored on records from the
//! independent generator (`breakaway-gen`, which shares no code with the
//! fitter).
//!
//! For each seed the generator writes `DIR/<name>/data.csv`, `truth.json`
//! (hidden effects, visibility = effect RMS / noise std, `accept_extra`);
//! `breakaway-lab diagnose data.csv --json report.json` names effects. A
//! record is **named exactly** when the named set equals the hidden set
//! plus any subset of `accept_extra` (names a correct diagnosis of a plant
//! outside MODEL.md may add, such as `frictional_lag` for LuGre); with
//! hidden effects it **halves the gap** when also
//! `rms_after <= 0.5·rms_before`. A record without hidden effects that names
//! one is a false positive. The scoring rule is fixed here, before any
//! sweep is run; the workflow's thresholds live in `breakaway-lab` and are
//! not tuned on a sweep's seeds.

use crate::{cargo, root, run};
use indicatif::{ProgressBar, ProgressStyle};
use serde::de::DeserializeOwned;
use serde::Deserialize;
use serde_json::{json, Value};
use std::collections::HashMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Options of `cargo xtask sweep`.
#[derive(Clone, Debug)]
pub struct Options {
    /// First seed.
    pub from: u64,
    /// One past the last seed.
    pub to: u64,
    /// Record kind for the generator (`model`, `outside`, `mixed`).
    pub kind: String,
    /// Where the records and reports go.
    pub out: PathBuf,
    /// Where the JSON summary goes (also printed).
    pub json: Option<PathBuf>,
}

impl Options {
    /// Parses `--seeds A..B --kind K --out DIR --json FILE`.
    pub fn parse(args: &[String]) -> Result<Options, String> {
        let mut o = Options {
            from: 100_000,
            to: 100_160,
            kind: "mixed".into(),
            out: root().join("target/sweep"),
            json: None,
        };
        let mut it = args.iter();
        while let Some(a) = it.next() {
            let mut value = || {
                it.next()
                    .cloned()
                    .ok_or_else(|| format!("sweep: {a} needs a value"))
            };
            match a.as_str() {
                "--seeds" => {
                    let v = value()?;
                    let (a, b) = v
                        .split_once("..")
                        .ok_or_else(|| format!("sweep: --seeds wants A..B, got `{v}`"))?;
                    o.from = a
                        .parse()
                        .map_err(|_| format!("sweep: --seeds: `{a}` is not a seed"))?;
                    o.to = b
                        .parse()
                        .map_err(|_| format!("sweep: --seeds: `{b}` is not a seed"))?;
                    if o.to <= o.from {
                        return Err(format!("sweep: --seeds {v} is empty"));
                    }
                }
                "--kind" => o.kind = value()?,
                "--out" => o.out = PathBuf::from(value()?),
                "--json" => o.json = Some(PathBuf::from(value()?)),
                other => return Err(format!("sweep: unknown argument `{other}`")),
            }
        }
        Ok(o)
    }
}

/// The score of one record.
#[derive(Clone, Debug)]
pub struct Scored {
    /// Record name.
    pub name: String,
    /// Plant of the generator.
    pub plant: String,
    /// Hidden effects.
    pub hidden: Vec<String>,
    /// Named effects.
    pub named: Vec<String>,
    /// Visibility per hidden effect.
    pub visibility: Vec<(String, f64)>,
    /// Named exactly (see the module doc).
    pub exact: bool,
    /// Gap shrink `1 − after/before` (with hidden effects).
    pub shrink: Option<f64>,
    /// Diagnose failed (message).
    pub failed: Option<String>,
}

impl Scored {
    /// Exact and, with hidden effects, the gap halved.
    pub fn success(&self) -> bool {
        self.exact && self.shrink.is_none_or(|s| s >= 0.5)
    }
}

/// What `truth.json` of the generator says about a record (the fields the
/// score reads; a missing field is empty).
#[derive(Debug, Default, Deserialize)]
#[serde(default)]
pub struct Truth {
    /// Hidden effects.
    pub hidden: Vec<String>,
    /// Effects a correct diagnosis may add.
    pub accept_extra: Vec<String>,
    /// Visibility per hidden effect (`null` when not finite).
    pub visibility: HashMap<String, Option<f64>>,
    /// Plant of the generator (`model` when absent).
    pub plant: Option<String>,
}

/// What the score reads of `breakaway-lab diagnose --json`.
#[derive(Debug, Deserialize)]
pub struct Report {
    /// Effects named, in order.
    #[serde(default)]
    pub effects_added: Vec<String>,
    /// Gap before [N] (`null` when not finite).
    pub rms_before: Option<f64>,
    /// Gap after [N].
    pub rms_after: Option<f64>,
}

/// Scores the report `report` against the truth `truth` (module doc).
pub fn score(name: &str, truth: Truth, report: Result<Report, String>) -> Scored {
    let Truth {
        hidden,
        accept_extra: extra,
        visibility: seen,
        plant,
    } = truth;
    let visibility = hidden
        .iter()
        .map(|h| {
            (
                h.clone(),
                seen.get(h).copied().flatten().unwrap_or(f64::NAN),
            )
        })
        .collect();
    let plant = plant.unwrap_or_else(|| "model".into());
    match report {
        Err(e) => Scored {
            name: name.into(),
            plant,
            hidden,
            named: Vec::new(),
            visibility,
            exact: false,
            shrink: None,
            failed: Some(e),
        },
        Ok(rep) => {
            let named = rep.effects_added;
            let exact = hidden.iter().all(|h| named.contains(h))
                && named
                    .iter()
                    .all(|n| hidden.contains(n) || extra.contains(n));
            let shrink = (!hidden.is_empty()).then(|| {
                let b = rep.rms_before.unwrap_or(f64::NAN);
                let a = rep.rms_after.unwrap_or(f64::NAN);
                1.0 - a / b
            });
            Scored {
                name: name.into(),
                plant,
                hidden,
                named,
                visibility,
                exact,
                shrink,
                failed: None,
            }
        }
    }
}

fn read_json<T: DeserializeOwned>(path: &Path) -> Result<T, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Generates the records of `o` and diagnoses each (two at a time).
pub fn sweep(o: &Options) -> Result<Vec<Scored>, String> {
    run(cargo().args([
        "build",
        "--release",
        "-p",
        "breakaway-gen",
        "-p",
        "breakaway-lab",
    ]))?;
    let bin = crate::target_dir().join("release");
    std::fs::create_dir_all(&o.out).map_err(|e| format!("{}: {e}", o.out.display()))?;
    run(Command::new(bin.join("breakaway-gen")).args([
        "suite",
        "--seeds",
        &format!("{}..{}", o.from, o.to),
        "--kind",
        &o.kind,
        "--out",
        &o.out.display().to_string(),
    ]))?;
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&o.out)
        .map_err(|e| format!("{}: {e}", o.out.display()))?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.join("truth.json").is_file())
        // Only this run's seeds (`s<seed>_…`), whatever else is in DIR.
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .and_then(|n| n.strip_prefix('s'))
                .and_then(|n| n.split('_').next())
                .and_then(|n| n.parse::<u64>().ok())
                .is_some_and(|seed| (o.from..o.to).contains(&seed))
        })
        .collect();
    dirs.sort();
    let total = dirs.len();
    let done = AtomicUsize::new(0);
    let lab = bin.join("breakaway-lab");
    let bar = progress_bar(total);
    let one = |dir: &PathBuf| -> Scored {
        let name = dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let truth = read_json(&dir.join("truth.json")).unwrap_or_default();
        let report_path = dir.join("report.json");
        let status = Command::new(&lab)
            .arg("diagnose")
            .arg(dir.join("data.csv"))
            .arg("--json")
            .arg(&report_path)
            .output();
        let report = match status {
            Ok(out) if out.status.success() => read_json(&report_path),
            Ok(out) => Err(String::from_utf8_lossy(&out.stderr).trim().to_string()),
            Err(e) => Err(format!("cannot run breakaway-lab: {e}")),
        };
        let s = score(&name, truth, report);
        let k = done.fetch_add(1, Ordering::Relaxed) + 1;
        let line = format!(
            "sweep [{k}/{total}] {name}: hidden [{}] named [{}]{}",
            s.hidden.join(", "),
            s.named.join(", "),
            if s.success() { "" } else { "  <- miss" }
        );
        if bar.is_hidden() {
            eprintln!("{line}");
        } else {
            bar.println(line);
            bar.inc(1);
        }
        s
    };
    let mut scored: Vec<Scored> = std::thread::scope(|sc| {
        let hs: Vec<_> = (0..2)
            .map(|t| {
                let dirs = &dirs;
                let one = &one;
                sc.spawn(move || dirs.iter().skip(t).step_by(2).map(one).collect::<Vec<_>>())
            })
            .collect();
        hs.into_iter()
            .flat_map(|h| h.join().unwrap_or_default())
            .collect()
    });
    bar.finish_and_clear();
    scored.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(scored)
}

/// A progress bar under the per-record lines on a terminal; hidden
/// elsewhere, where the lines alone are printed.
fn progress_bar(total: usize) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(total as u64);
    if let Ok(style) = ProgressStyle::with_template("sweep {bar:40} {pos}/{len} [{elapsed}]") {
        bar.set_style(style);
    }
    bar
}

fn median(mut v: Vec<f64>) -> f64 {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The summary: overall rates, false positives, per effect detection
/// against visibility, gap shrink, per plant.
pub fn summary(scored: &[Scored]) -> Value {
    let n = scored.len();
    let exact = scored.iter().filter(|s| s.exact).count();
    let success = scored.iter().filter(|s| s.success()).count();
    let nulls: Vec<&Scored> = scored.iter().filter(|s| s.hidden.is_empty()).collect();
    let fp = nulls.iter().filter(|s| !s.named.is_empty()).count();
    let shrinks: Vec<f64> = scored.iter().filter_map(|s| s.shrink).collect();
    let bins = [
        (0.0, 10.0),
        (10.0, 20.0),
        (20.0, 50.0),
        (50.0, f64::INFINITY),
    ];
    let mut effects: Vec<String> = scored.iter().flat_map(|s| s.hidden.clone()).collect();
    effects.sort();
    effects.dedup();
    let per_effect: Vec<Value> = effects
        .iter()
        .map(|e| {
            let with: Vec<(&Scored, f64)> = scored
                .iter()
                .filter_map(|s| {
                    s.visibility
                        .iter()
                        .find(|(n, _)| n == e)
                        .map(|(_, v)| (s, *v))
                })
                .collect();
            let by_bin: Vec<Value> = bins
                .iter()
                .map(|(lo, hi)| {
                    let inb: Vec<&(&Scored, f64)> =
                        with.iter().filter(|(_, v)| *v >= *lo && *v < *hi).collect();
                    json!({
                        "visibility": format!("{lo}-{hi}"),
                        "records": inb.len(),
                        "detected": inb.iter().filter(|(s, _)| s.named.contains(e)).count(),
                    })
                })
                .collect();
            json!({
                "effect": e,
                "records": with.len(),
                "detected": with.iter().filter(|(s, _)| s.named.contains(e)).count(),
                "exact": with.iter().filter(|(s, _)| s.exact).count(),
                "median_shrink": median(with.iter().filter_map(|(s, _)| s.shrink).collect()),
                "by_visibility": by_bin,
            })
        })
        .collect();
    let above20: Vec<bool> = scored
        .iter()
        .flat_map(|s| {
            s.visibility
                .iter()
                .filter(|(_, v)| *v >= 20.0)
                .map(|(e, _)| s.named.contains(e))
                .collect::<Vec<_>>()
        })
        .collect();
    let mut plants: Vec<String> = scored.iter().map(|s| s.plant.clone()).collect();
    plants.sort();
    plants.dedup();
    let per_plant: Vec<Value> = plants
        .iter()
        .map(|p| {
            let of: Vec<&Scored> = scored.iter().filter(|s| &s.plant == p).collect();
            json!({
                "plant": p,
                "records": of.len(),
                "exact": of.iter().filter(|s| s.exact).count(),
                "success": of.iter().filter(|s| s.success()).count(),
                "false_positives": of.iter().filter(|s| s.hidden.is_empty() && !s.named.is_empty()).count(),
                "nulls": of.iter().filter(|s| s.hidden.is_empty()).count(),
            })
        })
        .collect();
    json!({
        "records": n,
        "named_exactly": exact,
        "named_exactly_and_gap_halved": success,
        "null_records": nulls.len(),
        "false_positives": fp,
        "median_shrink": median(shrinks),
        "detection_above_20x": {
            "effects": above20.len(),
            "detected": above20.iter().filter(|d| **d).count(),
        },
        "failed": scored.iter().filter(|s| s.failed.is_some()).map(|s| json!({"record": s.name, "error": s.failed})).collect::<Vec<_>>(),
        "per_effect": per_effect,
        "per_plant": per_plant,
        "misses": scored.iter().filter(|s| !s.success()).map(|s| json!({
            "record": s.name, "hidden": s.hidden, "named": s.named, "shrink": s.shrink,
        })).collect::<Vec<_>>(),
    })
}

/// `cargo xtask sweep`.
pub fn command(o: &Options) -> Result<(), String> {
    let scored = sweep(o)?;
    let s = summary(&scored);
    let text = serde_json::to_string_pretty(&s).map_err(|e| e.to_string())?;
    if let Some(j) = &o.json {
        std::fs::write(j, format!("{text}\n")).map_err(|e| format!("{}: {e}", j.display()))?;
    }
    println!("{text}");
    Ok(())
}

/// Seeds of the subset `cargo xtask test` runs (never used to tune the
/// workflow; the development seeds were 9000–9139).
pub const SMOKE_SEEDS: (u64, u64) = (7000, 7012);

/// Least records of the subset named exactly (5 of 12 when fixed, 4 after
/// the `Prepared::walk` mend, 6 with stops and the floor-relative gain;
/// one record of margin).
pub const SMOKE_MIN_EXACT: u64 = 5;
/// Most false positives on the subset's 3 effect-free records (1 when
/// fixed and still: `frictional_lag` on an open-loop ramp record).
pub const SMOKE_MAX_FALSE_POSITIVES: u64 = 1;

/// The subset of `cargo xtask test`: every record diagnosed without an
/// error, and no regression below the figures measured when the subset
/// was fixed; prints the summary.
pub fn smoke() -> Result<(), String> {
    let o = Options {
        from: SMOKE_SEEDS.0,
        to: SMOKE_SEEDS.1,
        kind: "model".into(),
        out: crate::target_dir().join("sweep-smoke"),
        json: None,
    };
    let _ = std::fs::remove_dir_all(&o.out);
    let scored = sweep(&o)?;
    let s = summary(&scored);
    println!(
        "sweep subset (seeds {}..{}, independent generator): {} records, {} named exactly, {} with the gap halved, {} false positives on {} effect-free records, median shrink {:.2}",
        o.from,
        o.to,
        s["records"],
        s["named_exactly"],
        s["named_exactly_and_gap_halved"],
        s["false_positives"],
        s["null_records"],
        s["median_shrink"].as_f64().unwrap_or(f64::NAN)
    );
    if scored.is_empty() {
        return Err("sweep subset: no record was generated".into());
    }
    if let Some(f) = scored.iter().find(|x| x.failed.is_some()) {
        return Err(format!(
            "sweep subset: diagnose failed on {}: {:?}",
            f.name, f.failed
        ));
    }
    // A regression guard, not a quality claim (the quality figures come
    // from `cargo xtask sweep` on seeds of its own): on this subset the
    // workflow named 5 of 12 records exactly with 1 false positive on 3
    // effect-free records when the subset was fixed (4 of 12 after the
    // `Prepared::walk` mend, 6 of 12 with stops and the floor-relative
    // gain).
    let exact = s["named_exactly"].as_u64().unwrap_or(0);
    let fp = s["false_positives"].as_u64().unwrap_or(u64::MAX);
    if exact < SMOKE_MIN_EXACT || fp > SMOKE_MAX_FALSE_POSITIVES {
        return Err(format!(
            "sweep subset regressed: {exact} named exactly (at least {SMOKE_MIN_EXACT}), {fp} false positives (at most {SMOKE_MAX_FALSE_POSITIVES}); misses: {}",
            s["misses"]
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scores_a_truth_file_against_a_report() {
        let truth: Truth = serde_json::from_str(
            r#"{"name": "s1", "seed": 1, "plant": "lugre", "hidden": ["offset"],
                "accept_extra": ["frictional_lag"], "visibility": {"offset": 25.0},
                "targets": {"offset": 0.1}}"#,
        )
        .unwrap();
        let report: Report = serde_json::from_str(
            r#"{"effects_added": ["offset", "frictional_lag"], "rms_before": 1.0,
                "rms_after": 0.25, "model": {"fc": 1.0}}"#,
        )
        .unwrap();
        let s = score("s1", truth, Ok(report));
        assert!(s.exact && s.success());
        assert_eq!(s.plant, "lugre");
        assert_eq!(s.visibility, vec![("offset".to_string(), 25.0)]);
        assert_eq!(s.shrink, Some(0.75));
        // An unreadable truth file scores as a record without hidden
        // effects on the model plant; a null rms is not finite.
        let report: Report =
            serde_json::from_str(r#"{"effects_added": [], "rms_before": null}"#).unwrap();
        let s = score("s2", Truth::default(), Ok(report));
        assert_eq!((s.plant.as_str(), s.exact, s.shrink), ("model", true, None));
        let s = score("s3", Truth::default(), Err("failed".into()));
        assert_eq!(s.failed.as_deref(), Some("failed"));
    }
}
