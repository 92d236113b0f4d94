//! Development aid: how the workflow fares on the generator's compliant
//! two-mass records (`breakaway-gen`, plant `compliant`: the encoder on
//! the motor, the friction on the load behind a spring of stiffness `k`)
//! against the spring's static deflection under the Coulomb level,
//! `Fc/k`, in encoder counts and in presliding distances `z_max`. A
//! rigid axis's model sees that deflection as lost motion at every
//! reversal.
//!
//! On the record directories that `cargo xtask sweep --out DIR` leaves
//! (`DIR/s*`, each with `truth.json` and `report.json`); other plants are
//! skipped, and a report without a gap (a failed diagnosis) counts as a
//! miss.
//!
//! `cargo run -p breakaway-lab --release --example compliance -- DIR...`
//!
//! Prints one line per compliant record (name, `Fc/k` in counts and in
//! `z_max`, resonance [Hz], hidden and named effects, gap before and
//! after [N], and whether it scores: named exactly, with the gap halved
//! where effects are hidden; the rule of `xtask/src/sweep.rs`), then the
//! scores below and above [`SPLIT`] counts. See lab/README.md, *Known
//! gaps*.

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
    let dirs: Vec<String> = std::env::args().skip(1).collect();
    if dirs.is_empty() {
        eprintln!("usage: compliance DIR...");
        std::process::exit(2);
    }
    let read = |dir: &Path, file: &str| -> Result<serde_json::Value, Box<dyn std::error::Error>> {
        let text = std::fs::read_to_string(dir.join(file))
            .map_err(|e| format!("{}: {e}", dir.join(file).display()))?;
        Ok(serde_json::from_str(&text)?)
    };
    let mut scored = Vec::new();
    for dir in &dirs {
        let dir = Path::new(dir);
        let truth = read(dir, "truth.json")?;
        if truth["plant"].as_str() != Some("compliant") {
            continue;
        }
        let report = read(dir, "report.json")?;
        let k = number(&truth["plant_params"]["k"], dir, "plant_params.k")?;
        let resonance = number(&truth["plant_params"]["resonance_hz"], dir, "resonance_hz")?;
        let fc = number(&truth["model"]["fc"], dir, "model.fc")?;
        let z_max = number(&truth["model"]["z_max"], dir, "model.z_max")?;
        let q = number(&truth["encoder"], dir, "encoder")?;
        let gap = (report["rms_before"].as_f64(), report["rms_after"].as_f64());
        let hidden = names(&truth["hidden"]);
        let extra = names(&truth["accept_extra"]);
        let named = names(&report["effects_added"]);
        let exact = hidden.iter().all(|h| named.contains(h))
            && named
                .iter()
                .all(|n| hidden.contains(n) || extra.contains(n));
        let success = match gap {
            (Some(before), Some(after)) => exact && (hidden.is_empty() || after <= 0.5 * before),
            _ => false,
        };
        let gap = match gap {
            (Some(before), Some(after)) => format!("{before:.4} -> {after:.4} N"),
            _ => "none in report.json".into(),
        };
        let deflection = fc / k;
        let name = dir
            .file_name()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        println!(
            "{name}: Fc/k {:.0} counts, {:.1} z_max, resonance {resonance:.1} Hz; hidden [{}], named [{}]; gap {gap}; {}",
            deflection / q,
            deflection / z_max,
            hidden.join(", "),
            named.join(", "),
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
