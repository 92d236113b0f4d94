//! Development aid: can the break-away after a rest tell a model with
//! `dwell_stiction` from one without it? Each rest of the record (a run of
//! still samples of at least 0.1 s followed by motion) is replayed: from the
//! friction memory that the lab's walk of each model holds at the rest's
//! last sample, the plant `m·ẍ = u − F` is integrated (semi-implicit Euler,
//! 50 steps per sample) under the *measured* force, held over each sample,
//! until the position has left the rest by `2·z_max` plus 3 counts. The
//! replayed times are compared with the measured one.
//!
//! `cargo run -p breakaway-lab --release --example dwell_replay -- DATA A.toml B.toml`
//!
//! Prints one line per rest (start, length, direction, measured time, the
//! two replayed times [s]), then the regression of `measured − B` on
//! `A − B` with an intercept over the rests where both replays broke away
//! and differ by less than 50 ms: a slope of 1 says the measurement follows
//! A, 0 that it follows B. On the outside example `servo_dwell` with A its
//! true model and B that model without `dwell_stiction`, see lab/HISTORY.md
//! ("Known gaps, as recorded", dwell).

use breakaway_lab::data;
use breakaway_lab::residual::{auto_window, Prepared};
use breakaway_reference::{Friction, Model};
use std::path::Path;

/// Integration steps per sample.
const SUB: usize = 50;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [data, a, b] = args.as_slice() else {
        eprintln!("usage: dwell_replay DATA A.toml B.toml");
        std::process::exit(2);
    };
    let rec = data::load(Path::new(data))?;
    let models = [Model::load(Path::new(a))?, Model::load(Path::new(b))?];
    let mut p = Prepared::with_window(&rec, auto_window(&rec));
    let r0 = p.residual(&models[1]);
    p.set_error_weights(&models[1], &r0);
    let n = p.len();
    let min_rest = (0.1 / p.dt).ceil() as usize;
    // The walk's friction memory of each model after every sample.
    let states: Vec<Vec<Friction>> = models
        .iter()
        .map(|m| {
            let mut v = Vec::with_capacity(n);
            p.walk(m, |_, fr| v.push(fr.clone()));
            v
        })
        .collect();
    let mut pairs = Vec::new();
    let mut i = 0;
    while i < n {
        if !p.still[i] {
            i += 1;
            continue;
        }
        let i0 = i;
        while i < n && p.still[i] {
            i += 1;
        }
        if i - i0 < min_rest || i >= n {
            continue;
        }
        let last = i - 1;
        let reach = 2.0 * models[1].z_max + 3.0 * p.resolution;
        let x_rest = p.x[last];
        let end = (i + (0.3 / p.dt) as usize).min(n - 1);
        let Some(k) = (i..end).find(|&k| (p.x[k] - x_rest).abs() >= reach) else {
            continue;
        };
        let dir = (p.x[k] - x_rest).signum();
        let measured = p.t[k] - p.t[last];
        let replay = |m: &Model, start: &Friction| -> f64 {
            let mut fr = start.clone();
            let (mut x, mut v, mut t) = (x_rest, 0.0f64, p.t[last]);
            let h = p.dt / SUB as f64;
            let mut f = fr.force();
            for j in last..end {
                for _ in 0..SUB {
                    v += (rec.u[j + 1] - f) / m.mass * h;
                    x += v * h;
                    t += h;
                    f = fr.update(m, t, x, v);
                    if (x - x_rest) * dir >= reach {
                        return t - p.t[last];
                    }
                }
            }
            f64::NAN
        };
        let ta = replay(&models[0], &states[0][last]);
        let tb = replay(&models[1], &states[1][last]);
        println!(
            "{:8.3} rest {:6.3} dir {:+} measured {:7.4} A {:8.4} B {:8.4}",
            p.t[i0],
            p.t[i] - p.t[i0],
            dir,
            measured,
            ta,
            tb
        );
        if ta.is_finite() && tb.is_finite() && (ta - tb).abs() < 0.05 {
            pairs.push((ta - tb, measured - tb));
        }
    }
    // y = c + λ·x by least squares, with the standard error of λ.
    let k = pairs.len() as f64;
    if k < 3.0 {
        println!("fewer than 3 rests to compare");
        return Ok(());
    }
    let (mx, my) = pairs
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / k, b + y / k));
    let sxx: f64 = pairs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = pairs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let lambda = sxy / sxx;
    let c = my - lambda * mx;
    let sse: f64 = pairs
        .iter()
        .map(|(x, y)| (y - c - lambda * x).powi(2))
        .sum();
    let se = (sse / (k - 2.0) / sxx).sqrt();
    let mut shifts: Vec<f64> = pairs.iter().map(|(x, _)| x.abs()).collect();
    shifts.sort_by(f64::total_cmp);
    println!(
        "{} rests: measured - B = {c:.4} s + ({lambda:.2} ± {se:.2})·(A - B); median |A - B| {:.4} s",
        pairs.len(),
        shifts[shifts.len() / 2]
    );
    Ok(())
}
