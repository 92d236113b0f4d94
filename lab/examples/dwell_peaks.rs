//! Development aid: does the applied force at a break-away grow with the
//! rest before it, as `dwell_stiction` (MODEL.md §5) says it should? On
//! records of `breakaway-gen record` (a directory with `data.csv`,
//! `truth.json` and `rest_log.csv`), for each rest of at least 0.1 s
//! (the position within 1.5 counts) after which the axis travels 10
//! counts or more one way within 0.3 s, the peak of `d·u` from 50 ms
//! before the rest ends to 0.3 s after it (d the direction of the travel)
//! is regressed per direction, with an intercept, on `t_d/(t_d + γ)` at
//! the truth's γ, twice: with `t_d` the rest the counts show, and with
//! `t_d` the generator's own dwell clock at the departure (the longer of
//! its values at the rest's end and 50 ms later, from `rest_log.csv`). A
//! slope near the truth's `ΔFs` says the peaks carry the dwell.
//!
//! `cargo run -p breakaway-lab --release --example dwell_peaks -- DIR...`
//!
//! Prints one line per record: its name, the truth's `ΔFs` and γ [s],
//! then per direction the number of departures and the two slopes with
//! their standard errors [N]. See lab/README.md, *Known gaps*.

use breakaway_lab::data;
use std::path::Path;

/// Shortest rest [s].
const MIN_REST: f64 = 0.1;
/// Width of a rest, in encoder counts.
const REST_BAND: f64 = 1.5;
/// Window after a rest [s].
const WINDOW: f64 = 0.3;
/// Start of the window before the rest ends [s].
const LEAD: f64 = 0.05;
/// Least travel in the window, in encoder counts.
const TRAVEL: f64 = 10.0;

/// One departure from a rest.
struct Departure {
    /// Direction of the travel (±1).
    direction: f64,
    /// The rest as the counts show it [s].
    rest: f64,
    /// The generator's dwell clock at the departure [s].
    clock: f64,
    /// Peak of `direction·u` in the window [N].
    peak: f64,
}

/// Slope and its standard error of `y` on `x` with an intercept, or
/// `None` below three points or without spread in `x`.
fn slope(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = x.len();
    if n < 3 {
        return None;
    }
    let mx = x.iter().sum::<f64>() / n as f64;
    let my = y.iter().sum::<f64>() / n as f64;
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let b = sxy / sxx;
    let a = my - b * mx;
    let ss: f64 = x.iter().zip(y).map(|(p, q)| (q - a - b * p).powi(2)).sum();
    Some((b, (ss / (n - 2) as f64 / sxx).sqrt()))
}

/// The generator's rest intervals `(start, end)` [s] from `rest_log.csv`
/// (`t,rest`: 1 where a rest starts, 0 where it ends; the record starts
/// at rest at t = 0); an open last rest ends at infinity.
fn generator_rests(path: &Path) -> Result<Vec<(f64, f64)>, Box<dyn std::error::Error>> {
    let mut rests = Vec::new();
    let mut open: Option<f64> = None;
    for row in csv::Reader::from_path(path)?.records() {
        let row = row?;
        let t: f64 = row[0].parse()?;
        match (&row[1], open) {
            ("1", _) => open = Some(t),
            ("0", Some(s)) => {
                rests.push((s, t));
                open = None;
            }
            // The record starts at rest (MODEL.md §5), logged only as it ends.
            ("0", None) if rests.is_empty() => rests.push((0.0, t)),
            _ => {}
        }
    }
    if let Some(s) = open {
        rests.push((s, f64::INFINITY));
    }
    Ok(rests)
}

/// The generator's dwell clock `t_d` [s] at time `t`: the length of the
/// most recent rest that started at or before `t`, up to `t`.
fn clock(rests: &[(f64, f64)], t: f64) -> f64 {
    rests
        .iter()
        .rev()
        .find(|&&(s, _)| s <= t)
        .map_or(0.0, |&(s, e)| e.min(t) - s)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dirs: Vec<String> = std::env::args().skip(1).collect();
    if dirs.is_empty() {
        eprintln!("usage: dwell_peaks DIR...");
        std::process::exit(2);
    }
    for dir in &dirs {
        let dir = Path::new(dir);
        let rec = data::load(&dir.join("data.csv"))?;
        let truth: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("truth.json"))?)?;
        let q = truth["encoder"].as_f64().ok_or("truth.json: no encoder")?;
        let dwell = &truth["model"]["effects"]["dwell_stiction"];
        let (Some(delta_fs), Some(gamma)) = (dwell["delta_fs"].as_f64(), dwell["gamma"].as_f64())
        else {
            println!("{}: no dwell_stiction in its truth", dir.display());
            continue;
        };
        let rests = generator_rests(&dir.join("rest_log.csv"))?;
        let (t, u, x) = (&rec.t, &rec.u, &rec.x);
        let n = t.len();
        if n < 2 {
            return Err(format!("{}: fewer than two samples", dir.display()).into());
        }
        let dt = t[1] - t[0];
        let (window, lead) = ((WINDOW / dt) as usize, (LEAD / dt) as usize);
        let mut departures = Vec::new();
        let mut i = 0;
        while i < n {
            let (mut k, mut lo, mut hi) = (i, x[i], x[i]);
            while k + 1 < n && hi.max(x[k + 1]) - lo.min(x[k + 1]) <= REST_BAND * q {
                k += 1;
                lo = lo.min(x[k]);
                hi = hi.max(x[k]);
            }
            let end = k + 1 + window;
            if t[k] - t[i] >= MIN_REST && end < n {
                let travel = x[end - 1] - x[k];
                if travel.abs() >= TRAVEL * q {
                    let d = travel.signum();
                    let peak = (k.saturating_sub(lead)..end)
                        .map(|j| d * u[j])
                        .fold(f64::NEG_INFINITY, f64::max);
                    departures.push(Departure {
                        direction: d,
                        rest: t[k] - t[i],
                        clock: clock(&rests, t[k]).max(clock(&rests, t[k] + LEAD)),
                        peak,
                    });
                }
            }
            i = k + 1;
        }
        let name = dir
            .file_name()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let mut line = format!("{name}: ΔFs {delta_fs:.3} N, γ {gamma:.3} s;");
        for d in [1.0, -1.0] {
            let own: Vec<&Departure> = departures.iter().filter(|p| p.direction == d).collect();
            let y: Vec<f64> = own.iter().map(|p| p.peak).collect();
            let by = |td: fn(&Departure) -> f64| {
                let x: Vec<f64> = own.iter().map(|p| td(p) / (td(p) + gamma)).collect();
                slope(&x, &y).map_or("—".to_string(), |(b, se)| format!("{b:.3} ± {se:.3}"))
            };
            line += &format!(
                " d = {d:+}: {} departures, slope on the counts' rests {}, on the generator's clock {};",
                own.len(),
                by(|p| p.rest),
                by(|p| p.clock)
            );
        }
        println!("{line}");
    }
    Ok(())
}
