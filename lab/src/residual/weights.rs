//! The weights and the floor of a prepared record ([`Prepared`]): the
//! split into training and held-out blocks, the speed/direction classes,
//! the error weights from a model's residual, the stops, and the part of a
//! weighted RMS that noise and encoder resolution explain.

use super::*;

impl Prepared {
    /// Cuts the record into [`BLOCKS`] consecutive blocks that hold equal
    /// numbers of scored samples (valid and not window-still) and holds out
    /// every [`HELD_OUT_EVERY`]th ([`held_out_block`]). Equal time blocks
    /// would let a record that rests most of the time (a sinusoidal force
    /// mostly below break-away, a servo that holds for seconds) put none
    /// of its motion into the held-out blocks, and every figure would then
    /// compare nothing. With fewer scored samples than blocks the cut falls
    /// back to equal time.
    pub(super) fn set_split(&mut self) {
        let n = self.len();
        let valid = self.valid();
        let is_scored: Vec<bool> = (0..n)
            .map(|i| valid.contains(&i) && !self.still[i])
            .collect();
        let scored = is_scored.iter().filter(|s| **s).count();
        let (t0, t1) = (self.t[0], self.t[n - 1]);
        let mut before = 0;
        for (i, counts) in is_scored.into_iter().enumerate() {
            let b = if scored >= BLOCKS {
                before * BLOCKS / scored
            } else {
                (((self.t[i] - t0) / (t1 - t0)) * BLOCKS as f64) as usize
            };
            self.held_out[i] = held_out_block(b.min(BLOCKS - 1));
            before += usize::from(counts);
        }
    }

    /// Speed/direction class of a sample (for the weights).
    pub(super) fn class(&self, i: usize) -> usize {
        let s = self.v[i].abs();
        if s <= self.v_rest {
            return 0;
        }
        let b = ((s / self.v_rest).ln() / 3f64.ln())
            .floor()
            .clamp(0.0, 30.0) as usize;
        1 + 2 * b + usize::from(self.v[i] < 0.0)
    }

    /// Takes the weight off the [`Prepared::bursts`] (class weights now;
    /// the error weights, set later, keep it off).
    pub fn unweigh_bursts(&mut self) {
        self.bursts_unweighted = true;
        self.set_weights();
    }

    /// Whether the bursts carry no weight ([`Prepared::unweigh_bursts`]).
    pub fn bursts_unweighted(&self) -> bool {
        self.bursts_unweighted
    }

    /// Moving samples (valid, not still) within the kernel of a burst.
    pub fn burst_count(&self) -> usize {
        self.valid()
            .filter(|&i| self.bursts[i] && !self.still[i])
            .count()
    }

    pub(super) fn set_weights(&mut self) {
        let unscored = |p: &Self, i: usize| p.still[i] || (p.bursts_unweighted && p.bursts[i]);
        let mut count = [0usize; 64];
        for i in self.valid().filter(|&i| !unscored(self, i)) {
            count[self.class(i)] += 1;
        }
        let mut total = 0.0;
        for i in self.valid() {
            self.weight[i] = if !unscored(self, i) {
                1.0 / (count[self.class(i)] as f64).sqrt()
            } else {
                0.0
            };
            total += self.weight[i];
        }
        let nv = self.valid().filter(|&i| !unscored(self, i)).count() as f64;
        if total > 0.0 {
            for w in &mut self.weight {
                *w *= nv / total;
            }
        }
    }

    /// Error-in-variables weights for model `m` with residual `r` (of `m`).
    /// The residual of a correct model at moving sample `i` has variance
    ///
    /// ```text
    /// var_i = σ0² + (q²/12)·(Σ_j W_j·|∂F/∂x|_{i+j})² + σ_v²·(Σ_j W_j·|∂F/∂v|_{i+j})²
    ///             + (1/12)·(Σ_j W_j·ΔF_{i+j})² + (1/12)·(Σ_j W_j·U_{i+j})²
    /// ```
    ///
    /// * `σ0` [N]: the force noise through the kernel, the lower of two
    ///   upper bounds: differences of the residual `2K+1` samples apart in
    ///   fast sliding (a robust median; a missing effect that varies along
    ///   the motion inflates it, which on a heavy axis with a position
    ///   ripple made it 250× the noise through the kernel and hid every effect), and
    ///   `σ_f·‖W‖` with `σ_f` from the logged force ([`force_noise`]);
    /// * `q` [m] the encoder count, propagated through the presliding
    ///   stiffness `∂H/∂x = (d·S − H_r)·(−ln w)/z_max` (huge right after a
    ///   turning point);
    /// * `σ_v = q·‖c1‖/(√12·h)` [m/s], the quantisation error of the
    ///   Savitzky–Golay velocity, propagated through the slope of the
    ///   Stribeck curve `g(w)·|S'(v)|`;
    /// * `ΔF = (|∂F/∂x|·|v̂| + |∂F/∂v|·|â|)·h` [N], how far the friction
    ///   moves within one sample period `h` (version 6.4): the residual
    ///   takes the force at the sample instants while the motion
    ///   integrates it over the period, so a presliding branch crossed in
    ///   a fraction of a period is known at its samples only to about that
    ///   change (on three effect-free development records of the MODEL.md
    ///   plant where `frictional_lag` was named falsely, the generator's
    ///   own model had 0.06–0.23 N of model error without this term,
    ///   0.008–0.13 N with it);
    /// * `U = 2·max(Fs, Fc)` [N] at moving samples slower than one count per
    ///   sample, 0 elsewhere (version 7.0): there the axis may stick, slip
    ///   and reverse by less than a count between two samples, unseen, and
    ///   the presliding memory is anywhere in its range (on a servo record
    ///   of the development draws with a position ripple, the generator's
    ///   plant reversed in bursts of about 1 ms while the counts fell
    ///   steadily; its own model's error was 0.21 N without this term,
    ///   0.040 N with it). The weights keep the whole range; the floor
    ///   (version 7.4, [`Prepared::floor_var`]) takes `U` only as far as
    ///   the start model's residual shows it at slow samples
    ///   (`Prepared::slow_spread`): on slow sinusoids the whole range
    ///   made the floor 30× what the generator's own model left (0.48 N
    ///   against 0.016 N), so no effect there could be named.
    ///
    /// Each sample's class weight is multiplied by `σ0²/var_i` (≤ 1); the
    /// variances are kept ([`Prepared::var`], and [`Prepared::floor_var`]
    /// for [`Prepared::floor`]). Called once per record
    /// (from the start model), so every figure compared afterwards uses the
    /// same weights. Returns `σ0`.
    pub fn set_error_weights(&mut self, m: &Model, r: &[f64]) -> f64 {
        self.mark_stops(m);
        let lag = 2 * self.kf + 1;
        let q2 = self.resolution * self.resolution / 12.0;
        // Quantisation error of `m·â`: present wherever a second difference
        // of the counts falls inside the window (an exactly constant count
        // rate has none).
        let c2_norm = self.c2_norm();
        let var_acc = m.mass * m.mass * q2 * (c2_norm / (self.dt * self.dt)).powi(2);
        let n = self.len();
        let curved = spread(
            n,
            (1..n.saturating_sub(1))
                .filter(|&i| self.x[i + 1] - 2.0 * self.x[i] + self.x[i - 1] != 0.0),
            self.kf + 1,
        );
        let fast = self.median_moving_speed().unwrap_or(0.0);
        let pairs = |straight: bool| -> Vec<f64> {
            let mut d: Vec<f64> = self
                .valid()
                .filter(|&i| i + lag < self.valid().end)
                .filter(|&i| self.v[i].abs() >= fast && self.v[i + lag].abs() >= fast)
                .filter(|&i| !self.still[i] && !self.still[i + lag])
                .filter(|&i| !straight || !(curved[i] || curved[i + lag]))
                .map(|i| (r[i] - r[i + lag]).abs())
                .collect();
            d.sort_by(f64::total_cmp);
            d
        };
        let robust = |d: &[f64]| {
            d.get(d.len() / 2)
                .map(|med| med / (0.6745 * std::f64::consts::SQRT_2))
        };
        // The force noise: from windows without count curvature when the
        // record has enough of them, else from all fast windows less the
        // quantisation part.
        let straight = pairs(true);
        // The force noise seen through the kernel, from the logged force
        // alone: an upper bound too (Δ³u also holds the command's own fast
        // variations), but one that no missing effect inflates. The lower
        // of the two bounds is taken.
        let from_data = self.force_noise * self.kernel_norm();
        let sigma0 = match robust(&straight) {
            Some(s) if straight.len() >= 200 && s > 0.0 => s,
            _ => match robust(&pairs(false)) {
                Some(s) if s > 0.0 => (s * s - var_acc).max(0.01 * s * s).sqrt(),
                _ => 1e-3 * m.fc,
            },
        };
        let sigma0 = if from_data > 0.0 {
            sigma0.min(from_data)
        } else {
            sigma0
        };
        let (sx, sv) = self.sensitivities(m);
        // How far the friction moves within one sample period,
        // `|∂F/∂x|·|v̂|·h + |∂F/∂v|·|â|·h` [N]: the residual compares
        // the force at the sample instants with the motion, which
        // integrates it over the period, so a friction that changes by
        // more than the noise within a period (a presliding branch crossed
        // in a fraction of a period, a steep Stribeck slope under a fast
        // acceleration) is known at the sample only to about that change.
        let within: Vec<f64> = (0..n)
            .map(|i| (sx[i] * self.v[i].abs() + sv[i] * self.a[i].abs()) * self.dt)
            .collect();
        // Where the axis moves by less than a count per sample and is not
        // still, it may stick and slip, and reverse, between two samples
        // by less than a count (a limit cycle faster than the sampling,
        // which the counts cannot show): the presliding memory, and with
        // it the dry friction, is then anywhere between −S and S. Such a
        // sample's friction is known only to that range, `2·max(Fs, Fc)`
        // [N] (`2·Fs` for a model with Fs ≥ Fc).
        let range = 2.0 * m.fs.max(m.fc);
        let slow = |i: usize| self.v[i].abs() * self.dt < self.resolution && !self.still[i];
        let hidden_reversal: Vec<f64> = (0..n).map(|i| if slow(i) { range } else { 0.0 }).collect();
        // How much of that range the record shows (a fraction), for the
        // floor only: the weights keep the whole range.
        let shown = range.min(self.slow_spread(r, &slow).unwrap_or(range)) / range;
        // Neither term below can exceed the friction's whole range.
        let cap = range * range;
        let c1_norm = 1.0 / ((self.k * (self.k + 1) * (2 * self.k + 1)) as f64 / 3.0).sqrt();
        let sigma_v2 = q2 * (c1_norm / self.dt).powi(2);
        self.set_weights();
        self.sigma0 = sigma0;
        for i in self.valid() {
            let a = self.filter_at(&sx, i).abs();
            let b = self.filter_at(&sv, i).abs();
            let c = self.filter_at(&within, i);
            let d = self.filter_at(&hidden_reversal, i);
            let acc = if curved[i] { var_acc } else { 0.0 };
            let known = sigma0 * sigma0
                + acc
                + (q2 * a * a).min(cap)
                + (sigma_v2 * b * b).min(cap)
                + (c * c / 12.0).min(cap);
            let hidden = (d * d / 12.0).min(cap);
            self.var[i] = known + hidden;
            self.floor_var[i] = known + hidden * shown * shown;
            self.weight[i] *= sigma0 * sigma0 / self.var[i];
        }
        sigma0
    }

    /// The hidden-reversal range [N] that the residual `r` of the start
    /// model shows at the slow moving samples (`slow`): `√12·σ`, σ from
    /// the [`SLOW_QUANTILE`] of `|r_i − r_{i+2K+1}|` over pairs of slow
    /// samples (`z·√2·σ` for Gaussian differences), the same kernel span
    /// apart as the noise pairs of [`Prepared::set_error_weights`], so
    /// that a disagreement that varies slower than the kernel (a missing
    /// effect) cancels and stick-slip faster than the sampling does not;
    /// `None` with fewer than [`MIN_SLOW_PAIRS`] pairs.
    pub(super) fn slow_spread(&self, r: &[f64], slow: &dyn Fn(usize) -> bool) -> Option<f64> {
        let lag = 2 * self.kf + 1;
        let end = self.valid().end;
        let mut d: Vec<f64> = self
            .valid()
            .filter(|&i| i + lag < end && slow(i) && slow(i + lag))
            .map(|i| (r[i] - r[i + lag]).abs())
            .collect();
        if d.len() < MIN_SLOW_PAIRS {
            return None;
        }
        Some(12f64.sqrt() * quantile(&mut d, SLOW_QUANTILE) / (SLOW_Z * std::f64::consts::SQRT_2))
    }

    /// Adds the **stops** of the motion to the still samples: a sample
    /// whose position stays on one count over `i−2 … i+2`
    /// ([`STOP_HALF_WIDTH`]) while model `m`, run along the counts, is in
    /// gross sliding (w = 1). The axis has come to rest on that count
    /// (usually after a reversal smaller than a count, which the counts do
    /// not show), so its friction is the holding force; the model, which
    /// sees no reversal, would go on with `±S(v̂)` at the velocity the
    /// window still reports, a disagreement of up to `Fs + |u|` that no
    /// friction effect explains. Such samples are re-anchored and not
    /// scored, like the window-still ones. Inside presliding the rule
    /// does not apply: there the branch itself is the slow motion, and
    /// re-anchoring would restart it. Called once per record from the start
    /// model (from [`Prepared::set_error_weights`]), so every model compared
    /// on the record sees the same still samples.
    pub fn mark_stops(&mut self, m: &Model) {
        let n = self.len();
        // The model velocity changes with the still samples.
        self.terms.clear();
        self.still.clone_from(&self.window_still);
        let h = STOP_HALF_WIDTH;
        let valid = self.valid();
        let mut fr = Friction::new(m, self.t[0], self.x[0], self.model_velocity(0));
        for i in 0..n {
            fr.update(m, self.t[i], self.x[i], self.model_velocity(i));
            if !self.still[i] && valid.contains(&i) && i >= h && i + h < n {
                let on_count = self.x[i - h..=i + h].iter().all(|&x| x == self.x[i]);
                let pre = fr.presliding();
                if on_count && pre.direction() != 0 && pre.travel(m.z_max, self.x[i]) >= 1.0 {
                    self.still[i] = true;
                    let span = &self.u_mid[i - 2..=i];
                    self.u_still[i] = span.iter().sum::<f64>() / span.len() as f64;
                }
            }
            if self.still[i] {
                let additive = fr.force() - fr.dry();
                fr.anchor(self.x[i], self.u_still[i] - additive);
            }
        }
    }

    /// `‖c2‖`, the norm of the Savitzky–Golay second-derivative
    /// coefficients (per sample²).
    pub(super) fn c2_norm(&self) -> f64 {
        let kf = self.kf as f64;
        let mu2 = kf * (kf + 1.0) / 3.0;
        let d: f64 = (0..=2 * self.kf)
            .map(|i| (i as f64 - kf).powi(2) - mu2)
            .map(|e| e * e)
            .sum();
        2.0 / d.sqrt()
    }

    /// The part of the weighted RMS [N] that noise and resolution explain:
    /// `√(Σ c_i·w_i·v_i / Σ c_i·w_i)` over the samples selected by
    /// `held_out` (`c` class weight, `w = σ0²/var` the error factor, `v`
    /// [`Prepared::floor_var`]), what a correct model would show. 0 before
    /// [`Prepared::set_error_weights`].
    pub fn floor(&self, held_out: Option<bool>) -> f64 {
        let (mut s, mut w) = (0.0, 0.0);
        for i in self.valid() {
            if held_out.is_none_or(|h| self.held_out[i] == h) {
                s += self.weight[i] * self.floor_var[i];
                w += self.weight[i];
            }
        }
        if w > 0.0 {
            (s / w).sqrt()
        } else {
            0.0
        }
    }
}
