//! Measured records (MODEL.md §6): the CSV layout and the EMPS MATLAB v5
//! layout, read strictly.
//!
//! * CSV: one header line, comma-separated; required columns `t` [s]
//!   (strictly increasing), `u` [N], `x` [m]; optional `v` [m/s]; any order,
//!   other columns ignored; lines starting with `#` and blank lines skipped.
//! * `.mat` (MATLAB v5, the EMPS benchmark): `t ← t`, `x ← qm`,
//!   `u ← gtau·vir`.
//!
//! Every error is one line that names the file and the line (CSV) or the
//! variable and element (`.mat`) at fault. Input files are only read.

use crate::Error;
use std::path::Path;

/// Fewest samples a record may have.
pub const MIN_SAMPLES: usize = 100;

/// A measured record: time, actuation force, position, optional velocity.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// Time `t` [s], strictly increasing.
    pub t: Vec<f64>,
    /// Actuation force `u` [N], held from one sample to the next.
    pub u: Vec<f64>,
    /// Position `x` [m].
    pub x: Vec<f64>,
    /// Measured velocity `v` [m/s], when the file has it.
    pub v: Option<Vec<f64>>,
    /// Where the record came from (file name), for messages.
    pub source: String,
}

impl Record {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// True when the record holds no sample.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Median sampling interval [s].
    pub fn dt(&self) -> f64 {
        let mut d: Vec<f64> = self.t.windows(2).map(|w| w[1] - w[0]).collect();
        if d.is_empty() {
            return f64::NAN;
        }
        d.sort_by(f64::total_cmp);
        d[d.len() / 2]
    }
}

fn err(path: &Path, msg: impl std::fmt::Display) -> Error {
    Error::Runtime(format!("{}: {msg}", path.display()))
}

/// Reads a record: `.mat` files in the EMPS layout, anything else as CSV.
pub fn load(path: &Path) -> Result<Record, Error> {
    let is_mat = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("mat"));
    let rec = if is_mat {
        read_mat(path)?
    } else {
        let text = std::fs::read(path).map_err(|e| err(path, format!("cannot read: {e}")))?;
        let text = String::from_utf8(text).map_err(|e| {
            err(
                path,
                format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
            )
        })?;
        parse_csv(&text, path)?
    };
    Ok(rec)
}

/// The rows of comma-separated text as the `csv` crate splits them (no
/// quoting, rows of any length, lines ended by `\n` or `\r\n`), each with
/// its line number (1-based, counting every line of the file); blank lines
/// and lines starting with `#` are skipped. The first row is the header.
pub(crate) fn rows(text: &str) -> impl Iterator<Item = (u64, csv::StringRecord)> + '_ {
    let bytes = text.as_bytes();
    // The start and line of the previous row.
    let (mut at, mut line) = (0usize, 1u64);
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .quoting(false)
        .terminator(csv::Terminator::Any(b'\n'))
        .from_reader(bytes)
        .into_records()
        // Reading a `&str` cannot fail: no I/O, and fields split at ASCII
        // bytes are UTF-8.
        .map_while(Result::ok)
        .filter_map(move |record| {
            // The line from the row's byte offset: the crate positions a row
            // before the empty lines it skips, and counts its line there.
            let mut start = record.position().map_or(at, |p| p.byte() as usize).max(at);
            while bytes.get(start) == Some(&b'\n') {
                start += 1;
            }
            let newlines = bytes
                .get(at..start)
                .unwrap_or(&[])
                .iter()
                .filter(|&&b| b == b'\n');
            line += newlines.count() as u64;
            at = start;
            let first = record.get(0).map_or("", str::trim);
            let blank = record.len() == 1 && first.is_empty();
            (!blank && !first.starts_with('#')).then_some((line, record))
        })
}

/// The fields of a row, trimmed.
pub(crate) fn trimmed(record: &csv::StringRecord) -> Vec<&str> {
    record.iter().map(str::trim).collect()
}

/// Parses CSV text (MODEL.md §6); `path` only names the file in errors.
pub fn parse_csv(text: &str, path: &Path) -> Result<Record, Error> {
    // Lines end at `\n` (or `\r\n`); a file whose lines end at `\r` alone
    // would read as one line.
    if text.contains('\r') && !text.contains('\n') {
        return Err(err(
            path,
            "lines end with a carriage return alone (old Mac line endings); \
             convert them to `\\n` or `\\r\\n`",
        ));
    }
    let mut lines = rows(text);
    let Some((hline, header)) = lines.next() else {
        return Err(err(
            path,
            "empty file: no header line (a record needs columns t, u, x)",
        ));
    };
    let names = trimmed(&header);
    // A name given twice would leave the column read to the order of the
    // header: refused, as any column could be the one meant.
    if let Some((k, dup)) = names
        .iter()
        .enumerate()
        .find(|(k, n)| !n.is_empty() && names[..*k].contains(n))
    {
        return Err(err(
            path,
            format!(
                "line {hline}: column `{dup}` named twice in the header (fields {} and {})",
                names.iter().position(|n| n == dup).map_or(0, |i| i + 1),
                k + 1
            ),
        ));
    }
    let col = |name: &str| names.iter().position(|n| *n == name);
    let mut idx = [0usize; 3];
    for (slot, name) in idx.iter_mut().zip(["t", "u", "x"]) {
        *slot = col(name).ok_or_else(|| {
            err(
                path,
                format!(
                    "line {hline}: header lacks column `{name}` (a record needs t, u, x; found: {}){}",
                    names.join(", "),
                    header_hint(&names)
                ),
            )
        })?;
    }
    let vcol = col("v");
    let mut rec = Record {
        t: Vec::new(),
        u: Vec::new(),
        x: Vec::new(),
        v: vcol.map(|_| Vec::new()),
        source: path.display().to_string(),
    };
    let mut line_of = Vec::new();
    for (ln, row) in lines {
        line_of.push(ln);
        let fields = trimmed(&row);
        let get = |name: &str, i: usize| -> Result<f64, Error> {
            let s = fields.get(i).ok_or_else(|| {
                err(
                    path,
                    format!(
                        "line {ln}: column `{name}` missing ({} fields, header has {})",
                        fields.len(),
                        names.len()
                    ),
                )
            })?;
            let x: f64 = s.parse().map_err(|_| {
                err(
                    path,
                    format!("line {ln}: column `{name}`: `{s}` is not a number"),
                )
            })?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(err(
                    path,
                    format!("line {ln}: column `{name}`: value `{s}` is not finite"),
                ))
            }
        };
        let t = get("t", idx[0])?;
        if let Some(&prev) = rec.t.last() {
            if t <= prev {
                return Err(err(
                    path,
                    format!("line {ln}: column `t`: {t} does not increase (previous {prev})"),
                ));
            }
        }
        rec.t.push(t);
        rec.u.push(get("u", idx[1])?);
        rec.x.push(get("x", idx[2])?);
        if let (Some(vi), Some(v)) = (vcol, rec.v.as_mut()) {
            v.push(get("v", vi)?);
        }
    }
    if rec.len() < MIN_SAMPLES {
        return Err(err(
            path,
            format!(
                "too few samples: {} (need at least {MIN_SAMPLES})",
                rec.len()
            ),
        ));
    }
    check_sampling(&rec, path, |i| {
        format!("line {}", line_of.get(i).copied().unwrap_or(0))
    })?;
    Ok(rec)
}

/// What a header that lacks a column most likely got wrong, for the
/// message: the separator, quotes, units or the case of the names (the
/// names are `t`, `u`, `x`, `v`, bare, comma-separated).
fn header_hint(names: &[&str]) -> &'static str {
    let joined = names.join(",");
    if names.len() == 1 && [';', '\t', ' '].iter().any(|c| joined.contains(*c)) {
        "; the separator must be a comma"
    } else if joined.contains('"') || joined.contains('\'') {
        "; names are not quoted"
    } else if names.iter().any(|n| n.contains('[') || n.contains('(')) {
        "; names carry no units (t [s], u [N], x [m] are implied)"
    } else if names.iter().any(|n| ["T", "U", "X", "V"].contains(n)) {
        "; names are lower case"
    } else {
        ""
    }
}

/// Reads the EMPS layout of a MATLAB v5 file: `t`, `qm`, `vir`, `gtau`.
pub fn read_mat(path: &Path) -> Result<Record, Error> {
    let file = std::fs::File::open(path).map_err(|e| err(path, format!("cannot read: {e}")))?;
    let mat = matfile::MatFile::parse(std::io::BufReader::new(file)).map_err(|e| {
        err(
            path,
            format!(
                "not a readable MATLAB v5 file (the EMPS layout: double or single arrays \
                 t, qm, vir, gtau; integer, cell and struct arrays are not read){}",
                mat_detail(&e)
            ),
        )
    })?;
    let var = |name: &str| -> Result<Vec<f64>, Error> {
        let a = mat.find_by_name(name).ok_or_else(|| {
            // A file cut short parses up to its last whole variable: the
            // names found say whether the layout or the file is at fault.
            let found: Vec<&str> = mat.arrays().iter().map(|a| a.name()).collect();
            err(
                path,
                format!(
                    "variable `{name}` missing (EMPS layout: t, qm, vir, gtau; found: {}; \
                     a file cut short keeps only its first variables)",
                    if found.is_empty() {
                        "none".to_string()
                    } else {
                        found.join(", ")
                    }
                ),
            )
        })?;
        match a.data() {
            matfile::NumericData::Double { real, imag: None } => Ok(real.clone()),
            matfile::NumericData::Single { real, imag: None } => {
                Ok(real.iter().map(|&x| f64::from(x)).collect())
            }
            _ => Err(err(
                path,
                format!("variable `{name}` is not a real floating-point (double or single) array"),
            )),
        }
    };
    let t = var("t")?;
    let qm = var("qm")?;
    let vir = var("vir")?;
    let gtau = var("gtau")?;
    let [g] = gtau.as_slice() else {
        return Err(err(
            path,
            format!(
                "variable `gtau` must be a scalar, has {} elements",
                gtau.len()
            ),
        ));
    };
    for (name, v) in [("qm", &qm), ("vir", &vir)] {
        if v.len() != t.len() {
            return Err(err(
                path,
                format!(
                    "variable `{name}` has {} elements, `t` has {}",
                    v.len(),
                    t.len()
                ),
            ));
        }
    }
    for (name, v) in [("t", &t), ("qm", &qm), ("vir", &vir), ("gtau", &gtau)] {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(err(
                path,
                format!("variable `{name}`, element {}: value is not finite", i + 1),
            ));
        }
    }
    if let Some(i) = t.windows(2).position(|w| w[1] <= w[0]) {
        return Err(err(
            path,
            format!("variable `t`, element {}: does not increase", i + 2),
        ));
    }
    if t.len() < MIN_SAMPLES {
        return Err(err(
            path,
            format!("too few samples: {} (need at least {MIN_SAMPLES})", t.len()),
        ));
    }
    let rec = Record {
        u: vir.iter().map(|v| g * v).collect(),
        t,
        x: qm,
        v: None,
        source: path.display().to_string(),
    };
    check_sampling(&rec, path, |i| format!("element {} of `t`", i + 1))?;
    Ok(rec)
}

/// What the MATLAB parser said, for the message: its I/O error where it
/// has one; its parse errors name only the parser's internals, so none.
fn mat_detail(e: &matfile::Error) -> String {
    match e {
        matfile::Error::IOError(io) => format!(": {io}"),
        _ => String::new(),
    }
}

/// The differentiator assumes (near-)uniform sampling: every interval
/// within ±50 % of the median. `at(i)` names where sample `i` is in the
/// file (a CSV line, an element of a `.mat` array).
fn check_sampling(rec: &Record, path: &Path, at: impl Fn(usize) -> String) -> Result<(), Error> {
    let dt = rec.dt();
    if let Some(i) = rec
        .t
        .windows(2)
        .position(|w| ((w[1] - w[0]) - dt).abs() > 0.5 * dt)
    {
        return Err(err(
            path,
            format!(
                "{}: interval {} s from the sample before is not within 50 % of the median {} s \
                 (uniform sampling needed)",
                at(i + 1),
                rec.t[i + 1] - rec.t[i],
                dt
            ),
        ));
    }
    Ok(())
}

/// Writes a record as CSV (MODEL.md §6) with full-precision numbers,
/// preceded by `#` comment lines.
pub fn write_csv(path: &Path, rec: &Record, comments: &[String]) -> Result<(), Error> {
    std::fs::write(path, csv_text(rec, comments))
        .map_err(|e| err(path, format!("cannot write: {e}")))
}

/// The text [`write_csv`] writes.
pub fn csv_text(rec: &Record, comments: &[String]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for c in comments {
        let _ = writeln!(s, "# {c}");
    }
    s.push_str("t,u,x\n");
    for i in 0..rec.len() {
        let _ = writeln!(s, "{:?},{:?},{:?}", rec.t[i], rec.u[i], rec.x[i]);
    }
    s
}

/// Parses a steady-state record (MODEL.md §6): comma-separated, one header
/// line with columns `v` [m/s or rad/s] and `u` [N or N·m] in any order
/// (others ignored), `#` comments; one force reading per speed. Needs at
/// least 5 points; every error names the line and column.
pub fn parse_steady_csv(text: &str, path: &Path) -> Result<Vec<crate::static_curve::Point>, Error> {
    let mut lines = rows(text);
    let Some((hline, header)) = lines.next() else {
        return Err(err(path, "empty file: no header line (columns v, u)"));
    };
    let names = trimmed(&header);
    let col = |name: &str| {
        names.iter().position(|n| *n == name).ok_or_else(|| {
            err(
                path,
                format!(
                    "line {hline}: header lacks column `{name}` (a steady-state record needs v, u; found: {})",
                    names.join(", ")
                ),
            )
        })
    };
    let (iv, iu) = (col("v")?, col("u")?);
    let mut pts = Vec::new();
    for (ln, row) in lines {
        let fields = trimmed(&row);
        let get = |name: &str, i: usize| -> Result<f64, Error> {
            let s = fields
                .get(i)
                .ok_or_else(|| err(path, format!("line {ln}: column `{name}` missing")))?;
            s.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    err(
                        path,
                        format!("line {ln}: column `{name}`: `{s}` is not a finite number"),
                    )
                })
        };
        pts.push(crate::static_curve::Point {
            v: get("v", iv)?,
            tau: get("u", iu)?,
        });
    }
    if pts.len() < 5 {
        return Err(err(
            path,
            format!("too few points: {} (need at least 5)", pts.len()),
        ));
    }
    Ok(pts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(body: &str) -> String {
        let mut s = String::from(body);
        for i in 0..MIN_SAMPLES {
            s.push_str(&format!("{i},0.5,{i}\n"));
        }
        s
    }

    fn error(text: &str) -> String {
        match parse_csv(text, Path::new("f.csv")) {
            Err(Error::Runtime(e)) => e,
            other => panic!("{other:?}"),
        }
    }

    /// Comments (also indented), blank and whitespace-only lines, CRLF
    /// endings and spaces around fields; line numbers count every line.
    #[test]
    fn layout_and_line_numbers() {
        let text = csv("# a comment\n\n   \n  # indented\r\n t , u,x \r\n");
        let rec = parse_csv(&text, Path::new("f.csv")).unwrap();
        assert_eq!(rec.len(), MIN_SAMPLES);
        assert_eq!((rec.t[1], rec.u[1], rec.x[1]), (1.0, 0.5, 1.0));
        let bad = text.replacen("\n3,0.5,", "\n3,abc,", 1);
        assert_eq!(
            error(&bad),
            "f.csv: line 9: column `u`: `abc` is not a number"
        );
        let bad = text.replacen("\n3,0.5,3\n", "\n3,0.5\n", 1);
        assert_eq!(
            error(&bad),
            "f.csv: line 9: column `x` missing (2 fields, header has 3)"
        );
    }

    /// No quoting: a quoted number is not a number; the header must name
    /// the columns.
    #[test]
    fn strict_fields() {
        let bad = csv("t,u,x\n").replacen("\n2,", "\n\"2\",", 1);
        assert_eq!(
            error(&bad),
            "f.csv: line 4: column `t`: `\"2\"` is not a number"
        );
        assert_eq!(
            error("# only\n\n"),
            "f.csv: empty file: no header line (a record needs columns t, u, x)"
        );
        assert!(error(&csv("t;u;x\n")).starts_with("f.csv: line 1: header lacks column `t`"));
    }

    /// Every line counts, empty ones included, wherever they stand.
    #[test]
    fn line_numbers_count_empty_lines() {
        let lines = |text: &str| -> Vec<u64> { rows(text).map(|(line, _)| line).collect() };
        assert_eq!(lines("\n\n\nq\n\n\nr"), [4, 7]);
        assert_eq!(lines("a\r\n\r\nb\r\n"), [1, 3]);
        assert_eq!(lines("#a,b\n\nx,y\n"), [3]);
        assert_eq!(lines("a\n\nx\n  \ny\nz\n"), [1, 3, 5, 6]);
    }

    #[test]
    fn steady_state_points() {
        let text = "# v, u\nu, v\n1,0.1\n\n2,0.2\n3,0.3\n4,0.4\n5,0.5\n";
        let pts = parse_steady_csv(text, Path::new("s.csv")).unwrap();
        assert_eq!((pts.len(), pts[4].v, pts[4].tau), (5, 0.5, 5.0));
        let e = parse_steady_csv(&text.replace("4,0.4", "4,x"), Path::new("s.csv"));
        assert!(
            matches!(&e, Err(Error::Runtime(m)) if m == "s.csv: line 7: column `v`: `x` is not a finite number"),
            "{e:?}"
        );
    }
}
