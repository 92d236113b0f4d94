//! The **in-model** hidden-effect matrix: records from `synth`, which uses
//! the same `Friction` code the fitter uses (a regression check, not
//! evidence of generalisation; the independent evidence is
//! `tests/independent_records.rs` and `cargo xtask sweep`). Each catalogue
//! effect alone, several pairs and none, on two parameter sets, two noise
//! levels and several seeds; `diagnose` must name the hidden effects
//! exactly in ≥ 90 % of the cases, name nothing on effect-free data, and
//! shrink the gap by ≥ 50 % (median). The table is printed (run with
//! `--nocapture`); a larger sweep is the ignored test `sweep`.

use breakaway_lab::diagnose::{self, Options};
use breakaway_lab::progress::Progress;
use breakaway_lab::synth::{self, Noise, SynthSpec};
use breakaway_reference::Effect;

/// The effects hidden alone: every one `synth` can hide but
/// `nonlinear_viscous`, in catalogue order.
fn singles() -> impl Iterator<Item = Effect> {
    Effect::ALL
        .into_iter()
        .filter(|&e| synth::hideable(e) && e != Effect::NonlinearViscous)
}
const PAIRS: [[Effect; 2]; 3] = [
    [Effect::Offset, Effect::PositionRipple],
    [Effect::Viscous, Effect::Drift],
    [Effect::Asymmetry, Effect::FrictionalLag],
];

/// The names of `effects`, joined by `sep`.
fn join(effects: &[Effect], sep: &str) -> String {
    let names: Vec<&str> = effects.iter().map(|e| e.name()).collect();
    names.join(sep)
}

struct Row {
    spec: SynthSpec,
    named: Vec<Effect>,
    before: f64,
    after: f64,
}

impl Row {
    fn exact(&self) -> bool {
        let mut a = self.named.clone();
        let mut b = self.spec.effects.clone();
        a.sort();
        b.sort();
        a == b
    }
    fn shrink(&self) -> f64 {
        (self.before - self.after) / self.before
    }
}

fn cases(configs: &[(usize, Noise, u64)]) -> Vec<SynthSpec> {
    let mut sets: Vec<Vec<Effect>> = vec![vec![]];
    sets.extend(singles().map(|s| vec![s]));
    sets.extend(PAIRS.iter().map(|p| p.to_vec()));
    let mut out = Vec::new();
    for &(set, noise, seed) in configs {
        for (k, e) in sets.iter().enumerate() {
            out.push(SynthSpec {
                effects: e.clone(),
                seed: seed * 100 + k as u64,
                noise,
                set,
            });
        }
    }
    out
}

fn run_all(specs: Vec<SynthSpec>) -> Vec<Row> {
    let threads = 2;
    let chunks: Vec<Vec<SynthSpec>> = (0..threads)
        .map(|t| specs.iter().skip(t).step_by(threads).cloned().collect())
        .collect();
    let mut rows: Vec<Row> = std::thread::scope(|s| {
        let hs: Vec<_> = chunks
            .into_iter()
            .map(|c| {
                s.spawn(move || {
                    c.into_iter()
                        .map(|spec| {
                            let (rec, _) = synth::generate(&spec).expect("synth");
                            let rep = diagnose::diagnose(
                                &rec,
                                None,
                                &Options::default(),
                                &mut Progress::quiet(),
                            );
                            Row {
                                named: rep.effects_added().collect(),
                                before: rep.rms_before,
                                after: rep.rms_after,
                                spec,
                            }
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        hs.into_iter()
            .flat_map(|h| h.join().expect("thread"))
            .collect()
    });
    rows.sort_by_key(|r| (r.spec.set, r.spec.noise == Noise::High, r.spec.seed));
    rows
}

/// Prints the markdown table and returns (naming rate, false positives on
/// effect-free data, median shrink over records with hidden effects).
fn summarise(rows: &[Row]) -> (f64, usize, f64) {
    println!(
        "| hidden | set | noise | seed | named | exact | rms before [N] | rms after [N] | shrink |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let hidden = if r.spec.effects.is_empty() {
            "none".to_string()
        } else {
            join(&r.spec.effects, " + ")
        };
        let named = if r.named.is_empty() {
            "—".to_string()
        } else {
            join(&r.named, ", ")
        };
        println!(
            "| {hidden} | {} | {} | {} | {named} | {} | {:.4} | {:.4} | {:.0} % |",
            r.spec.set,
            r.spec.noise.name(),
            r.spec.seed,
            if r.exact() { "yes" } else { "**no**" },
            r.before,
            r.after,
            100.0 * r.shrink()
        );
    }
    let exact = rows.iter().filter(|r| r.exact()).count();
    let rate = exact as f64 / rows.len() as f64;
    let fp = rows
        .iter()
        .filter(|r| r.spec.effects.is_empty() && !r.named.is_empty())
        .count();
    let mut sh: Vec<f64> = rows
        .iter()
        .filter(|r| !r.spec.effects.is_empty())
        .map(Row::shrink)
        .collect();
    sh.sort_by(f64::total_cmp);
    let median = sh[sh.len() / 2];
    println!(
        "\nnamed exactly: {exact}/{} ({:.0} %); effects named on effect-free records: {fp}/{}; median gap shrink {:.0} %",
        rows.len(),
        100.0 * rate,
        rows.iter().filter(|r| r.spec.effects.is_empty()).count(),
        100.0 * median
    );
    (rate, fp, median)
}

#[test]
fn matrix() {
    let rows = run_all(cases(&[
        (0, Noise::Low, 1),
        (0, Noise::High, 2),
        (1, Noise::Low, 3),
        (1, Noise::High, 4),
    ]));
    let (rate, fp, median) = summarise(&rows);
    assert_eq!(fp, 0, "effects named on effect-free data");
    assert!(median >= 0.5, "median shrink {median}");
    // Every effect, `dwell_stiction` included, is named; the bar is the
    // issue's target.
    assert!(rate >= 0.9, "naming rate {rate} (issue target 0.9)");
}

#[test]
#[ignore = "larger sweep (several minutes): cargo test -p breakaway-lab --test hidden_effects -- --ignored --nocapture"]
fn sweep() {
    let mut configs = Vec::new();
    for seed in 5..11 {
        for set in [0, 1] {
            for noise in [Noise::Low, Noise::High] {
                configs.push((set, noise, seed));
            }
        }
    }
    let rows = run_all(cases(&configs));
    let (rate, fp, median) = summarise(&rows);
    assert!(rate >= 0.9 && fp == 0 && median >= 0.5);
}
