//! Minimal SVG plots (no dependency): stacked panels of line and dot series
//! with auto-scaled axes.

use crate::diagnose::Report;
use std::fmt::Write as _;

/// One data series.
#[derive(Clone, Debug)]
pub struct Series {
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
    /// CSS colour.
    pub color: String,
    /// Dots instead of a polyline.
    pub dots: bool,
}

impl Series {
    /// A polyline.
    pub fn line(points: &[(f64, f64)], color: &str) -> Series {
        Series {
            points: points.to_vec(),
            color: color.into(),
            dots: false,
        }
    }

    /// Dots.
    pub fn dots(points: &[(f64, f64)], color: &str) -> Series {
        Series {
            points: points.to_vec(),
            color: color.into(),
            dots: true,
        }
    }

    /// The points with both coordinates finite (the others are not drawn).
    fn finite_points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
    }
}

/// One panel.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// Series drawn in order.
    pub series: Vec<Series>,
}

/// Width and height of a panel [px].
const W: f64 = 900.0;
const H: f64 = 260.0;
/// Left and top margin of the plot area [px] (the y tick labels, the title).
const ML: f64 = 70.0;
const MT: f64 = 30.0;
/// Width and height of the plot area [px]: 20 px are left on its right,
/// 30 px below it (the x tick labels).
const PW: f64 = W - ML - 20.0;
const PH: f64 = H - MT - 30.0;

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Renders panels stacked vertically.
pub fn render(panels: &[Panel]) -> String {
    let total = H * panels.len().max(1) as f64;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{W}\" height=\"{total}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (k, p) in panels.iter().enumerate() {
        let y0 = k as f64 * H;
        let pts = p.series.iter().flat_map(Series::finite_points);
        let (mut x0, mut x1, mut ya, mut yb) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for (x, y) in pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            ya = ya.min(y);
            yb = yb.max(y);
        }
        if !(x0.is_finite() && ya.is_finite()) {
            x0 = 0.0;
            x1 = 1.0;
            ya = 0.0;
            yb = 1.0;
        }
        if x1 <= x0 {
            x1 = x0 + 1.0;
        }
        if yb <= ya {
            yb = ya + 1.0;
        }
        let sx = |x: f64| ML + (x - x0) / (x1 - x0) * PW;
        let sy = |y: f64| y0 + MT + (yb - y) / (yb - ya) * PH;
        let _ = writeln!(
            s,
            "<text x=\"{ML}\" y=\"{:.1}\">{}</text>\n<rect x=\"{ML}\" y=\"{:.1}\" width=\"{PW}\" height=\"{PH}\" fill=\"none\" stroke=\"#999\"/>",
            y0 + 18.0,
            esc(&p.title),
            y0 + MT
        );
        for (v, anchor_y) in [(ya, sy(ya)), (yb, sy(yb))] {
            let _ = writeln!(
                s,
                "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
                ML - 4.0,
                anchor_y + 4.0,
                crate::format::short(v, 3)
            );
        }
        if ya < 0.0 && yb > 0.0 {
            let _ = writeln!(
                s,
                "<line x1=\"{ML}\" x2=\"{:.1}\" y1=\"{:.1}\" y2=\"{:.1}\" stroke=\"#ccc\"/>",
                ML + PW,
                sy(0.0),
                sy(0.0)
            );
        }
        for (v, ax) in [(x0, sx(x0)), (x1, sx(x1))] {
            let _ = writeln!(
                s,
                "<text x=\"{ax:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
                y0 + H - 10.0,
                crate::format::short(v, 4)
            );
        }
        for ser in &p.series {
            if ser.dots {
                for (x, y) in ser.finite_points() {
                    let _ = writeln!(
                        s,
                        "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"1.3\" fill=\"{}\" fill-opacity=\"0.5\"/>",
                        sx(x),
                        sy(y),
                        ser.color
                    );
                }
            } else {
                let mut d = String::new();
                for (x, y) in ser.finite_points() {
                    let _ = write!(
                        d,
                        "{}{:.1},{:.1}",
                        if d.is_empty() { "M" } else { " L" },
                        sx(x),
                        sy(y)
                    );
                }
                let _ = writeln!(
                    s,
                    "<path d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1\"/>",
                    ser.color
                );
            }
        }
    }
    s.push_str("</svg>\n");
    s
}

/// Min/max envelope of `y(t)` in `cols` columns (keeps spikes visible).
#[allow(clippy::needless_range_loop)]
fn envelope(t: &[f64], y: &[f64], cols: usize) -> Vec<(f64, f64)> {
    let n = t.len().min(y.len());
    if n == 0 {
        return Vec::new();
    }
    let per = n.div_ceil(cols.max(1)).max(1);
    let mut out = Vec::new();
    for c in (0..n).step_by(per) {
        let e = (c + per).min(n);
        let (mut lo, mut hi, mut ilo, mut ihi) = (f64::INFINITY, f64::NEG_INFINITY, c, c);
        for i in c..e {
            if y[i] < lo {
                lo = y[i];
                ilo = i;
            }
            if y[i] > hi {
                hi = y[i];
                ihi = i;
            }
        }
        let (a, b) = if ilo <= ihi { (ilo, ihi) } else { (ihi, ilo) };
        out.push((t[a], y[a]));
        if b != a {
            out.push((t[b], y[b]));
        }
    }
    out
}

/// Every `step`-th finite `(s, r)` pair, at most about `max` of them.
fn scatter(s: &[f64], r: &[f64], max: usize) -> Vec<(f64, f64)> {
    let idx: Vec<usize> = (0..s.len().min(r.len()))
        .filter(|&i| s[i].is_finite() && r[i] != 0.0)
        .collect();
    let step = idx.len().div_ceil(max.max(1)).max(1);
    idx.iter().step_by(step).map(|&i| (s[i], r[i])).collect()
}

/// The diagnose plot: residual before (grey) and after (blue) over time,
/// then per added effect the residual before that step (grey) and after
/// the final model (blue) against the signal that localised it.
pub fn diagnose_svg(rep: &Report) -> String {
    let mut panels = vec![Panel {
        title: format!(
            "force residual [N] over time [s]: start model (grey, held-out model error {} N) and final (blue, {} N)",
            crate::format::short(rep.rms_before, 3),
            crate::format::short(rep.rms_after, 3)
        ),
        series: vec![
            Series::line(&envelope(&rep.t, &rep.residual_before, 1200), "#999999"),
            Series::line(&envelope(&rep.t, &rep.residual_after, 1200), "#1f5fbf"),
        ],
    }];
    for st in &rep.steps {
        let name = &st.signal.0;
        let Some((_, s)) = rep.signal_series.iter().find(|(n, _)| n == name) else {
            continue;
        };
        panels.push(Panel {
            title: format!(
                "step `{}`: residual [N] against {name} — before the step (grey), final (blue)",
                st.effect
            ),
            series: vec![
                Series::dots(&scatter(s, &st.residual_before, 3000), "#999999"),
                Series::dots(&scatter(s, &rep.residual_after, 3000), "#1f5fbf"),
            ],
        });
    }
    render(&panels)
}
