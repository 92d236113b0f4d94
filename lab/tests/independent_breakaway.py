#!/usr/bin/env python3
"""Independent check of `breakaway-lab breakaway --json` against MODEL.md §4.

Written from MODEL.md §2–§4 alone (Python 3 standard library only), not from
the Rust code. Usage:

    python3 lab/tests/independent_breakaway.py PATH/TO/breakaway-lab

For several model files and k grids it runs the binary with --json, recomputes
every row (variants coulomb, stiction, mean, consistent) and compares v_b,
f_ba and t_ba: relative tolerance 1e-6 for the closed-form variants, 1e-5 for
`consistent`. It prints the worst relative error per variant and a final line
`N passed, M failed` (one per row); the exit status is non-zero on any failure.
"""

import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
LAB = os.path.dirname(HERE)

TOL = {"coulomb": 1e-6, "stiction": 1e-6, "mean": 1e-6, "consistent": 1e-5}

# (model file, --k argument, expanded grid, w_b or None for the default 0.95)
PAPER_GRID = "0.01:30:2"


def frange(start, stop, step):
    """START:STOP:STEP, STOP included when it lies on the grid."""
    n = int(math.floor((stop - start) / step + 1e-9))
    out = [start + i * step for i in range(n + 1)]
    if abs(out[-1] - stop) <= 1e-9 * step:
        out[-1] = stop
    return out


CASES = [
    ("models/fig5.toml", PAPER_GRID, frange(0.01, 30, 2), None),
    ("models/fig5.toml", "0.001,0.01,0.1,1:30:1", [0.001, 0.01, 0.1] + frange(1, 30, 1), None),
    ("models/fig5.toml", "0.05,0.5,5,50", [0.05, 0.5, 5, 50], 0.9),
    ("tests/models/viscous_delta05.toml", "0.001,0.01,0.1,0.5:30:0.5,100",
     [0.001, 0.01, 0.1] + frange(0.5, 30, 0.5) + [100], None),
    ("tests/models/delta2.toml", "0.01,0.1,1:60:1", [0.01, 0.1] + frange(1, 60, 1), 0.97),
    ("tests/models/fs4_delta2.toml", "0.01,0.1,1:20:0.25,30,100",
     [0.01, 0.1] + frange(1, 20, 0.25) + [30, 100], None),
]


# ---- model files (MODEL.md §7) ----------------------------------------------

def parse_toml_subset(text):
    """Fallback for Python < 3.11: flat `key = number` lines and [tables]."""
    model, table = {}, None
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        if line.startswith("["):
            table = line.strip("[]").strip()
            continue
        key, value = (s.strip() for s in line.split("=", 1))
        if table is None:
            model[key] = float(value)
    return model


def load_model(path):
    with open(path, "rb") as f:
        raw = f.read()
    try:
        import tomllib
        data = tomllib.loads(raw.decode("utf-8"))
    except ImportError:
        data = parse_toml_subset(raw.decode("utf-8"))
    keys = ("mass", "fc", "fs", "v_stribeck", "delta", "sigma", "z_max")
    return {k: float(data.get(k, 0.0)) for k in keys}


# ---- MODEL.md §2–§4 ------------------------------------------------------------

def S(m, v):
    """Stribeck magnitude S(v) = Fc + (Fs − Fc)·exp(−(|v|/V)^δ)."""
    return m["fc"] + (m["fs"] - m["fc"]) * math.exp(-((abs(v) / m["v_stribeck"]) ** m["delta"]))


def g(w):
    """Presliding shape g(w) = w·(1 − ln w)."""
    return 0.0 if w <= 0.0 else w * (1.0 - math.log(w))


def consistent_v(m, c):
    """Smallest positive root of v·S(v) = c (c > 0).

    Since Fc ≤ S ≤ Fs the root lies in [c/Fs, c/Fc]; h(v) = v·S(v) − c is ≤ 0
    at the left end and ≥ 0 at the right end. A fine scan finds the first sign
    change, bisection refines it.
    """
    lo, hi = c / m["fs"], c / m["fc"]
    h = lambda v: v * S(m, v) - c
    if h(lo) >= 0.0:
        return lo
    n = 20000
    prev = lo
    for i in range(1, n + 1):
        v = lo + (hi - lo) * i / n
        if h(v) >= 0.0:
            a, b = prev, v
            break
        prev = v
    else:
        a, b = prev, hi
    for _ in range(200):
        mid = 0.5 * (a + b)
        if mid == a or mid == b:
            break
        if h(mid) >= 0.0:
            b = mid
        else:
            a = mid
    return 0.5 * (a + b)


def predict(m, variant, k, wb):
    c = -k * m["z_max"] / math.log(wb)            # = v_b·F̂
    if variant == "coulomb":
        v_b = c / m["fc"]
    elif variant == "stiction":
        v_b = c / m["fs"]
    elif variant == "mean":
        v_b = c / ((m["fc"] + m["fs"]) / 2.0)
    else:
        v_b = consistent_v(m, c)
    s = S(m, v_b)
    f_ba = s + m["sigma"] * v_b
    t_ba = (s * g(wb) + m["sigma"] * v_b) / k
    return {"v_b": v_b, "f_ba": f_ba, "t_ba": t_ba}


# ---- the check ---------------------------------------------------------------

def rel(a, b):
    return abs(a - b) / max(abs(b), 1e-300)


def main():
    if len(sys.argv) != 2:
        print("usage: independent_breakaway.py PATH/TO/breakaway-lab", file=sys.stderr)
        return 2
    exe = sys.argv[1]
    passed = failed = 0
    worst = {v: 0.0 for v in TOL}
    for model_file, k_arg, grid, wb in CASES:
        path = os.path.join(LAB, model_file)
        m = load_model(path)
        cmd = [exe, "breakaway", "--model", path, "--k", k_arg, "--json"]
        if wb is not None:
            cmd += ["--wb", repr(wb)]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            print(f"FAIL {model_file}: exit {proc.returncode}: {proc.stderr.strip()}")
            failed += 1
            continue
        rows = json.loads(proc.stdout)
        w = 0.95 if wb is None else wb
        expected_rows = len(TOL) * len(grid)
        if len(rows) != expected_rows:
            print(f"FAIL {model_file} --k {k_arg}: {len(rows)} rows, expected {expected_rows}")
            failed += 1
        seen = {v: [] for v in TOL}
        for row in rows:
            variant = row.get("variant")
            if variant not in TOL or not all(key in row for key in ("k", "v_b", "f_ba", "t_ba")):
                print(f"FAIL {model_file}: malformed row {row}")
                failed += 1
                continue
            seen[variant].append(row["k"])
            want = predict(m, variant, row["k"], w)
            errs = {key: rel(row[key], want[key]) for key in want}
            err = max(errs.values())
            worst[variant] = max(worst[variant], err)
            if err > TOL[variant]:
                print(f"FAIL {model_file} {variant} k={row['k']}: got "
                      f"{ {key: row[key] for key in want} } want {want} rel {errs}")
                failed += 1
            else:
                passed += 1
        for variant, ks in seen.items():
            if len(ks) != len(grid) or any(rel(a, b) > 1e-12 for a, b in zip(ks, grid)):
                print(f"FAIL {model_file} {variant}: k grid {ks} differs from {grid}")
                failed += 1
    for variant, e in worst.items():
        print(f"worst relative error {variant:>10}: {e:.3e} (tolerance {TOL[variant]:.0e})")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
