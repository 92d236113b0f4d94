//! Excitation families, the 1 kHz digital controllers (zero-order hold) and
//! the record loop.
//!
//! A record is a queue of segments (servo rests, velocity plateaus,
//! staircases, modulations, position sines, point-to-point moves, open-loop
//! force ramps and sine forces) played by a controller: a PID position loop
//! with velocity term ("PI velocity loop whose integral is the position
//! error, plus an outer position integral") for `servo`, `point_to_point`,
//! `ramps` and `sinusoid`, a PI velocity loop for `velocity_loop`.
//!
//! Set `BREAKAWAY_GEN_TRACE=1` to print each segment as it starts (stderr).
//!
//! The controller measures the true (continuous) encoder-side position at
//! each sample, so that the logged force carries no quantisation-driven
//! chatter: all the scatter of the logged `u` is the stated Gaussian noise.
//! The log holds the quantised position.
//!
//! Units: [m], [m/s], [N], [s], [kg].

use crate::draw::{lu, sign, uni};
use crate::plants::{Plant, DT};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::collections::VecDeque;
use std::f64::consts::TAU;

/// Excitation family.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// PI velocity loop with position integral: plateaus, rests, staircases,
    /// modulation, reversals, then open-loop ramps.
    Servo,
    /// PI velocity loop only: staircases, reversals, short stops.
    VelocityLoop,
    /// PID position loop, trapezoidal point-to-point moves with dwells.
    PointToPoint,
    /// Open-loop force ramps at 4–6 rates, servo-held rests of varying length.
    Ramps,
    /// Slow position sines in a position loop, plus an open-loop sine force.
    Sinusoid,
    /// Steady-state (constant-velocity) points `v,u`.
    Steady,
}

impl Family {
    /// Every family.
    pub const ALL: [Family; 6] = [
        Family::Servo,
        Family::VelocityLoop,
        Family::PointToPoint,
        Family::Ramps,
        Family::Sinusoid,
        Family::Steady,
    ];
    /// The families with dynamics (time records).
    pub const DYNAMIC: [Family; 5] = [
        Family::Servo,
        Family::VelocityLoop,
        Family::PointToPoint,
        Family::Ramps,
        Family::Sinusoid,
    ];

    /// Identifier.
    pub fn name(self) -> &'static str {
        match self {
            Family::Servo => "servo",
            Family::VelocityLoop => "velocity_loop",
            Family::PointToPoint => "point_to_point",
            Family::Ramps => "ramps",
            Family::Sinusoid => "sinusoid",
            Family::Steady => "steady",
        }
    }

    /// Parses an identifier.
    pub fn from_name(s: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == s)
    }
}

/// What the excitation needs to know about the axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Context {
    /// Total moving mass [kg].
    pub mass: f64,
    /// Coulomb level [N].
    pub fc: f64,
    /// Stiction level [N].
    pub fs: f64,
    /// Stribeck velocity [m/s].
    pub v_s: f64,
    /// Presliding distance [m].
    pub z_max: f64,
    /// Encoder count [m].
    pub q: f64,
    /// Record length [s].
    pub duration: f64,
    /// Force saturation [N].
    pub u_max: f64,
    /// Position-loop gains `(kv [N·s/m], kp [N/m], ki [N/(m·s)])`.
    pub gains: (f64, f64, f64),
    /// Velocity-loop gains `(kv [N·s/m], ki [N/m])`.
    pub vgains: (f64, f64),
    /// Open-loop zero-force pause [s] before each ramp of the `servo`
    /// family (the servo lets go of the axis, which relaxes from its
    /// holding force, then the ramp starts from 0), as the outside
    /// generator's servo records have it; 0: the ramp starts at once.
    pub ramp_pause: f64,
}

impl Context {
    /// Largest reference acceleration [m/s²]: half the Coulomb level over
    /// the mass.
    pub fn a_lim(&self) -> f64 {
        0.5 * self.fc / self.mass
    }

    /// Gains for a loop bandwidth `f_hz` [Hz] on mass `m` [kg]: position
    /// PID with the three closed-loop poles at `ω/3` (`kv = m·ω`,
    /// `kp = m·ω²/3`, `ki = m·ω³/27`), velocity PI `kv = m·ω`, `ki = m·ω²/5`.
    pub fn gains_for(m: f64, f_hz: f64) -> ((f64, f64, f64), (f64, f64)) {
        let w = TAU * f_hz;
        (
            (m * w, m * w * w / 3.0, m * w * w * w / 27.0),
            (m * w, m * w * w / 5.0),
        )
    }
}

/// One segment of an excitation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Seg {
    /// Servo-held rest (velocity reference 0) [s].
    Rest {
        /// Length [s].
        dur: f64,
    },
    /// Constant velocity reference `v` [m/s] (slew-limited) for `dur` [s].
    Plateau {
        /// Velocity [m/s].
        v: f64,
        /// Length [s].
        dur: f64,
    },
    /// `v_ref = v0·(1 + depth·sin(2π·f·τ))`.
    Modulated {
        /// Mean velocity [m/s].
        v0: f64,
        /// Relative depth [-].
        depth: f64,
        /// Frequency [Hz].
        freq: f64,
        /// Length [s].
        dur: f64,
    },
    /// Position sine `x_ref = x0 + A·(1 − cos(2π·f·τ))` over whole cycles.
    SineRef {
        /// Amplitude `A` [m] (signed).
        amp: f64,
        /// Frequency [Hz].
        freq: f64,
        /// Number of cycles.
        cycles: f64,
    },
    /// Trapezoidal move to the absolute position `target` [m].
    MoveTo {
        /// Target [m].
        target: f64,
        /// Cruise speed [m/s].
        vmax: f64,
        /// Acceleration [m/s²].
        acc: f64,
    },
    /// Open-loop ramp `u = u0 + rate·τ` (sign of `rate` = direction), from 0
    /// or from the last servo force; stopped once the axis has broken away.
    Ramp {
        /// Force rate [N/s] (signed).
        rate: f64,
        /// Start from the holding force instead of 0.
        from_hold: bool,
        /// Longest ramp [s].
        t_max: f64,
    },
    /// Open-loop release: the servo lets go of the axis, its last force
    /// falling linearly to 0 within 50 ms, then 0 until `dur` [s].
    Release {
        /// Length [s].
        dur: f64,
    },
    /// Open-loop `u = amp·sin(2π·f·τ)` over whole cycles.
    SineForce {
        /// Amplitude [N].
        amp: f64,
        /// Frequency [Hz].
        freq: f64,
        /// Number of cycles.
        cycles: f64,
    },
}

/// Time [s] over which a [`Seg::Release`] lets the force fall to 0.
const RELEASE: f64 = 0.05;

/// Longest distance of one plateau [m].
const DIST_CAP: f64 = 0.08;

/// Estimated length [s] of a segment (ramps by their nominal break time).
fn est(seg: &Seg, ctx: &Context) -> f64 {
    match *seg {
        Seg::Rest { dur }
        | Seg::Release { dur }
        | Seg::Plateau { dur, .. }
        | Seg::Modulated { dur, .. } => dur,
        Seg::SineRef { freq, cycles, .. } | Seg::SineForce { freq, cycles, .. } => cycles / freq,
        Seg::MoveTo { vmax, acc, .. } => 2.0 * vmax / acc + 0.5,
        Seg::Ramp { rate, t_max, .. } => (1.2 * ctx.fs / rate.abs()).min(t_max) + 0.2,
    }
}

/// The schedule of a record: a queue of segments drawn from the family's
/// random stream; more (filler) segments are drawn when it runs dry.
pub struct Schedule {
    family: Family,
    ctx: Context,
    rng: ChaCha8Rng,
    queue: VecDeque<Seg>,
}

impl Schedule {
    /// Draws the schedule of `family`.
    pub fn new(family: Family, ctx: Context, mut rng: ChaCha8Rng) -> Self {
        let mut queue = VecDeque::new();
        let c = &ctx;
        let d = c.duration;
        queue.push_back(Seg::Rest {
            dur: uni(&mut rng, 0.2, 0.5),
        });
        let total = |q: &VecDeque<Seg>| q.iter().map(|s| est(s, c)).sum::<f64>();
        match family {
            Family::Servo => {
                // Every kind of block once (plateau pair, staircase,
                // modulation, reversals) in random order, more plateau pairs
                // up to ~55 % of the record, then the ramps.
                let mut blocks: Vec<u8> = vec![0, 1, 2, 3];
                shuffle(&mut blocks, &mut rng);
                for b in blocks {
                    match b {
                        0 => plateau_pair(&mut queue, c, &mut rng, 5.0),
                        1 => staircase(&mut queue, c, &mut rng, true),
                        2 => modulation(&mut queue, c, &mut rng),
                        _ => reversals(&mut queue, c, &mut rng),
                    }
                }
                while total(&queue) < 0.55 * d {
                    plateau_pair(&mut queue, c, &mut rng, 5.0);
                }
                let budget = (d - total(&queue) - 1.0).max(0.3 * d);
                ramps(&mut queue, c, &mut rng, 3, budget, false);
            }
            Family::VelocityLoop => {
                staircase(&mut queue, c, &mut rng, false);
                while total(&queue) < 0.8 * d {
                    match rng.gen_range(0..3) {
                        0 => plateau_pair(&mut queue, c, &mut rng, 0.5),
                        1 => staircase(&mut queue, c, &mut rng, false),
                        _ => {
                            // Direct reversal without a stop.
                            let v = lu(&mut rng, 0.5 * c.v_s, 30.0 * c.v_s) * sign(&mut rng);
                            let dur = uni(&mut rng, 0.3, 1.5).min(DIST_CAP / v.abs());
                            queue.push_back(Seg::Plateau { v, dur });
                            queue.push_back(Seg::Plateau { v: -v, dur });
                            queue.push_back(Seg::Rest {
                                dur: lu(&mut rng, 0.05, 0.5),
                            });
                        }
                    }
                }
            }
            Family::PointToPoint => {
                let mut side = sign(&mut rng);
                while total(&queue) < d {
                    let lo = (20.0 * c.z_max).max(100.0 * c.q);
                    let dist = lu(&mut rng, lo, 0.03_f64.max(2.0 * lo));
                    let target = side * dist;
                    if rng.gen_bool(0.8) {
                        side = -side;
                    }
                    let vmax = lu(&mut rng, c.v_s, 50.0 * c.v_s).max(dist / 3.0);
                    let acc = (vmax / uni(&mut rng, 0.05, 0.3)).min(c.fs / c.mass);
                    queue.push_back(Seg::MoveTo { target, vmax, acc });
                    queue.push_back(Seg::Rest {
                        dur: lu(&mut rng, 0.1, 2.0),
                    });
                }
            }
            Family::Ramps => {
                plateau_pair(&mut queue, c, &mut rng, 1.0);
                plateau_pair(&mut queue, c, &mut rng, 1.0);
                let n = rng.gen_range(4..=6);
                let budget = (d - total(&queue) - 1.0).max(4.0);
                ramps(&mut queue, c, &mut rng, n, budget, true);
            }
            Family::Sinusoid => {
                let n = rng.gen_range(3..=5);
                let budget = 0.7 * d;
                let mut freqs: Vec<f64> = (0..n).map(|_| lu(&mut rng, 0.05, 0.5)).collect();
                let per: f64 = freqs.iter().map(|f| 1.0 / f).sum();
                if per > budget {
                    for f in &mut freqs {
                        *f *= per / budget;
                    }
                }
                let force_at = rng.gen_range(0..n);
                for (i, freq) in freqs.into_iter().enumerate() {
                    let amp = lu(&mut rng, 0.25 * c.z_max, 150.0 * c.z_max)
                        .min(0.04)
                        .min(25.0 * c.v_s / (TAU * freq))
                        .min(c.a_lim() / (TAU * freq).powi(2))
                        .max(0.25 * c.z_max)
                        * sign(&mut rng);
                    queue.push_back(Seg::SineRef {
                        amp,
                        freq,
                        cycles: 1.0,
                    });
                    queue.push_back(Seg::Rest {
                        dur: uni(&mut rng, 0.3, 1.0),
                    });
                    if i == force_at {
                        sine_force(&mut queue, c, &mut rng);
                    }
                }
            }
            Family::Steady => {}
        }
        Schedule {
            family,
            ctx,
            rng,
            queue,
        }
    }

    /// The next segment (filler drawn when the queue is empty).
    pub fn next_seg(&mut self) -> Seg {
        if self.queue.is_empty() {
            let c = self.ctx;
            match self.family {
                Family::PointToPoint => {
                    let dist = lu(&mut self.rng, 20.0 * c.z_max, 0.01_f64.max(40.0 * c.z_max));
                    let target = sign(&mut self.rng) * dist;
                    let vmax = lu(&mut self.rng, c.v_s, 20.0 * c.v_s).max(dist / 3.0);
                    let acc = (vmax / 0.1).min(c.fs / c.mass);
                    self.queue.push_back(Seg::MoveTo { target, vmax, acc });
                    self.queue.push_back(Seg::Rest {
                        dur: lu(&mut self.rng, 0.1, 2.0),
                    });
                }
                Family::VelocityLoop => plateau_pair(&mut self.queue, &c, &mut self.rng, 0.5),
                _ => plateau_pair(&mut self.queue, &c, &mut self.rng, 5.0),
            }
        }
        self.queue.pop_front().unwrap_or(Seg::Rest { dur: 1.0 })
    }
}

fn shuffle<T>(v: &mut [T], rng: &mut ChaCha8Rng) {
    for i in (1..v.len()).rev() {
        let j = rng.gen_range(0..=i);
        v.swap(i, j);
    }
}

/// `+v` then `−v` plateaus of equal length, each followed by a rest of
/// 0.05 s … `rest_max` s.
fn plateau_pair(q: &mut VecDeque<Seg>, c: &Context, rng: &mut ChaCha8Rng, rest_max: f64) {
    let v = lu(rng, 0.3 * c.v_s, 50.0 * c.v_s) * sign(rng);
    let dur = uni(rng, 0.4, 1.5).min(DIST_CAP / v.abs()).max(0.15);
    q.push_back(Seg::Plateau { v, dur });
    q.push_back(Seg::Rest {
        dur: lu(rng, 0.05, rest_max),
    });
    q.push_back(Seg::Plateau { v: -v, dur });
    q.push_back(Seg::Rest {
        dur: lu(rng, 0.05, rest_max),
    });
}

/// A speed staircase up in one direction, then the same in the other.
fn staircase(q: &mut VecDeque<Seg>, c: &Context, rng: &mut ChaCha8Rng, rests: bool) {
    let n = rng.gen_range(3..=4);
    let lo = lu(rng, 0.3 * c.v_s, 3.0 * c.v_s);
    let hi = lu(rng, 5.0 * c.v_s, 50.0 * c.v_s);
    let s = sign(rng);
    for dir in [s, -s] {
        for i in 0..n {
            let v = lo * (hi / lo).powf(i as f64 / (n - 1) as f64);
            let dur = uni(rng, 0.25, 0.6).min(0.3 * DIST_CAP / v).max(0.1);
            q.push_back(Seg::Plateau { v: dir * v, dur });
        }
        q.push_back(Seg::Rest {
            dur: if rests {
                lu(rng, 0.05, 2.0)
            } else {
                lu(rng, 0.05, 0.5)
            },
        });
    }
}

/// A sinusoidal speed modulation in both directions.
fn modulation(q: &mut VecDeque<Seg>, c: &Context, rng: &mut ChaCha8Rng) {
    let v0 = lu(rng, 2.0 * c.v_s, 20.0 * c.v_s);
    let depth = uni(rng, 0.3, 0.8);
    let freq = uni(rng, 1.0, 3.0).min(c.a_lim() / (v0 * depth * TAU));
    let dur = uni(rng, 1.0, 2.0).min(DIST_CAP / v0).max(0.5);
    let s = sign(rng);
    for dir in [s, -s] {
        q.push_back(Seg::Modulated {
            v0: dir * v0,
            depth,
            freq,
            dur,
        });
        q.push_back(Seg::Rest {
            dur: lu(rng, 0.05, 2.0),
        });
    }
}

/// Slow sinusoidal reversals (a position sine over 2–3 cycles).
fn reversals(q: &mut VecDeque<Seg>, c: &Context, rng: &mut ChaCha8Rng) {
    let freq = uni(rng, 0.4, 1.2);
    let vpk = lu(rng, 1.0 * c.v_s, 20.0 * c.v_s);
    let amp = (vpk / (TAU * freq))
        .min(0.02)
        .min(c.a_lim() / (TAU * freq).powi(2))
        * sign(rng);
    q.push_back(Seg::SineRef {
        amp,
        freq,
        cycles: 2.0,
    });
    q.push_back(Seg::Rest {
        dur: lu(rng, 0.1, 1.0),
    });
}

/// Open-loop force ramps at `n` rates in both directions within `budget`
/// [s]; `varied` draws rests of 0.05–5 s before each ramp and starts half of
/// the ramps from the holding force.
fn ramps(
    q: &mut VecDeque<Seg>,
    c: &Context,
    rng: &mut ChaCha8Rng,
    n: usize,
    budget: f64,
    varied: bool,
) {
    let (t_lo, t_hi) = if varied { (0.2, 5.0) } else { (0.3, 3.0) };
    // Break times log-spaced with a random offset, each used in both directions.
    let base = lu(rng, t_lo, t_lo * 2.0);
    let ratio = (t_hi / base).powf(1.0 / (n.max(2) - 1) as f64);
    let mut times: Vec<f64> = (0..n).map(|i| base * ratio.powi(i as i32)).collect();
    let mut rests: Vec<f64> = (0..2 * n)
        .map(|_| {
            if varied {
                lu(rng, 0.05, 5.0)
            } else {
                lu(rng, 0.3, 1.5)
            }
        })
        .collect();
    let overhead = 0.8 * (2 * n) as f64;
    let need = 2.0 * times.iter().sum::<f64>() * 1.3 + rests.iter().sum::<f64>() + overhead;
    if need > budget {
        let k = ((budget - overhead) / (need - overhead)).clamp(0.05, 1.0);
        for t in &mut times {
            *t = (*t * k).max(0.1);
        }
        for r in &mut rests {
            *r = (*r * k).max(0.05);
        }
    }
    let mut order: Vec<(f64, f64)> = Vec::new();
    for &t in &times {
        order.push((t, 1.0));
        order.push((t, -1.0));
    }
    shuffle(&mut order, rng);
    for (i, (t, dir)) in order.into_iter().enumerate() {
        q.push_back(Seg::Rest { dur: rests[i] });
        if !varied && c.ramp_pause > 0.0 {
            q.push_back(Seg::Release {
                dur: c.ramp_pause.max(RELEASE),
            });
        }
        let rate = dir * c.fs / t;
        q.push_back(Seg::Ramp {
            rate,
            from_hold: varied && rng.gen_bool(0.5),
            t_max: 3.0 * c.fs / rate.abs() + 0.2,
        });
        q.push_back(Seg::Rest { dur: 0.3 });
        if varied {
            let vmax = lu(rng, c.v_s, 5.0 * c.v_s);
            q.push_back(Seg::MoveTo {
                target: 0.0,
                vmax,
                acc: (vmax / 0.1).min(c.fs / c.mass),
            });
        }
    }
}

/// One open-loop sine force, then a servo rest and a move home.
fn sine_force(q: &mut VecDeque<Seg>, c: &Context, rng: &mut ChaCha8Rng) {
    let freq = lu(rng, 0.1, 0.5);
    // Sliding speed stays below ~50 V when amp ≤ Fc + 50·V·m·π·f.
    let slide_max = (c.fc + 25.0 * c.v_s * c.mass * std::f64::consts::PI * freq).min(1.6 * c.fs);
    // Otherwise stay below Fc (presliding loops only).
    let amp = if slide_max > 1.1 * c.fs && rng.gen_bool(0.7) {
        uni(rng, 1.05 * c.fs, slide_max)
    } else {
        uni(rng, 0.3, 0.9) * c.fc
    };
    q.push_back(Seg::Rest { dur: 0.3 });
    q.push_back(Seg::SineForce {
        amp,
        freq,
        cycles: f64::from(rng.gen_range(1..=2)),
    });
    q.push_back(Seg::Rest { dur: 0.5 });
    let vmax = lu(rng, c.v_s, 10.0 * c.v_s);
    q.push_back(Seg::MoveTo {
        target: 0.0,
        vmax,
        acc: (vmax / 0.1).min(c.fs / c.mass),
    });
    q.push_back(Seg::Rest { dur: 0.3 });
}

/// The controller type.
#[derive(Clone, Copy, Debug, PartialEq)]
enum LoopKind {
    Position,
    Velocity,
}

/// Active segment with its run-time data.
#[derive(Clone, Copy, Debug)]
struct Active {
    seg: Seg,
    k0: usize,
    /// Start position reference / measured position [m].
    x0: f64,
    /// Ramp start force [N].
    u0: f64,
    /// Move profile: direction, accel time, cruise time, peak speed, acc.
    prof: (f64, f64, f64, f64, f64),
}

/// The digital controller and the segment player.
struct Player {
    kind: LoopKind,
    ctx: Context,
    sched: Schedule,
    active: Option<Active>,
    closed: bool,
    x_ref: f64,
    v_ref: f64,
    a_ref: f64,
    integ: f64,
    y_prev: f64,
    v_filt: f64,
    u_last: f64,
    y_hist: VecDeque<f64>,
    slew: f64,
}

impl Player {
    fn new(family: Family, ctx: Context, sched: Schedule) -> Self {
        let kind = if family == Family::VelocityLoop {
            LoopKind::Velocity
        } else {
            LoopKind::Position
        };
        Player {
            kind,
            ctx,
            sched,
            active: None,
            closed: true,
            x_ref: 0.0,
            v_ref: 0.0,
            a_ref: 0.0,
            integ: 0.0,
            y_prev: 0.0,
            v_filt: 0.0,
            u_last: 0.0,
            y_hist: VecDeque::with_capacity(16),
            slew: (50.0 * ctx.v_s / 0.15).min(ctx.a_lim()),
        }
    }

    fn close_loop(&mut self, y: f64) {
        self.closed = true;
        self.x_ref = y;
        self.v_ref = 0.0;
        self.a_ref = 0.0;
        self.integ = 0.0;
        self.v_filt = 0.0;
    }

    fn start(&mut self, seg: Seg, k: usize, y: f64) -> Active {
        let mut a = Active {
            seg,
            k0: k,
            x0: self.x_ref,
            u0: 0.0,
            prof: (0.0, 0.0, 0.0, 0.0, 0.0),
        };
        match seg {
            Seg::Ramp { from_hold, .. } => {
                a.x0 = y;
                a.u0 = if from_hold { self.u_last } else { 0.0 };
                self.closed = false;
            }
            Seg::SineForce { .. } => {
                a.x0 = y;
                self.closed = false;
            }
            Seg::Release { .. } => {
                a.x0 = y;
                a.u0 = self.u_last;
                self.closed = false;
            }
            Seg::MoveTo { target, vmax, acc } => {
                let dist = target - self.x_ref;
                let dir = dist.signum();
                let dist = dist.abs();
                // Long moves are sped up to take about 2 s.
                let vmax = vmax.max(dist / 2.0);
                let acc = acc
                    .max(vmax / 0.3)
                    .min(acc.max(self.ctx.fs / self.ctx.mass));
                let (ta, tc, vp) = if dist >= vmax * vmax / acc {
                    (vmax / acc, (dist - vmax * vmax / acc) / vmax, vmax)
                } else {
                    let vp = (dist * acc).sqrt();
                    (vp / acc, 0.0, vp)
                };
                a.prof = (dir, ta, tc, vp, acc);
            }
            _ => {}
        }
        a
    }

    /// Whether the active segment is over at sample `k` with measurement `y`.
    fn finished(&self, a: &Active, k: usize, y: f64) -> bool {
        let tau = (k - a.k0) as f64 * DT;
        match a.seg {
            Seg::Rest { dur }
            | Seg::Release { dur }
            | Seg::Plateau { dur, .. }
            | Seg::Modulated { dur, .. } => tau >= dur,
            Seg::SineRef { freq, cycles, .. } | Seg::SineForce { freq, cycles, .. } => {
                tau >= cycles / freq
            }
            Seg::MoveTo { .. } => {
                let (_, ta, tc, _, _) = a.prof;
                tau >= 2.0 * ta + tc
            }
            Seg::Ramp { rate, t_max, .. } => {
                let dir = rate.signum();
                let d_stop = 3.0 * self.ctx.z_max + 20.0 * self.ctx.q;
                let u = a.u0 + rate * tau;
                // Broken away: moved on, with a force that can break the
                // axis free (creep under a small force does not stop it).
                let moved = dir * (y - a.x0) > d_stop && dir * u >= 0.5 * self.ctx.fc;
                tau >= t_max || moved || u.abs() >= self.ctx.u_max
            }
        }
    }

    /// Velocity reference command of a closed-loop segment at `tau` [s].
    fn command(&self, a: &Active, tau: f64) -> f64 {
        match a.seg {
            Seg::Plateau { v, .. } => v,
            Seg::Modulated {
                v0, depth, freq, ..
            } => v0 * (1.0 + depth * (TAU * freq * tau).sin()),
            Seg::SineRef { amp, freq, .. } => amp * TAU * freq * (TAU * freq * tau).sin(),
            Seg::MoveTo { .. } => {
                let (dir, ta, tc, vp, acc) = a.prof;
                let v = if tau < ta {
                    acc * tau
                } else if tau < ta + tc {
                    vp
                } else {
                    (vp - acc * (tau - ta - tc)).max(0.0)
                };
                dir * v
            }
            _ => 0.0,
        }
    }

    fn update(&mut self, k: usize, y: f64) -> f64 {
        if self.y_hist.len() == 11 {
            self.y_hist.pop_front();
        }
        self.y_hist.push_back(y);
        loop {
            if let Some(a) = self.active {
                if self.finished(&a, k, y) {
                    if !self.closed {
                        self.close_loop(y);
                    }
                    self.active = None;
                    continue;
                }
                break;
            }
            let seg = self.sched.next_seg();
            if std::env::var_os("BREAKAWAY_GEN_TRACE").is_some() {
                eprintln!("{:8.3} {:?}", k as f64 * DT, seg);
            }
            let a = self.start(seg, k, y);
            self.active = Some(a);
        }
        let a = match self.active {
            Some(a) => a,
            None => return 0.0,
        };
        let tau = (k - a.k0) as f64 * DT;
        let c = self.ctx;
        let v_raw = if k == 0 { 0.0 } else { (y - self.y_prev) / DT };
        self.y_prev = y;
        let u = if self.closed {
            // Slew-limited velocity reference; x_ref integrates it (trapezoid).
            let cmd = self.command(&a, tau);
            let lim = match a.seg {
                Seg::MoveTo { acc, .. } => 1.5 * acc,
                Seg::SineRef { amp, freq, .. } => 1.5 * amp.abs() * (TAU * freq).powi(2),
                _ => self.slew,
            }
            .max(self.slew);
            let v_new = self.v_ref + (cmd - self.v_ref).clamp(-lim * DT, lim * DT);
            self.a_ref = (v_new - self.v_ref) / DT;
            self.x_ref += 0.5 * (self.v_ref + v_new) * DT;
            self.v_ref = v_new;
            let ff = c.mass * self.a_ref;
            match self.kind {
                LoopKind::Position => {
                    let (kv, kp, ki) = c.gains;
                    let e = self.x_ref - y;
                    let lin = kv * (self.v_ref - v_raw) + kp * e + ki * self.integ + ff;
                    let sat = lin.abs() >= c.u_max;
                    if !(sat && lin.signum() == e.signum()) {
                        self.integ += e * DT;
                    }
                    lin
                }
                LoopKind::Velocity => {
                    let (kv, ki) = c.vgains;
                    let tf = 0.002;
                    self.v_filt += (v_raw - self.v_filt) * DT / (tf + DT);
                    let e = self.v_ref - self.v_filt;
                    let lin = kv * e + ki * self.integ + ff;
                    let sat = lin.abs() >= c.u_max;
                    if !(sat && lin.signum() == e.signum()) {
                        self.integ += e * DT;
                    }
                    lin
                }
            }
        } else {
            match a.seg {
                Seg::Ramp { rate, .. } => a.u0 + rate * tau,
                Seg::SineForce { amp, freq, .. } => amp * (TAU * freq * tau).sin(),
                Seg::Release { .. } => a.u0 * (1.0 - tau / RELEASE).max(0.0),
                _ => 0.0,
            }
        };
        let u = u.clamp(-c.u_max, c.u_max);
        self.u_last = u;
        u
    }
}

/// Encoder jitter on the measurement (the `noisy_velocity` plant).
#[derive(Clone, Debug)]
pub struct Jitter {
    /// Probability of a ±1-count error per sample.
    pub prob: f64,
    /// Random stream.
    pub rng: ChaCha8Rng,
}

/// The outcome of one simulated record.
#[derive(Clone, Debug, Default)]
pub struct SimOut {
    /// Applied force per sample [N] (clean, held over the next interval).
    pub u: Vec<f64>,
    /// Logged position per sample [m] (quantised, with jitter when asked).
    pub x: Vec<f64>,
    /// RMS over the samples of each hidden effect's force [N].
    pub effect_rms: Vec<f64>,
    /// Range of the true encoder position [m].
    pub x_range: f64,
    /// Largest contact speed [m/s].
    pub v_max: f64,
    /// The plant's [`crate::plants::Plant::rest_log`] at the end.
    pub rest_log: Vec<(f64, bool)>,
}

/// Why a simulation was given up.
#[derive(Clone, Debug, PartialEq)]
pub struct Unstable(pub String);

/// Quantises `x` [m] to the encoder count `q` [m].
pub fn quantise(x: f64, q: f64) -> f64 {
    (x / q).round() * q
}

/// Plays `family` on `plant` for `ctx.duration` s: each sample reads the
/// encoder, the controller computes `u` (held for the interval), the plant
/// integrates the interval. `n_hidden` effect forces are accumulated.
pub fn run(
    family: Family,
    ctx: Context,
    sched_rng: ChaCha8Rng,
    plant: &mut dyn Plant,
    n_hidden: usize,
    mut jitter: Option<Jitter>,
) -> Result<SimOut, Unstable> {
    let n = (ctx.duration / DT).round() as usize;
    let sched = Schedule::new(family, ctx, sched_rng);
    let mut player = Player::new(family, ctx, sched);
    let mut out = SimOut {
        u: Vec::with_capacity(n),
        x: Vec::with_capacity(n),
        effect_rms: vec![0.0; n_hidden],
        ..SimOut::default()
    };
    let mut diffs = vec![0.0; n_hidden];
    let mut sums = vec![0.0; n_hidden];
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    let v_lim = 1000.0 * ctx.v_s + 1.0;
    for k in 0..n {
        let xe = plant.encoder();
        lo = lo.min(xe);
        hi = hi.max(xe);
        let mut y = quantise(xe, ctx.q);
        if let Some(j) = jitter.as_mut() {
            if j.rng.gen_bool(j.prob) {
                y += if j.rng.gen_bool(0.5) { ctx.q } else { -ctx.q };
            }
        }
        let u = player.update(k, xe);
        out.u.push(u);
        out.x.push(y);
        let v = plant.interval(u, &mut diffs);
        for (s, d) in sums.iter_mut().zip(&diffs) {
            *s += d * d;
        }
        out.v_max = out.v_max.max(v.abs());
        if !plant.finite() || v.abs() > v_lim || plant.encoder().abs() > 5.0 {
            return Err(Unstable(format!(
                "state ran away at t = {:.3} s (v = {v:e} m/s)",
                k as f64 * DT
            )));
        }
    }
    for (r, s) in out.effect_rms.iter_mut().zip(&sums) {
        *r = (s / n as f64).sqrt();
    }
    out.x_range = hi - lo;
    out.rest_log = plant.rest_log().to_vec();
    Ok(out)
}
