//! Output: aligned text tables and JSON.
//!
//! JSON is written by `serde_json` from the structures below (shortest
//! round-trip `f64`, so full precision; a non-finite number would be written
//! as `null`), one object per line. Objects keep the key order documented in
//! the `--help` text and MODEL.md §4 names (the order of the fields).

use crate::commands::{BreakawayRow, ValidityBlock};
use crate::reference::Variant;
use serde::{Serialize, Serializer};
use std::fmt::Write as _;

/// `x` with `sig` significant digits, trailing zeros trimmed (like C's `%g`).
pub fn short(x: f64, sig: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let exp = x.abs().log10().floor();
    if (-4.0..15.0).contains(&exp) {
        let decimals = (sig as f64 - 1.0 - exp).max(0.0) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.prec$e}", prec = sig.saturating_sub(1))
    }
}

/// Renders rows as a table: a header line, then right-aligned columns
/// separated by two spaces (the first column left-aligned).
pub fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut out = String::new();
    let line = |out: &mut String, cells: &mut dyn Iterator<Item = &str>| {
        let mut first = true;
        let mut s = String::new();
        for (i, cell) in cells.enumerate() {
            let pad = widths[i].saturating_sub(cell.chars().count());
            if !first {
                s.push_str("  ");
            }
            if i == 0 {
                s.push_str(cell);
                s.extend(std::iter::repeat_n(' ', pad));
            } else {
                s.extend(std::iter::repeat_n(' ', pad));
                s.push_str(cell);
            }
            first = false;
        }
        out.push_str(s.trim_end());
        out.push('\n');
    };
    line(&mut out, &mut header.iter().copied());
    for row in rows {
        line(&mut out, &mut row.iter().map(String::as_str));
    }
    out
}

/// A JSON array, one compact object per line.
fn array<T: Serialize>(items: impl IntoIterator<Item = T>) -> String {
    // Serialising these plain structs into a string cannot fail.
    let items: Vec<String> = items
        .into_iter()
        .map(|item| serde_json::to_string(&item).unwrap_or_default())
        .collect();
    if items.is_empty() {
        return "[]\n".to_string();
    }
    format!("[\n  {}\n]\n", items.join(",\n  "))
}

/// Serialises `(key, value)` pairs as a JSON object, in their order.
fn in_order<V: Serialize, S: Serializer>(pairs: &[(&str, V)], s: S) -> Result<S::Ok, S::Error> {
    s.collect_map(pairs.iter().map(|(k, v)| (k, v)))
}

/// One row of `breakaway --json`.
#[derive(Serialize)]
struct BreakawayJson<'a> {
    variant: &'a str,
    k: f64,
    v_b: f64,
    f_ba: f64,
    t_ba: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    f_ba_sim: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    t_ba_sim: Option<f64>,
}

/// One `(m, k)` point of `validity-map --json`.
#[derive(Serialize)]
struct ValidityJson<'a> {
    m: f64,
    pi: f64,
    k: f64,
    lambda: f64,
    f_ba_sim: f64,
    t_ba_sim: f64,
    #[serde(serialize_with = "in_order")]
    variants: Vec<(&'a str, Compared)>,
}

/// One variant at one point of `validity-map --json`.
#[derive(Serialize)]
struct Compared {
    f_ba: f64,
    drift: f64,
}

/// `breakaway` as a table.
pub fn breakaway_table(rows: &[BreakawayRow], dynamic: bool) -> String {
    let mut header = vec!["variant", "k [N/s]", "v_b [m/s]", "F_ba [N]", "t_ba [s]"];
    if dynamic {
        header.extend(["F_ba_sim [N]", "t_ba_sim [s]"]);
    }
    let cells: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            let mut c = vec![
                r.variant.name().to_string(),
                short(r.k, 6),
                format!("{:.4e}", r.v_b),
                format!("{:.6}", r.f_ba),
                format!("{:.6}", r.t_ba),
            ];
            if let Some(d) = r.dynamic {
                c.push(format!("{:.6}", d.f_ba));
                c.push(format!("{:.6}", d.t_ba));
            }
            c
        })
        .collect();
    table(&header, &cells)
}

/// `breakaway --json`: keys `variant`, `k`, `v_b`, `f_ba`, `t_ba` and with
/// `--dynamic` `f_ba_sim`, `t_ba_sim`.
pub fn breakaway_json(rows: &[BreakawayRow]) -> String {
    array(rows.iter().map(|r| BreakawayJson {
        variant: r.variant.name(),
        k: r.k,
        v_b: r.v_b,
        f_ba: r.f_ba,
        t_ba: r.t_ba,
        f_ba_sim: r.dynamic.map(|d| d.f_ba),
        t_ba_sim: r.dynamic.map(|d| d.t_ba),
    }))
}

/// The band of a relative drift: `ok` below 1 %, `>1%`, `>10%`.
pub fn band(drift: f64) -> &'static str {
    let d = drift.abs();
    if d < 0.01 {
        "ok"
    } else if d < 0.1 {
        ">1%"
    } else {
        ">10%"
    }
}

/// `validity-map` as one table per mass, each headed by `Π` and `k(Λ = 1)`.
pub fn validity_table(blocks: &[ValidityBlock], variants: &[Variant], w_b: f64) -> String {
    let mut header: Vec<String> = vec!["k [N/s]".into(), "Λ".into(), "F_ba_sim [N]".into()];
    for v in variants {
        header.push(format!("F_{} [N]", v.name()));
        header.push(format!("drift_{}", v.name()));
    }
    header.push("worst".into());
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# drift = (F_ba - F_ba_sim)/F_ba_sim; worst: ok < 1 % <= >1% < 10 % <= >10%; w_b = {w_b}"
    );
    for b in blocks {
        let _ = writeln!(
            out,
            "\n# m = {} kg: Π = sqrt(2*Fs*z_max/m)/V = {}; Λ = 1 at k = {} N/s",
            short(b.mass, 6),
            short(b.pi, 4),
            short(b.k_unit_inertia, 4)
        );
        let cells: Vec<Vec<String>> = b
            .points
            .iter()
            .map(|p| {
                let mut c = vec![
                    short(p.k, 6),
                    short(p.lambda, 4),
                    format!("{:.6}", p.sim.f_ba),
                ];
                for cmp in &p.compared {
                    c.push(format!("{:.6}", cmp.f_ba));
                    c.push(format!("{:+.3}%", 100.0 * cmp.drift));
                }
                c.push(band(p.worst_drift()).to_string());
                c
            })
            .collect();
        out.push_str(&table(&header, &cells));
    }
    out
}

/// `validity-map --json`: one object per `(m, k)` with keys `m`, `pi`, `k`,
/// `lambda`, `f_ba_sim`, `t_ba_sim` and `variants`, an object
/// `{variant: {"f_ba": …, "drift": …}}` (drift relative, not in %).
pub fn validity_json(blocks: &[ValidityBlock]) -> String {
    array(blocks.iter().flat_map(|b| {
        b.points.iter().map(|p| ValidityJson {
            m: b.mass,
            pi: b.pi,
            k: p.k,
            lambda: p.lambda,
            f_ba_sim: p.sim.f_ba,
            t_ba_sim: p.sim.t_ba,
            variants: p
                .compared
                .iter()
                .map(|c| {
                    let (f_ba, drift) = (c.f_ba, c.drift);
                    (c.variant.name(), Compared { f_ba, drift })
                })
                .collect(),
        })
    }))
}

/// A markdown table (numbers right-aligned).
pub fn markdown(header: &[String], rows: &[Vec<String>]) -> String {
    let mut out = format!("| {} |\n|", header.join(" | "));
    for (i, _) in header.iter().enumerate() {
        out.push_str(if i == 0 { "---|" } else { "---:|" });
    }
    out.push('\n');
    for row in rows {
        out.push_str(&format!("| {} |\n", row.join(" | ")));
    }
    out
}

/// `breakaway --markdown`: one row per `k` (in the order given), `F_ba` per
/// variant, and `F_ba_sim` when the rows carry the dynamics.
pub fn breakaway_markdown(rows: &[BreakawayRow], variants: &[Variant]) -> String {
    let dynamic = rows.first().is_some_and(|r| r.dynamic.is_some());
    let mut header = vec!["k [N/s]".to_string()];
    header.extend(variants.iter().map(|v| format!("F_ba {} [N]", v.name())));
    if dynamic {
        header.push("F_ba sim [N]".into());
        header.push("t_ba sim [s]".into());
    }
    // Rows are grouped by variant, then k: row i of variant j is rows[j·n + i].
    let n = rows.len() / variants.len().max(1);
    let cells: Vec<Vec<String>> = (0..n)
        .map(|i| {
            let mut c = vec![short(rows[i].k, 6)];
            c.extend((0..variants.len()).map(|j| {
                rows.get(j * n + i)
                    .map_or("—".to_string(), |r| format!("{:.4}", r.f_ba))
            }));
            if let Some(d) = rows[i].dynamic {
                c.push(format!("{:.4}", d.f_ba));
                c.push(short(d.t_ba, 4));
            }
            c
        })
        .collect();
    markdown(&header, &cells)
}

/// `validity-map --markdown`: a line of `Π` and `k(Λ = 1)` per mass, then per
/// variant a table of the relative drift in %, `k` down and `m` across,
/// marked `*` above 1 % and `**` above 10 %.
pub fn validity_markdown(blocks: &[ValidityBlock], variants: &[Variant], w_b: f64) -> String {
    let mut out = String::new();
    let mut header = vec!["".to_string()];
    header.extend(
        blocks
            .iter()
            .map(|b| format!("m = {} kg", short(b.mass, 6))),
    );
    let pi: Vec<String> = std::iter::once("Π (MODEL.md §8)".to_string())
        .chain(blocks.iter().map(|b| short(b.pi, 3)))
        .collect();
    let k1: Vec<String> = std::iter::once("k at Λ = 1 [N/s]".to_string())
        .chain(blocks.iter().map(|b| short(b.k_unit_inertia, 3)))
        .collect();
    out.push_str(&markdown(&header, &[pi, k1]));
    let n = blocks.first().map_or(0, |b| b.points.len());
    for (j, v) in variants.iter().enumerate() {
        let _ = writeln!(
            out,
            "\nDrift of `{}`, (F_ba − F_ba_sim)/F_ba_sim in % (w_b = {w_b}; * > 1 %, ** > 10 %):\n",
            v.name()
        );
        let mut header = vec!["k [N/s]".to_string()];
        header.extend(
            blocks
                .iter()
                .map(|b| format!("m = {} kg", short(b.mass, 6))),
        );
        let cells: Vec<Vec<String>> = (0..n)
            .map(|i| {
                let mut c = vec![short(blocks[0].points[i].k, 6)];
                c.extend(blocks.iter().map(|b| {
                    let Some(d) = b.points.get(i).and_then(|p| p.compared.get(j)) else {
                        return "—".to_string();
                    };
                    let d = d.drift;
                    let mark = match band(d) {
                        "ok" => "",
                        ">1%" => " *",
                        _ => " **",
                    };
                    format!("{:+.2}{mark}", 100.0 * d)
                }));
                c
            })
            .collect();
        out.push_str(&markdown(&header, &cells));
    }
    out
}
