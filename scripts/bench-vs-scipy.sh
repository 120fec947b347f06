#!/usr/bin/env bash
# Fairway's default full fair against SciPy's smoothing spline, side by side in one run (issue 28; not CI).
#
# For every curve of the quality suite (crates/fairway/tests/common/suite.rs) at 1, 3 and 10 × its noise σ:
#   * Fairway: one default full fair (`fair_curve`, setup included), from `cargo run --release -p fairway
#     --example speed_suite`: the fastest of ≥ 0.3 s of fairs (wall), and the process CPU per fair over them (all threads);
#   * SciPy: the curve sampled at 2000 parameters (20 a control point on long curves), fitted by FITPACK's
#     parametric smoothing spline (`scipy.interpolate.splprep`, degree min(p, 5), periodic for closed
#     curves) with the smoothing factor s searched (bisection in log s, 40 solves at most) for the largest s
#     whose parametric deviation at the samples stays within the band m — a SciPy user's tolerance search —
#     and then one solve at that s timed alone (the fastest of 5, process CPU time).
# It prints per row the times and the ratios  one SciPy solve / Fairway  (> 1: Fairway is faster than one
# solve) and  SciPy search / Fairway, and their geometric means.
#
# SciPy is installed into a throw-away venv under /tmp (FAIRWAY_SCIPY_VENV to reuse one).
#
#   scripts/bench-vs-scipy.sh            # all rows
#   scripts/bench-vs-scipy.sh circle     # rows whose name contains "circle"
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${FAIRWAY_SCIPY_VENV:-/tmp/fairway-scipy-venv}"
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import scipy" 2>/dev/null; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet --disable-pip-version-check numpy scipy
fi
suite="$(mktemp /tmp/fairway-suite.XXXXXX.jsonl)"
trap 'rm -f "$suite"' EXIT
cargo run --quiet --release -p fairway --example speed_suite > "$suite"
"$venv/bin/python" - "$suite" "${1:-}" <<'PY'
import json, math, sys, time
import numpy as np
from scipy.interpolate import BSpline, splprep, splev

rows = [json.loads(l) for l in open(sys.argv[1])]
only = sys.argv[2]

def evaluate(r, u):
    k = r["degree"]
    t = np.array(r["knots"])
    P = np.array([r["x"], r["y"], r["z"]]).T[:, : r["dim"]]
    if r["w"] is None:
        return BSpline(t, P, k)(u)
    w = np.array(r["w"])
    h = BSpline(t, np.hstack([P * w[:, None], w[:, None]]), k)(u)
    return h[:, :-1] / h[:, -1:]

def cpu():
    return time.process_time()

def solve(data, u, k, s, per):
    tck, _ = splprep(list(data.T), u=u, k=k, s=s, per=per, quiet=1)
    return tck

def deviation(tck, data, u):
    return np.max(np.linalg.norm(np.array(splev(u, tck)).T - data, axis=1))

print(f"{'curve':<22} {'m/σ':>4} {'cps':>4} {'Fairway ms':>11} {'(CPU ms)':>9} {'SciPy solve ms':>15} {'SciPy search ms':>16} "
      f"{'solve/Fairway':>14} {'search/Fairway':>15}")
solve_ratios, search_ratios = [], []
for r in rows:
    if only and only not in r["name"]:
        continue
    n = len(r["x"])
    ns = max(2000, 20 * n)
    t = r["knots"]
    d0, d1 = t[r["degree"]], t[-r["degree"] - 1]
    u = np.linspace(d0, d1, ns)
    data = evaluate(r, u)
    per = 1 if r["closed"] else 0
    if per:
        # FITPACK's periodic fit wants the first and last data point equal and drops the last one
        data[-1] = data[0]
    k = min(r["degree"], 5)
    m = r["m"]
    # the tolerance search: the largest s whose fit keeps every sample within m (bisection in log s)
    c0 = cpu()
    def holds(s):
        try:
            return deviation(solve(data, u, k, s, per), data, u) <= m
        except Exception:
            return False
    top = hi = ns * m * m  # every sample at m: the largest s that can hold the band
    if holds(hi):
        best = lo = hi
    else:
        lo = hi / 16
        while lo > 1e-12 * top and not holds(lo):
            hi, lo = lo, lo / 16
        best = lo if lo > 1e-12 * top else 0.0
        while best > 0 and hi / lo > 1.05:
            mid = math.sqrt(lo * hi)
            if holds(mid):
                lo = best = mid
            else:
                hi = mid
    search_ms = (cpu() - c0) * 1e3
    s = best
    times = []
    for _ in range(5):
        c0 = cpu()
        solve(data, u, k, s, per)
        times.append((cpu() - c0) * 1e3)
    solve_ms = min(times)
    fw = r["fairway_min_ms"]
    solve_ratios.append(solve_ms / fw)
    search_ratios.append(search_ms / fw)
    print(f"{r['name']:<22} {r['factor']:>4g} {n:>4} {fw:>11.3f} {r['fairway_cpu_ms']:>9.3f} {solve_ms:>15.3f} {search_ms:>16.1f} "
          f"{solve_ms / fw:>14.2f} {search_ms / fw:>15.1f}")
gm = lambda v: math.exp(sum(map(math.log, v)) / len(v)) if v else float("nan")
print(f"\n{len(solve_ratios)} rows; geometric mean of one SciPy solve / Fairway's full fair: {gm(solve_ratios):.2f} "
      f"(> 1: Fairway faster); of the SciPy tolerance search / Fairway: {gm(search_ratios):.1f}; "
      f"rows where Fairway beats one solve: {sum(x > 1 for x in solve_ratios)} of {len(solve_ratios)}")
PY
