//! Development aid: do the open-loop force ramps of a record tell a model
//! with `dwell_stiction` from one without it? An open-loop ramp from a
//! zero-force rest is the one stretch of a servo record where the force is
//! not the servo's reaction to the motion: the axis creeps through
//! presliding count by count while the force rises, and breaks away where
//! its stiction level, raised by the rest before (MODEL.md §5), lets it.
//! The lab's walk does not see that creep (it is still by the window rule,
//! so the memory is re-anchored at the measured force at every sample).
//!
//! Each such ramp (at least 0.1 s of `|u|` within the noise band of zero,
//! then `u` rising one way, as the outside generator's servo records end)
//! is replayed: the plant `m·ẍ = u − F` integrated by semi-implicit Euler
//! at [`SUB`] steps a sample from an idle memory at the start of the rest
//! the counts show before the ramp ([`rest_start`]: through the release
//! and the hold back to the last motion faster than the rest speed), so
//! that the dwell clock has run as long, under zero force and then the ramp's
//! least-squares line from where it crosses zero. The logged force's noise
//! is the measurement's: replayed, it would turn the presliding memory back
//! and forth at every dip, each new branch starting infinitely stiff
//! (g'(0) = ∞), and hold the replayed axis back. The replayed count
//! crossings (the first at a fraction φ of a count, chosen per ramp from a
//! grid; counted from the ramp's start) are compared with the measured
//! ones up to a travel of 1.5 `z_max` (`RAMP_TRAVEL=F`: F·`z_max`): the
//! ramp's force at the replayed crossing time against that at the measured
//! one [N]. The onset is continuous; a step onto an idle branch would ring
//! in the replay.
//!
//! Then, per ramp, the stiction level is refitted alone (`Fs + Δ`, Δ by a
//! golden-section search), and the levels of the ramps that take at least
//! 0.1 s to reach `Fs` are regressed on `τ/(τ + γ)` with an intercept per
//! direction, over a grid of γ, `τ` the time from the rest's start to the
//! measured break-away (the travel reaching `z_max`): a slope near the
//! truth's `ΔFs` says the ramps carry the dwell term, a flat one that they
//! do not — provided the first model's other parameters are right, for the
//! slow ramps are also the ones after the longest rests (lab/HISTORY.md,
//! *Known gaps, as recorded*: on the development records the slope does
//! not separate dwell records from others). With `RAMP_NESTED=1` the
//! stiction level and `z_max` are also refitted on all creeping ramps
//! together, without and with a dwell term at γ = 0.3, 1 and 3 s (a
//! profile over `ΔFs`, both refitted at each); with
//! `RAMP_HOLD=1` the replay starts from the hold instead (idle at its mean
//! force, the release as a line to zero). With `RAMP_STATIC=1` each ramp's
//! stiction level is also estimated without a replay ([`static_level`]),
//! as if the creep were quasi-static: each measured crossing where the
//! first model's virgin branch `S·g(w)` reaches the ramp's force (on the
//! outside records the replay follows the slow ramps 2–5 times closer:
//! inertia is not negligible there); the slowest ramp's level less the
//! next slowest one's, per direction, is what a dwell term raises.
//!
//! `cargo run -p breakaway-lab --release --example ramp_replay -- DATA MODEL.toml...`
//!
//! Prints per ramp its start [s], direction, rate [N/s], `τ` [s] and, per
//! model, the mean and rms of the force difference [N], and for the first
//! model the refitted Δ [N] and its rms; then per model the rms over all
//! crossings, and the regression of the first model's Δ. See lab/README.md,
//! *Known gaps*.

use breakaway_lab::data;
use breakaway_lab::linalg::lstsq;
use breakaway_lab::residual::{auto_window, Prepared};
use breakaway_reference::{shape, stribeck_decay, DwellStiction, Friction, Model};
use std::path::Path;

/// Shortest zero-force rest before a ramp [s].
const MIN_ZERO: f64 = 0.1;
/// The rest speed, in Stribeck velocities `V` of the first model, where no
/// model given has `dwell_stiction` (else the first such model's `v_rest`).
const REST_SPEED: f64 = 0.1;
/// Travel compared, in `z_max` of the first model (overridden by the
/// environment variable `RAMP_TRAVEL`).
const TRAVEL: f64 = 1.5;
/// Grid of the first crossing's fraction of a count.
const PHASES: usize = 10;
/// Integration steps per sample.
const SUB: usize = 50;
/// The profile's `ΔFs`, in shares of the stiction level refitted without
/// dwell (`RAMP_NESTED`).
const DWELL_SHARES: [f64; 6] = [0.05, 0.1, 0.2, 0.3, 0.5, 0.8];
/// The γ grid of the regression [s].
const GAMMAS: [f64; 8] = [0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0];

/// One open-loop ramp from a zero-force rest.
struct Ramp {
    /// First sample of the rest before it (the counts').
    rest: usize,
    /// First sample of the release before the zero-force stretch (the
    /// force falling monotonically to it).
    release: usize,
    /// First sample of the zero-force stretch.
    zero: usize,
    /// First sample of the ramp.
    start: usize,
    /// One past its last sample.
    end: usize,
    /// Direction (±1).
    dir: f64,
    /// Slope [N/s] of its least-squares line in time.
    rate: f64,
    /// That line's force [N] at the ramp's first sample.
    u0: f64,
    /// Time [s] of the ramp's first sample.
    t_start: f64,
}

/// The open-loop ramps of a record (times `t` [s], force `u` [N],
/// positions `x` [m], count `q` [m], force noise std `noise` [N]): at least
/// [`MIN_ZERO`] of `|u|` within the noise band, then a rise one way that a
/// line follows to within the noise.
fn ramps(t: &[f64], u: &[f64], x: &[f64], q: f64, noise: f64, rest_speed: f64) -> Vec<Ramp> {
    let n = u.len();
    let peak = u.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    let band = (5.0 * noise).max(0.005 * peak);
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let min_zero = (MIN_ZERO / dt).ceil() as usize;
    let mut out = Vec::new();
    let mut i = 0;
    while i < n {
        if u[i].abs() > band {
            i += 1;
            continue;
        }
        let zero = i;
        while i < n && u[i].abs() <= band {
            i += 1;
        }
        if i - zero < min_zero || i + 20 >= n {
            continue;
        }
        let start = i;
        let dir = u[(start + 5).min(n - 1)].signum();
        let mut end = start + 1;
        while end < n && dir * u[end] >= dir * u[end - 1] - 3.0 * noise - 0.02 * peak {
            end += 1;
        }
        // The line by the lab's least squares, in the time since the
        // ramp's start (the columns then have comparable scales).
        let since: Vec<f64> = t[start..end].iter().map(|ti| ti - t[start]).collect();
        let Some(c) = lstsq(&[vec![1.0; end - start], since.clone()], &u[start..end]) else {
            i = end;
            continue;
        };
        let (u0, rate) = (c[0], c[1]);
        // A ramp is a line: the servo's own force sweeps are not.
        let off = since
            .iter()
            .zip(&u[start..end])
            .map(|(s, uk)| (uk - u0 - rate * s).powi(2))
            .sum::<f64>()
            / (end - start).max(1) as f64;
        if end - start < 20 || dir * rate <= 0.0 || off.sqrt() > 3.0 * noise + 0.01 * peak {
            continue;
        }
        let rest = rest_start(t, x, q, zero, rest_speed);
        let mut release = zero;
        while release > rest + 1
            && u[release - 1].abs() > u[release].abs() - 3.0 * noise
            && u[release - 1].abs() > band
        {
            release -= 1;
        }
        out.push(Ramp {
            rest,
            release,
            zero,
            start,
            end,
            dir,
            rate,
            u0,
            t_start: t[start],
        });
        i = end;
    }
    out
}

/// The first sample of the rest that ends at `zero`, as a dwell clock with
/// a rest speed of `speed` [m/s] sees it in the counts (times `t` [s],
/// positions `x` [m], count `q` [m]): walking back over the count changes,
/// the first one after a count the axis crossed faster than `speed` (in
/// less than `q/speed`), or the first sample after a jump of more than one
/// count between two samples. The release before a ramp moves the axis back through
/// presliding by up to a fraction of `z_max`, often several counts, and
/// the hold before it is a rest as well.
fn rest_start(t: &[f64], x: &[f64], q: f64, zero: usize, speed: f64) -> usize {
    let mut later: Option<usize> = None;
    for i in (1..=zero).rev() {
        let step = ((x[i] - x[i - 1]).abs() / q).round();
        if step == 0.0 {
            continue;
        }
        // The count held from `i` to the next change was crossed fast.
        if let Some(l) = later {
            if q / (t[l] - t[i]) > speed {
                return l;
            }
        }
        // A jump of counts: the rest begins after it.
        if step > 1.0 {
            return i;
        }
        later = Some(i);
    }
    later.unwrap_or(0)
}

/// Whether a ramp of `rate` [N/s] is slow enough to creep under `m`: the
/// force takes at least 0.1 s to reach `Fs` (faster ones break away within
/// a few samples, where the replay's dynamics, not the level, set the
/// crossings).
fn creeps(rate: f64, m: &Model) -> bool {
    rate.abs() <= 10.0 * m.fs
}

/// The stiction level a ramp asks of the first model.
struct Level {
    /// Time [s] from the rest's start to the measured break-away.
    tau: f64,
    /// Refitted raise Δ of `Fs` [N].
    delta: f64,
    /// Direction (±1).
    dir: f64,
    /// Force rate [N/s].
    rate: f64,
}

/// A ramp's measured count crossings and what a replay is compared on.
struct Case<'a> {
    ramp: &'a Ramp,
    /// Time of the rest's start [s].
    t0: f64,
    /// Replayed span [s].
    span: f64,
    /// Sampling interval [s].
    dt: f64,
    /// Encoder count [m].
    q: f64,
    /// Measured positions [m] at the rest's start and at the ramp's (a
    /// position ripple is a function of where the axis is).
    x_rest: f64,
    x_start: f64,
    /// Measured crossings: count (from the ramp's start), time [s] since
    /// `t0`.
    crossings: Vec<(f64, f64)>,
    /// With `RAMP_HOLD`: the mean force of the hold [N] and the times [s]
    /// since `t0` of the release's start and end (the replay starts from
    /// the hold and lets go as the record does).
    hold: Option<(f64, f64, f64)>,
}

impl Case<'_> {
    /// The replayed force at `tau` [s] since `t0`: the ramp's line from
    /// where it crosses zero (a little before the sample where the logged
    /// force leaves the noise band), zero before. The onset is continuous:
    /// a step onto an idle branch, which starts infinitely stiff
    /// (g'(0) = ∞), would ring in the replay and turn its memory.
    fn force(&self, tau: f64) -> f64 {
        if let Some((f, a, b)) = self.hold {
            if tau < a {
                return f;
            }
            if tau < b {
                return f * (b - tau) / (b - a);
            }
        }
        let r = self.ramp;
        let f = r.u0 + r.rate * (self.t0 + tau - r.t_start);
        if r.dir * f > 0.0 {
            f
        } else {
            0.0
        }
    }

    /// The replayed positions [m] at every integration step, from the
    /// measured one at the rest's start, with the step [s]; `None` if the
    /// replay runs off. The
    /// memory starts idle at the rest's start with no force (at rest the
    /// friction is the force: the dry part is anchored at minus the
    /// additive terms); `drift` is rebased to that start, as the replay's
    /// clock starts there.
    fn replay(&self, m: &Model) -> Option<(Vec<f64>, f64)> {
        let mut m = m.clone();
        if let Some(d) = m.effects.drift.as_mut() {
            let scale = 1.0 + d.beta * self.t0;
            m.fc *= scale;
            m.fs *= scale;
            d.beta /= scale;
        }
        let m = &m;
        let h = self.dt / SUB as f64;
        let steps = (self.span / h).ceil() as usize;
        let mut fr = Friction::new(m, 0.0, self.x_rest, 0.0);
        let additive = fr.update(m, 0.0, self.x_rest, 0.0) - fr.dry();
        fr.anchor(self.x_rest, self.hold.map_or(0.0, |h| h.0) - additive);
        let (mut x, mut v) = (self.x_rest, 0.0f64);
        let mut xs = Vec::with_capacity(steps + 1);
        let mut held = 0.0;
        for k in 0..=steps {
            let tau = k as f64 * h;
            xs.push(x);
            let f = fr.update(m, tau, x, v);
            // Force held over each sample, as a digital controller does.
            if k % SUB == 0 {
                held = self.force(tau);
            }
            v += (held - f) / m.mass * h;
            x += v * h;
            if !x.is_finite() {
                return None;
            }
        }
        Some((xs, h))
    }

    /// Mean and rms [N] of the force difference at the crossings, at the
    /// best φ of the grid.
    fn score(&self, m: &Model) -> Option<(f64, f64)> {
        let (xs, h) = self.replay(m)?;
        let r = self.ramp;
        let first = (((r.t_start - self.t0) / h).round() as usize).min(xs.len() - 1);
        let x0 = xs[first];
        let mut best: Option<(f64, f64)> = None;
        for ph in 0..PHASES {
            let phi = (ph as f64 + 0.5) / PHASES as f64;
            let (mut s1, mut s2) = (0.0, 0.0);
            let mut j = first;
            for &(c, tm) in &self.crossings {
                let target = r.dir * x0 + (c - 1.0 + phi) * self.q;
                while j < xs.len() && r.dir * xs[j] < target {
                    j += 1;
                }
                let ts = (j as f64 * h).min(self.span);
                let e = r.dir * (self.force(tm) - self.force(ts));
                s1 += e;
                s2 += e * e;
            }
            let n = self.crossings.len() as f64;
            let rms = (s2 / n).sqrt();
            if best.is_none_or(|b| rms < b.1) {
                best = Some((s1 / n, rms));
            }
        }
        best
    }
}

/// The stiction level `Fs'` [N] of one ramp read quasi-statically from its
/// crossings (count from the ramp's start, time [s] since the rest's
/// start) with the rms [N] left, or `None` with fewer than 4 crossings
/// within `w_max·z_max`. The ramp starts a branch from the force it
/// starts at (MODEL.md §3: a reversal after the release, `H_r` ≈ 0), and
/// with inertia and the branch's own velocity negligible the force at a
/// travel `s` is `F0 + A·sin(2π·x/λ + φ) + d·S·g(s/z_max)`: `S` the
/// Stribeck level of `m` at the creep's speed `v = z_max·|k|/(S·(−ln w))`
/// (four fixed-point steps; `Fc` with `m`'s asymmetry), `F0` its offset,
/// the ripple at the crossing's position. The first crossing lies a
/// fraction φ of a count from the start (a grid); `Fs'` by golden section
/// at each φ, the best pair kept.
fn static_level(case: &Case, m: &Model, w_max: f64) -> Option<(f64, f64)> {
    let r = case.ramp;
    let f0 = m.effects.offset.as_ref().map_or(0.0, |o| o.f0);
    let fc = m.fc * (1.0 + m.effects.asymmetry.as_ref().map_or(0.0, |a| a.a * r.dir));
    let ripple = |x: f64| {
        m.effects.position_ripple.as_ref().map_or(0.0, |p| {
            p.amplitude * (std::f64::consts::TAU * x / p.wavelength + p.phase).sin()
        })
    };
    let predicted = |fs1: f64, w: f64| {
        let mut s = fs1;
        for _ in 0..4 {
            let stiff = (s * -w.min(1.0 - 1e-9).ln()).max(1e-12);
            let v = m.z_max * r.rate.abs() / stiff;
            s = fc + (fs1 - fc) * stribeck_decay(m.v_stribeck, m.delta, v);
        }
        let x = case.x_start + r.dir * w * m.z_max;
        f0 + ripple(x) + r.dir * s * shape(w)
    };
    let mut best: Option<(f64, f64)> = None;
    for ph in 0..PHASES {
        let phi = (ph as f64 + 0.5) / PHASES as f64;
        let points: Vec<(f64, f64)> = case
            .crossings
            .iter()
            .map(|&(c, tm)| ((c - 1.0 + phi) * case.q / m.z_max, case.force(tm)))
            .filter(|&(w, _)| w <= w_max)
            .collect();
        if points.len() < 4 {
            continue;
        }
        let sq = |fs1: f64| {
            points
                .iter()
                .map(|&(w, f)| (predicted(fs1, w) - f).powi(2))
                .sum::<f64>()
        };
        let (fs1, s2) = golden(0.3 * m.fs, 3.0 * m.fs, sq);
        let rms = (s2 / points.len() as f64).sqrt();
        if best.is_none_or(|b| rms < b.1) {
            best = Some((fs1, rms));
        }
    }
    best
}

/// The model with its stiction level raised by `delta` [N].
fn raised(m: &Model, delta: f64) -> Model {
    let mut m = m.clone();
    m.fs = (m.fs + delta).max(m.fc);
    m
}

/// The Δ [N] within `lo..hi` that minimises `f` (golden section), with
/// `f` there.
fn golden(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (hi - r * (hi - lo), lo + r * (hi - lo));
    let (mut fa, mut fb) = (f(a), f(b));
    for _ in 0..24 {
        if fa < fb {
            hi = b;
            b = a;
            fb = fa;
            a = hi - r * (hi - lo);
            fa = f(a);
        } else {
            lo = a;
            a = b;
            fa = fb;
            b = lo + r * (hi - lo);
            fb = f(b);
        }
    }
    if fa < fb {
        (a, fa)
    } else {
        (b, fb)
    }
}

/// Root-mean-square force difference [N] of `m` over the crossings of all
/// `cases` (each at its best φ), or infinity where a replay runs off.
fn pooled(cases: &[Case], m: &Model) -> f64 {
    let (mut s2, mut n) = (0.0, 0usize);
    for c in cases {
        match c.score(m) {
            Some((_, rms)) => {
                s2 += rms * rms * c.crossings.len() as f64;
                n += c.crossings.len();
            }
            None => return f64::INFINITY,
        }
    }
    (s2 / n.max(1) as f64).sqrt()
}

/// The nested comparison (with `RAMP_NESTED` set) on the creeping ramps
/// together: the stiction level
/// and the presliding distance refitted without dwell (a), then with a
/// dwell term at each γ of a short grid (b; `v_rest` so large that the
/// clock runs from the rest's start through the creep).
fn nested(cases: &[Case], m0: &Model) {
    if cases.len() < 4 {
        return;
    }
    // The stiction level and z_max refitted, one after the other, with
    // what `with` adds to the model.
    let refit = |m: &Model, with: &dyn Fn(&Model) -> Model| -> Model {
        let mut m = m.clone();
        for _ in 0..3 {
            let (d, _) = golden(-0.6 * m.fs, 0.3 * m.fs, |dl| {
                pooled(cases, &with(&raised(&m, dl)))
            });
            m = raised(&m, d);
            let (k, _) = golden(0.5, 2.0, |k| {
                let mut mk = with(&m);
                mk.z_max *= k;
                pooled(cases, &mk)
            });
            m.z_max *= k;
        }
        m
    };
    let ma = refit(m0, &|m: &Model| m.clone());
    let rms_a = pooled(cases, &ma);
    println!(
        "nested, {} creeping ramps: without dwell Fs {:.4} z_max {:.3e} rms {rms_a:.4} N",
        cases.len(),
        ma.fs,
        ma.z_max
    );
    // A profile over ΔFs, both refitted at each: the level and ΔFs trade
    // against each other, which a descent that moves one at a time does
    // not follow.
    for g in [0.3, 1.0, 3.0] {
        let mut best: Option<(f64, Model, f64)> = None;
        for share in DWELL_SHARES {
            let dfs = share * ma.fs;
            let with = |m: &Model| {
                let mut m = m.clone();
                m.effects.dwell_stiction = Some(DwellStiction {
                    delta_fs: dfs,
                    gamma: g,
                    v_rest: 1e3,
                });
                m
            };
            let m = refit(&ma, &with);
            let rms = pooled(cases, &with(&m));
            if best.as_ref().is_none_or(|b| rms < b.2) {
                best = Some((dfs, m, rms));
            }
        }
        if let Some((dfs, m, rms_b)) = best {
            println!(
                "  with dwell, gamma {g:.1} s: Fs {:.4} dFs {dfs:.4} z_max {:.3e} rms {rms_b:.4} N (ratio {:.3})",
                m.fs,
                m.z_max,
                rms_b / rms_a
            );
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((d, ms)) = args.split_first() else {
        eprintln!("usage: ramp_replay DATA MODEL.toml...");
        std::process::exit(2);
    };
    let rec = data::load(Path::new(d))?;
    let models = ms
        .iter()
        .map(|m| Model::load(Path::new(m)))
        .collect::<Result<Vec<_>, _>>()?;
    let p = Prepared::with_window(&rec, auto_window(&rec));
    let (t, u, x, q) = (&rec.t, &rec.u, &rec.x, p.resolution);
    let z_counts = models[0].z_max / q;
    let travel = std::env::var("RAMP_TRAVEL")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(TRAVEL);
    let mut total = vec![(0.0f64, 0usize); models.len()];
    let hold = std::env::var_os("RAMP_HOLD").is_some();
    let mut levels: Vec<Level> = Vec::new();
    let rest_speed = models
        .iter()
        .find_map(|m| m.effects.dwell_stiction.as_ref().map(|d| d.v_rest))
        .unwrap_or(REST_SPEED * models[0].v_stribeck);
    let all = ramps(t, u, x, q, p.force_noise, rest_speed);
    let mut creeping: Vec<Case> = Vec::new();
    let quasi_static = std::env::var_os("RAMP_STATIC").is_some();
    // Direction, |rate| [N/s] and quasi-static level [N] per ramp.
    let mut statics: Vec<(f64, f64, f64)> = Vec::new();
    for r in &all {
        let counts = |i: usize| (r.dir * (x[i] - x[r.start]) / q).round();
        let limit = (travel * z_counts).ceil();
        let t0 = t[r.rest];
        let mut crossings = Vec::new();
        let mut last = 0.0;
        let mut broke = None;
        for (i, ti) in t.iter().enumerate().take(r.end).skip(r.start) {
            let c = counts(i);
            // The crossing lies between samples i − 1 and i.
            let tm = ti - 0.5 * p.dt - t0;
            if c > last && c <= limit {
                crossings.push((c, tm));
            }
            if broke.is_none() && c >= z_counts {
                broke = Some(tm);
            }
            last = last.max(c);
        }
        if crossings.len() < 3 {
            continue;
        }
        let case = Case {
            ramp: r,
            t0,
            span: t[r.end - 1] - t0,
            dt: p.dt,
            q,
            x_rest: x[r.rest],
            x_start: x[r.start],
            crossings,
            hold: (hold && r.release > r.rest).then(|| {
                let f = u[r.rest..r.release].iter().sum::<f64>() / (r.release - r.rest) as f64;
                (f, t[r.release] - t0, t[r.zero] - t0)
            }),
        };
        let tau = broke.unwrap_or(case.span);
        print!(
            "{:8.3} dir {:+.0} rate {:8.2} N/s tau {:6.3} s crossings {:3}",
            t[r.start],
            r.dir,
            r.rate,
            tau,
            case.crossings.len()
        );
        for (mi, m) in models.iter().enumerate() {
            match case.score(m) {
                Some((mean, rms)) => {
                    print!(" | mean {mean:+.4} rms {rms:.4}");
                    total[mi].0 += rms * rms * case.crossings.len() as f64;
                    total[mi].1 += case.crossings.len();
                }
                None => print!(" | replay ran off"),
            }
        }
        let m0 = &models[0];
        let (delta, rms) = golden(-0.3 * m0.fs, 0.5 * m0.fs, |dl| {
            case.score(&raised(m0, dl)).map_or(f64::INFINITY, |s| s.1)
        });
        print!(" | refit Δ {delta:+.4} rms {rms:.4}");
        if quasi_static {
            match static_level(&case, m0, travel) {
                Some((fs1, rms)) => {
                    print!(" | static Fs' {fs1:.4} rms {rms:.4}");
                    statics.push((r.dir, r.rate.abs(), fs1));
                }
                None => print!(" | static: too few crossings"),
            }
        }
        println!();
        levels.push(Level {
            tau,
            delta,
            dir: r.dir,
            rate: r.rate,
        });
        if creeps(r.rate, m0) {
            creeping.push(case);
        }
    }
    if quasi_static {
        // Per direction the slowest ramp's level less the next slowest's.
        let mut diffs = Vec::new();
        for dir in [1.0, -1.0] {
            let mut own: Vec<&(f64, f64, f64)> = statics.iter().filter(|s| s.0 == dir).collect();
            own.sort_by(|a, b| a.1.total_cmp(&b.1));
            if let [slow, next, ..] = own[..] {
                diffs.push(slow.2 - next.2);
                println!(
                    "static, direction {dir:+.0}: slowest {:.2} N/s Fs' {:.4}, next {:.2} N/s Fs' {:.4}, difference {:+.4} N",
                    slow.1,
                    slow.2,
                    next.1,
                    next.2,
                    slow.2 - next.2
                );
            }
        }
        if !diffs.is_empty() {
            let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
            println!(
                "static difference, mean of {}: {mean:+.4} N ({:+.4} Fs)",
                diffs.len(),
                mean / models[0].fs
            );
        }
    }
    if std::env::var_os("RAMP_NESTED").is_some() {
        nested(&creeping, &models[0]);
    }
    for (m, (s2, n)) in ms.iter().zip(&total) {
        if *n > 0 {
            println!(
                "{m}: rms {:.4} N over {n} crossings",
                (s2 / *n as f64).sqrt()
            );
        }
    }
    // The regression over the ramps that creep, with an intercept per
    // direction.
    let slow: Vec<&Level> = levels
        .iter()
        .filter(|l| creeps(l.rate, &models[0]))
        .collect();
    if slow.len() >= 4 {
        let ys: Vec<f64> = slow.iter().map(|l| l.delta).collect();
        let mean = ys.iter().sum::<f64>() / ys.len() as f64;
        let spread = (ys.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / ys.len() as f64).sqrt();
        println!(
            "refitted Δ of {} over {} creeping ramps: mean {mean:+.4} N, spread {spread:.4} N",
            ms[0],
            slow.len()
        );
        for g in GAMMAS {
            // Δ = a_dir + b·τ/(τ + γ): centre per direction, then one slope.
            let centred = |f: &dyn Fn(&Level) -> f64| -> Vec<f64> {
                slow.iter()
                    .map(|l| {
                        let same: Vec<f64> = slow
                            .iter()
                            .filter(|o| o.dir == l.dir)
                            .map(|o| f(o))
                            .collect();
                        f(l) - same.iter().sum::<f64>() / same.len() as f64
                    })
                    .collect()
            };
            let xs = centred(&|l| l.tau / (l.tau + g));
            let yc = centred(&|l| l.delta);
            let sxx: f64 = xs.iter().map(|x| x * x).sum();
            if sxx <= 0.0 {
                continue;
            }
            let b = xs.iter().zip(&yc).map(|(x, y)| x * y).sum::<f64>() / sxx;
            let dof = (slow.len() as f64 - 3.0).max(1.0);
            let res2 = xs
                .iter()
                .zip(&yc)
                .map(|(x, y)| (y - b * x).powi(2))
                .sum::<f64>();
            let se = (res2 / dof / sxx).sqrt();
            println!(
                "  gamma {g:5.2} s: slope {b:+.4} ± {se:.4} N, rms left {:.4} N",
                (res2 / slow.len() as f64).sqrt()
            );
        }
    }
    Ok(())
}
