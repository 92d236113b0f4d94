//! Development aid: how the workflow fares on the generator's compliant
//! two-mass records (`breakaway-gen`, plant `compliant`: the encoder on
//! the motor, the friction on the load behind a spring of stiffness `k`)
//! against the spring's static deflection under the Coulomb level,
//! `Fc/k`, in encoder counts and in presliding distances `z_max`. A
//! rigid axis's model sees that deflection as lost motion at every
//! reversal.
//!
//! On the JSON summary of a sweep and the record directories it left
//! (`cargo xtask sweep --out DIR --json SUMMARY`: `DIR/s*`, each with
//! `truth.json` and `report.json`); other plants are skipped. Whether a
//! record scores is the sweep's own verdict: it scores unless the
//! summary lists it among its `misses`.
//!
//! `cargo run -p breakaway-lab --release --example compliance -- SUMMARY DIR...`
//!
//! Prints one line per compliant record (name, `Fc/k` in counts and in
//! `z_max`, resonance [Hz], hidden and named effects, gap before and
//! after [N], and the verdict), then the scores below and above
//! [`SPLIT`] counts. See lab/README.md, *Known gaps*.

use std::path::Path;

/// Deflection [counts] at which the summary splits the records.
const SPLIT: f64 = 100.0;

/// One compliant record and its score.
struct Scored {
    /// Static deflection `Fc/k` [encoder counts].
    counts: f64,
    /// Whether the record scores.
    success: bool,
}

/// The strings of a JSON array (empty when absent).
fn names(v: &serde_json::Value) -> Vec<String> {
    v.as_array()
        .map(|a| {
            a.iter()
                .filter_map(|s| s.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default()
}

/// The number `v`, or an error naming `what` in `dir`.
fn number(v: &serde_json::Value, dir: &Path, what: &str) -> Result<f64, String> {
    v.as_f64()
        .ok_or_else(|| format!("{}: no number `{what}`", dir.display()))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((summary, dirs)) = args.split_first().filter(|(_, d)| !d.is_empty()) else {
        eprintln!("usage: compliance SUMMARY DIR...");
        std::process::exit(2);
    };
    let read = |path: &Path| -> Result<serde_json::Value, Box<dyn std::error::Error>> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(serde_json::from_str(&text)?)
    };
    let summary = read(Path::new(summary))?;
    let misses: Vec<&str> = summary["misses"]
        .as_array()
        .ok_or("the summary has no `misses`")?
        .iter()
        .filter_map(|m| m["record"].as_str())
        .collect();
    let mut scored = Vec::new();
    for dir in dirs {
        let dir = Path::new(dir);
        let truth = read(&dir.join("truth.json"))?;
        if truth["plant"].as_str() != Some("compliant") {
            continue;
        }
        let report = read(&dir.join("report.json"))?;
        let k = number(&truth["plant_params"]["k"], dir, "plant_params.k")?;
        let resonance = number(&truth["plant_params"]["resonance_hz"], dir, "resonance_hz")?;
        let fc = number(&truth["model"]["fc"], dir, "model.fc")?;
        let z_max = number(&truth["model"]["z_max"], dir, "model.z_max")?;
        let q = number(&truth["encoder"], dir, "encoder")?;
        let name = dir
            .file_name()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let success = !misses.contains(&name.as_str());
        let gap = match (report["rms_before"].as_f64(), report["rms_after"].as_f64()) {
            (Some(before), Some(after)) => format!("{before:.4} -> {after:.4} N"),
            _ => "none in report.json".into(),
        };
        let deflection = fc / k;
        println!(
            "{name}: Fc/k {:.0} counts, {:.1} z_max, resonance {resonance:.1} Hz; hidden [{}], named [{}]; gap {gap}; {}",
            deflection / q,
            deflection / z_max,
            names(&truth["hidden"]).join(", "),
            names(&report["effects_added"]).join(", "),
            if success { "scores" } else { "misses" }
        );
        scored.push(Scored {
            counts: deflection / q,
            success,
        });
    }
    for (label, below) in [("below", true), ("at or above", false)] {
        let part: Vec<&Scored> = scored
            .iter()
            .filter(|s| (s.counts < SPLIT) == below)
            .collect();
        let hits = part.iter().filter(|s| s.success).count();
        println!("Fc/k {label} {SPLIT} counts: {hits}/{} score", part.len());
    }
    Ok(())
}
