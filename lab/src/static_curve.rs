//! The steady-state (Stribeck + viscous) curve of MODEL.md §2 fitted per
//! direction to constant-velocity friction measurements
//! (`breakaway-lab static-curve`), such as the Indy7 joint files
//! (`desired vel, real vel, tau` in deg/s and N·m after a logger header).
//!
//! Per direction `d`, `|τ| = Fc + (Fs − Fc)·exp(−(|v|/V)^δ) + σ·|v|` with
//! `v` the measured ("real") velocity converted to rad/s. For fixed `(V, δ)`
//! the curve is linear in `(Fc, Fs, σ)`, so the fit is a grid over
//! `V` (log-spaced over the measured speeds) and `δ ∈ [0.5, 2.5]` with linear
//! least squares at each node, then a finer grid around the best node.
//! A node whose solution breaks `Fs ≥ Fc > 0`, `σ ≥ 0` is skipped; when no
//! node is admissible the direction is fitted without Stribeck
//! (`Fs = Fc`).

use crate::Error;
use std::f64::consts::PI;
use std::path::Path;

/// One measured point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Measured velocity [rad/s].
    pub v: f64,
    /// Torque [N·m].
    pub tau: f64,
}

/// The fitted curve of one direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curve {
    /// +1 or −1.
    pub direction: i8,
    /// Points used.
    pub n: usize,
    /// Coulomb level [N·m].
    pub fc: f64,
    /// Stiction level [N·m].
    pub fs: f64,
    /// Stribeck velocity [rad/s].
    pub v_stribeck: f64,
    /// Shape exponent.
    pub delta: f64,
    /// Viscous coefficient [N·m·s/rad].
    pub sigma: f64,
    /// RMS of the fit [N·m].
    pub rms: f64,
}

impl Curve {
    /// `|τ|` of the curve at speed `s = |v|` [rad/s].
    pub fn magnitude(&self, s: f64) -> f64 {
        self.fc
            + (self.fs - self.fc) * (-(s / self.v_stribeck).powf(self.delta)).exp()
            + self.sigma * s
    }
}

/// The file's points and the curves fitted to them.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticFit {
    /// All points.
    pub points: Vec<Point>,
    /// One curve per direction with readings at [`MIN_SPEEDS`] distinct speeds at least.
    pub curves: Vec<Curve>,
}

/// Reads an Indy7-layout file: lines of at least three numbers
/// `desired vel, real vel, tau` (a trailing comma allowed); other lines
/// (logger header, separators, blank) are skipped. Velocities in deg/s.
pub fn read(path: &Path) -> Result<Vec<Point>, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::Runtime(format!("{}: cannot read: {e}", path.display())))?;
    let mut pts = Vec::new();
    let mut header = false;
    for (ln, row) in crate::data::rows(&text) {
        let first = row.get(0).map_or("", str::trim);
        if first.to_ascii_lowercase().starts_with("desired vel") {
            header = true;
            continue;
        }
        // Before the header: the logger's preamble. After it, every row
        // that is not blank is a reading, read or refused: a row skipped
        // for its look would be a speed lost without a word.
        if !header || first.is_empty() {
            continue;
        }
        let f: Vec<&str> = crate::data::trimmed(&row)
            .into_iter()
            .filter(|s| !s.is_empty())
            .collect();
        if f.len() < 3 {
            return Err(Error::Runtime(format!(
                "{}: line {ln}: expected 3 columns (desired vel, real vel, tau), got {}",
                path.display(),
                f.len()
            )));
        }
        let num = |i: usize, name: &str| -> Result<f64, Error> {
            f[i].parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    Error::Runtime(format!(
                        "{}: line {ln}: column `{name}`: `{}` is not a finite number",
                        path.display(),
                        f[i]
                    ))
                })
        };
        num(0, "desired vel")?;
        let v = num(1, "real vel")?;
        let tau = num(2, "tau")?;
        pts.push(Point {
            v: v * PI / 180.0,
            tau,
        });
    }
    if !header {
        return Err(Error::Runtime(format!(
            "{}: no header line `desired vel, real vel, tau` (static-curve reads the Indy7 \
             layout; a steady-state CSV with columns v, u goes to `diagnose`)",
            path.display()
        )));
    }
    if pts.len() < 5 {
        return Err(Error::Runtime(format!(
            "{}: too few points: {} (need at least 5)",
            path.display(),
            pts.len()
        )));
    }
    Ok(pts)
}

/// Fewest distinct speeds in a direction for its curve to be fitted: the
/// curve has five parameters (Fc, Fs, V, δ, σ), and readings repeated at
/// one speed do not make another.
pub const MIN_SPEEDS: usize = 5;

/// The number of distinct speeds among `speeds` [rad/s or m/s], 0 not
/// counted (a reading at rest is no point of the sliding curve).
pub fn distinct_speeds(speeds: impl Iterator<Item = f64>) -> usize {
    let mut s: Vec<f64> = speeds.map(f64::abs).filter(|&s| s > 0.0).collect();
    s.sort_by(f64::total_cmp);
    s.dedup();
    s.len()
}

fn fit_direction(pts: &[Point], direction: i8) -> Option<Curve> {
    let sel: Vec<&Point> = pts
        .iter()
        .filter(|p| p.v * f64::from(direction) > 0.0)
        .collect();
    if distinct_speeds(sel.iter().map(|p| p.v)) < MIN_SPEEDS {
        return None;
    }
    let s: Vec<f64> = sel.iter().map(|p| p.v.abs()).collect();
    let y: Vec<f64> = sel.iter().map(|p| p.tau * f64::from(direction)).collect();
    let rms_of = |c: &Curve| {
        (s.iter()
            .zip(&y)
            .map(|(s, y)| (c.magnitude(*s) - y).powi(2))
            .sum::<f64>()
            / s.len() as f64)
            .sqrt()
    };
    let solve = |v_s: f64, delta: f64| -> Option<Curve> {
        let e: Vec<f64> = s.iter().map(|x| (-(x / v_s).powf(delta)).exp()).collect();
        let c_fc: Vec<f64> = e.iter().map(|e| 1.0 - e).collect();
        let c = crate::linalg::lstsq(&[c_fc, e, s.clone()], &y)?;
        let (fc, fs, sigma) = (c[0], c[1], c[2]);
        if !(fc > 0.0 && fs >= fc && sigma >= 0.0) {
            return None;
        }
        let mut curve = Curve {
            direction,
            n: s.len(),
            fc,
            fs,
            v_stribeck: v_s,
            delta,
            sigma,
            rms: 0.0,
        };
        curve.rms = rms_of(&curve);
        Some(curve)
    };
    let (lo, hi) = s
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    let lo = lo.max(1e-9);
    let mut best: Option<Curve> = None;
    let consider = |best: &mut Option<Curve>, c: Option<Curve>| {
        if let Some(c) = c {
            if best.is_none_or(|b| c.rms < b.rms) {
                *best = Some(c);
            }
        }
    };
    let n_v = 80;
    for i in 0..=n_v {
        let v_s = lo * 0.3 * (hi / (lo * 0.3)).powf(i as f64 / n_v as f64);
        for k in 0..=8 {
            consider(&mut best, solve(v_s, 0.5 + 0.25 * k as f64));
        }
    }
    if let Some(b) = best {
        for i in -10..=10 {
            for k in -5..=5 {
                let v_s = b.v_stribeck * 1.02f64.powi(i);
                let delta = (b.delta + 0.025 * f64::from(k)).max(0.1);
                consider(&mut best, solve(v_s, delta));
            }
        }
    }
    best.or_else(|| {
        // Without Stribeck: |τ| = Fc + σ·|v|.
        let c = crate::linalg::lstsq(&[vec![1.0; s.len()], s.clone()], &y)?;
        let mut curve = Curve {
            direction,
            n: s.len(),
            fc: c[0].max(1e-12),
            fs: c[0].max(1e-12),
            v_stribeck: 1.0,
            delta: 1.0,
            sigma: c[1].max(0.0),
            rms: 0.0,
        };
        curve.rms = rms_of(&curve);
        Some(curve)
    })
}

/// Reads `path` and fits both directions.
pub fn run(path: &Path) -> Result<StaticFit, Error> {
    let points = read(path)?;
    let curves: Vec<Curve> = [1i8, -1]
        .into_iter()
        .filter_map(|d| fit_direction(&points, d))
        .collect();
    if curves.is_empty() {
        return Err(Error::Runtime(format!(
            "{}: no direction has readings at {MIN_SPEEDS} distinct speeds to fit",
            path.display()
        )));
    }
    Ok(StaticFit { points, curves })
}

/// The fit as JSON (units: N·m, rad/s).
pub fn json(f: &StaticFit) -> String {
    let curves: Vec<_> = f
        .curves
        .iter()
        .map(|c| {
            serde_json::json!({
                "direction": c.direction, "points": c.n, "fc": c.fc, "fs": c.fs,
                "v_stribeck": c.v_stribeck, "delta": c.delta, "sigma": c.sigma, "rms": c.rms,
            })
        })
        .collect();
    let v = serde_json::json!({"units": "N*m, rad/s", "curves": curves});
    format!("{}\n", serde_json::to_string_pretty(&v).unwrap_or_default())
}

/// The fit as a table.
pub fn text(f: &StaticFit, source: &str) -> String {
    use crate::format::short;
    let rows: Vec<Vec<String>> = f
        .curves
        .iter()
        .map(|c| {
            vec![
                if c.direction > 0 { "+" } else { "-" }.to_string(),
                c.n.to_string(),
                short(c.fc, 4),
                short(c.fs, 4),
                short(c.v_stribeck, 3),
                short(c.delta, 3),
                short(c.sigma, 4),
                short(c.rms, 3),
            ]
        })
        .collect();
    format!(
        "{source}: |tau| = Fc + (Fs - Fc)*exp(-(|v|/V)^delta) + sigma*|v| per direction\n{}",
        crate::format::table(
            &[
                "dir",
                "points",
                "Fc [N·m]",
                "Fs [N·m]",
                "V [rad/s]",
                "delta",
                "sigma [N·m·s/rad]",
                "rms [N·m]"
            ],
            &rows
        )
    )
}

/// The points and curves, torque against velocity (log speed axis per
/// direction is not used: a linear axis with an inset would need more; the
/// low-speed part is shown by a second panel on a log axis).
pub fn svg(f: &StaticFit) -> String {
    use crate::svg::{Panel, Series};
    let mut panels = Vec::new();
    for log in [false, true] {
        let mut series = Vec::new();
        for c in &f.curves {
            let d = f64::from(c.direction);
            let pts: Vec<(f64, f64)> = f
                .points
                .iter()
                .filter(|p| p.v * d > 0.0)
                .map(|p| (if log { p.v.abs().log10() } else { p.v }, p.tau))
                .collect();
            series.push(Series::dots(
                &pts,
                if d > 0.0 { "#1f77b4" } else { "#d62728" },
            ));
            let (lo, hi) = pts
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p.0), b.max(p.0))
                });
            let line: Vec<(f64, f64)> = (0..=200)
                .map(|i| {
                    let x = lo + (hi - lo) * f64::from(i) / 200.0;
                    let s = if log { 10f64.powf(x) } else { x.abs() };
                    (x, d * c.magnitude(s))
                })
                .collect();
            series.push(Series::line(&line, "#333333"));
        }
        panels.push(Panel {
            title: if log {
                "torque against log10 |v| [rad/s]".into()
            } else {
                "torque [N·m] against velocity [rad/s]".into()
            },
            series,
        });
    }
    crate::svg::render(&panels)
}
