//! The model along the measured motion ([`Prepared`]): the velocity the
//! friction is evaluated at, the rest clock, the walk of the friction
//! memory, its cached terms and sensitivities, and the model force.

use super::*;

impl Prepared {
    /// The velocity [m/s] the model runs at on sample `i`: `v̂`, and 0 on
    /// the still samples. MODEL.md §5: in measured data a rest is where the
    /// position stays within the encoder's resolution, so the lagged
    /// velocity at rest must not follow the ±1-count dither of a held axis,
    /// whose `v̂` is about `q/(k·h)`. (At still samples the friction is the
    /// measured force in any case. The `dwell_stiction` clock takes its
    /// speed from [`Prepared::rest_speed`] instead.)
    pub fn model_velocity(&self, i: usize) -> f64 {
        if self.still[i] {
            0.0
        } else {
            self.v[i]
        }
    }

    /// The speed [m/s] that the `dwell_stiction` clock compares with
    /// `v_rest` at sample `i` ([`Prepared::count_period_speed`]).
    pub fn rest_speed(&self, i: usize) -> f64 {
        self.rest_speed[i]
    }

    /// The rests of at least [`MIN_DWELL_REST`] that end in motion, as a
    /// `dwell_stiction` clock with `v_rest` [m/s] counts them (rest while
    /// [`Prepared::rest_speed`] `≤ v_rest`; the record starts at rest):
    /// `(shortest, longest [s], how many)`, or `None` without such a rest.
    pub fn rests(&self, v_rest: f64) -> Option<(f64, f64, usize)> {
        let mut start: Option<f64> = Some(self.t[0]);
        let (mut lo, mut hi, mut n) = (f64::INFINITY, f64::NEG_INFINITY, 0);
        for i in 0..self.len() {
            if self.rest_speed(i) <= v_rest {
                start.get_or_insert(self.t[i]);
            } else if let Some(s) = start.take() {
                let td = self.t[i] - s;
                if td >= MIN_DWELL_REST {
                    lo = lo.min(td);
                    hi = hi.max(td);
                    n += 1;
                }
            }
        }
        (n > 0).then_some((lo, hi, n))
    }

    /// Speed [m/s] of the axis for the `dwell_stiction` clock at every
    /// sample of the positions `xs` [m] at times `t` [s], `q` [m] the
    /// encoder count, from the counts alone (the encoder's period, "1/T",
    /// estimate). A **stay** is a run of samples on one count. The speed
    /// over a stay is the step that ends it over the time from the change
    /// that began it, when both changes go the same way (the axis crossed
    /// the whole count); 0 when they go opposite ways (the axis turned
    /// within the count, through zero velocity, and may have moved no more
    /// than a hair either side of a count boundary). The first stay counts
    /// from the record's start, the last one to its end with the last step;
    /// a record that never changes its count has speed 0. At the sample of
    /// a count change the speed is the larger of the stays on either side,
    /// and at least the step less one count over one sample period (a jump
    /// of several counts within a sample is fast motion).
    ///
    /// MODEL.md §5 counts a rest while `|v| ≤ v_rest`, with `v_rest`
    /// usually well below a count per sample. A slow presliding creep
    /// crosses counts at such speeds: `v̂` over the window around each
    /// change reads about a count per window, which would restart the
    /// clock at every count although the axis never moved faster than a
    /// count per stay. An axis that settles on a count after a move is
    /// still moving while its stays are short, and its rest starts with
    /// the first long stay; a dither on a count boundary is rest, and
    /// every reversal passes through rest, as it does in the model.
    /// (Dips below `v_rest` within a count, which restart the clock of a
    /// simulation, cannot be seen, but for the sticks below.)
    ///
    /// A **stick** (version 8.4): a stay that the axis crosses on its way
    /// (both changes the same way) but of at least [`STICK_MIN_STAY`]
    /// samples and [`STICK_RATIO`] times the stay before it counts as rest
    /// too. The count rate fell several-fold within one count, which a
    /// servo-driven axis does when it sticks for a few milliseconds after
    /// a break-away or in a jerky slow move: its velocity passed through
    /// `v_rest`, and MODEL.md's clock starts a new, short rest there,
    /// while the stay's mean speed, a count over its length, still reads
    /// above `v_rest`.
    pub fn count_period_speed(xs: &[f64], t: &[f64], q: f64) -> Vec<f64> {
        let n = xs.len();
        let changes: Vec<usize> = (1..n).filter(|&i| xs[i] != xs[i - 1]).collect();
        let mut speed = vec![0.0; n];
        let Some(&last) = changes.last() else {
            return speed;
        };
        let step = |c: usize| xs[c] - xs[c - 1];
        // Speed over the stay [begin, end): `begin` 0 or a change, `end` the
        // next change or `n`.
        let stay_speed = |begin: usize, end: usize| -> f64 {
            let (to, s) = if end < n {
                (end, step(end))
            } else {
                (n - 1, step(last))
            };
            let turned = begin > 0 && end < n && step(begin).signum() != s.signum();
            if turned || t[to] <= t[begin] {
                0.0
            } else {
                s.abs() / (t[to] - t[begin])
            }
        };
        let mut begin = 0;
        let mut before = 0.0;
        // Samples of the stay before, `None` for the record's first one.
        let mut previous: Option<usize> = None;
        for k in 0..=changes.len() {
            let end = changes.get(k).copied().unwrap_or(n);
            let mut stay = stay_speed(begin, end);
            let len = end - begin;
            if let Some(prev) = previous {
                // Crossed on the way, but far slower than the count before:
                // the axis stuck within it.
                if stay > 0.0 && end < n && stuck(len, prev) {
                    stay = 0.0;
                }
            }
            previous = (begin > 0).then_some(len);
            speed[begin..end].fill(stay);
            if begin > 0 {
                // (The loader admits only increasing times.)
                let jump = (step(begin).abs() - q).max(0.0) / (t[begin] - t[begin - 1]);
                speed[begin] = stay.max(before).max(jump);
            }
            before = stay;
            begin = end;
        }
        speed
    }

    /// Runs the friction memory of `m` along the measured motion and calls
    /// `f(i, &friction)` after each sample's update. After a still sample
    /// the memory is re-anchored at the measured force (see
    /// [`Prepared::still`]): dry friction `ū − (F − H)`, so that the
    /// friction there is `ū` and the next motion starts from it. Every pass
    /// of the lab over a record goes through here, so they all see the same
    /// memory.
    pub fn walk(&self, m: &Model, mut f: impl FnMut(usize, &Friction)) {
        let (v_s, delta) = (m.v_stribeck, m.delta);
        // The decay multiplies Fs − Fc (plus the dwell excess): without a
        // dip and without `dwell_stiction` it is never read.
        let needs_decay = m.fs != m.fc || m.effects.dwell_stiction.is_some();
        let decay = match m.effects.frictional_lag {
            _ if !needs_decay => None,
            None => Some(TermCache::get(
                &self.terms.decay,
                [v_s.to_bits(), delta.to_bits()],
                || {
                    // exp(−(|v|/V)^δ) as `exp(δ·(ln|v| − ln V))`.
                    let ln_v = v_s.ln();
                    let ln_speed = self.ln_speed();
                    ln_speed
                        .iter()
                        .map(|&l| decay_of_power((delta * (l - ln_v)).exp()))
                        .collect()
                },
            )),
            Some(lag) => Some({
                let key = [v_s.to_bits(), delta.to_bits(), lag.tau_l.to_bits()];
                TermCache::get(&self.terms.lagged_decay, key, || {
                    let lagged = self.lagged_velocity(lag.tau_l);
                    lagged
                        .iter()
                        .map(|&v_l| stribeck_decay(v_s, delta, v_l))
                        .collect()
                })
            }),
        };
        // The lagged velocity enters the force only through the decay, which
        // is given (or not read): the walk's own lag filter is skipped (its
        // exp and expm1 per sample, where the sampling period varies in its
        // last bits, were a tenth of EMPS's time).
        let lag_free;
        let m = if m.effects.frictional_lag.is_some() {
            let mut free = m.clone();
            free.effects.frictional_lag = None;
            lag_free = free;
            &lag_free
        } else {
            m
        };
        let speed_pow = m.effects.nonlinear_viscous.map(|nv| self.speed_pow(nv.n));
        let ripple_sin = m.effects.position_ripple.map(|r| {
            let key = [r.wavelength.to_bits(), r.phase.to_bits()];
            TermCache::get(&self.terms.ripple_sin, key, || {
                self.x
                    .iter()
                    .map(|&x| (2.0 * PI * x / r.wavelength + r.phase).sin())
                    .collect()
            })
        });
        let mut fr = Friction::new(m, self.t[0], self.x[0], self.model_velocity(0));
        for i in 0..self.len() {
            let terms = SampleTerms {
                decay: decay.as_ref().map(|d| d[i]),
                speed_pow: speed_pow.as_ref().map(|p| p[i]),
                rest_speed: Some(self.rest_speed[i]),
                ripple_sin: ripple_sin.as_ref().map(|r| r[i]),
            };
            fr.update_with(m, self.t[i], self.x[i], self.model_velocity(i), terms);
            f(i, &fr);
            if self.still[i] {
                let additive = fr.force() - fr.dry();
                fr.anchor(self.x[i], self.u_still[i] - additive);
            }
        }
    }

    /// `|v|^n` of [`Prepared::model_velocity`] at every sample (0 at still
    /// samples), as the walk's `nonlinear_viscous` term and its Jacobian
    /// column take it (cached by `n`).
    pub(crate) fn speed_pow(&self, n: f64) -> Arc<Vec<f64>> {
        TermCache::get(&self.terms.speed_pow, n.to_bits(), || {
            self.ln_speed().iter().map(|&l| (n * l).exp()).collect()
        })
    }

    /// `ln |v|` of [`Prepared::model_velocity`] at every sample (−∞ where
    /// it is 0), kept until the still samples change: the powers of the
    /// Stribeck decay and of `nonlinear_viscous` are taken as `exp(p·ln|v|)`
    /// from it (a `powf` per sample and shape was an eighth of a fit's
    /// time).
    pub(super) fn ln_speed(&self) -> Arc<Vec<f64>> {
        let mut cached = self
            .terms
            .ln_speed
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        Arc::clone(cached.get_or_insert_with(|| {
            Arc::new(
                (0..self.len())
                    .map(|i| self.model_velocity(i).abs().ln())
                    .collect(),
            )
        }))
    }

    /// The lagged velocity `v_l` [m/s] of `frictional_lag` with time
    /// constant `tau_l` [s] (a [`LagFilter`] over
    /// [`Prepared::model_velocity`]), cached by `tau_l`: the fit of V and δ
    /// walks many decays of one lag.
    fn lagged_velocity(&self, tau_l: f64) -> Arc<Vec<f64>> {
        TermCache::get(&self.terms.lagged_velocity, tau_l.to_bits(), || {
            let mut filter = LagFilter::new(self.t[0], self.model_velocity(0));
            (0..self.len())
                .map(|i| filter.update(Some(tau_l), self.t[i], self.model_velocity(i)))
                .collect()
        })
    }

    /// Per-sample `|∂H/∂x|` [N/m] of the presliding branch (0 in gross
    /// sliding; `w` at least half an encoder count from the turning point)
    /// and `|∂F/∂v|` [N·s/m] (the Stribeck slope times `g(w)`, plus σ) of
    /// model `m` along the motion, in one pass.
    pub fn sensitivities(&self, m: &Model) -> (Vec<f64>, Vec<f64>) {
        let n = self.len();
        let (mut sx, mut sv) = (vec![0.0; n], vec![0.0; n]);
        let w_min = if m.z_max > 0.0 {
            (0.5 * self.resolution / m.z_max).min(0.5)
        } else {
            1.0
        };
        self.walk(m, |i, fr| {
            let pre = fr.presliding();
            let d = pre.direction();
            let w = pre.travel(m.z_max, self.x[i]);
            let g = if d == 0 || m.z_max <= 0.0 {
                1.0
            } else {
                let w = w.max(1e-12);
                w * (1.0 - w.ln())
            };
            if m.z_max > 0.0 && (d == 0 || w < 1.0) {
                let w = w.max(w_min);
                let amp = if d == 0 {
                    (m.fs - fr.dry()).abs().max((m.fs + fr.dry()).abs())
                } else {
                    let gw = w * (1.0 - w.ln());
                    ((fr.dry() - pre.dry_at_turning_point()) / gw).abs()
                };
                sx[i] = amp * (-w.ln()) / m.z_max;
            }
            let s = self.v[i].abs() / m.v_stribeck;
            let slope = if s > 0.0 {
                (m.fs - m.fc) * m.delta / m.v_stribeck
                    * s.powf(m.delta - 1.0)
                    * (-s.powf(m.delta)).exp()
            } else {
                0.0
            };
            sv[i] = g * slope.min(1e12) + m.sigma;
        });
        (sx, sv)
    }

    /// The friction `F` of `m` along the measured motion, every sample
    /// ([`Prepared::walk`]: `F = ū` at still samples).
    pub fn friction(&self, m: &Model) -> Vec<f64> {
        let mut f = vec![0.0; self.len()];
        self.walk(m, |i, fr| {
            f[i] = if self.still[i] {
                self.u_still[i]
            } else {
                fr.force()
            }
        });
        f
    }

    /// `ū − F` of `m` at every sample [N], before the force kernel.
    pub(super) fn force_gap(&self, m: &Model) -> Vec<f64> {
        let f = self.friction(m);
        self.u_mid.iter().zip(&f).map(|(u, f)| u - f).collect()
    }
}
