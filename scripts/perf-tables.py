#!/usr/bin/env python3
"""The current figures of docs/PERFORMANCE.md: one markdown table per criterion benchmark group, read from
criterion's saved estimates (target/criterion/**/new/{benchmark,estimates}.json) after a bench run.

Usage: bash scripts/perf-tables.sh   (runs the benches, then this)
       python3 scripts/perf-tables.py [CRITERION_DIR]   (default target/criterion)

Each row: the bench, its mean time with criterion's 95 % interval, and the issue's target where one is set.
"""
import json
import os
import platform
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.environ.get("CARGO_TARGET_DIR", "target"), "criterion")

# Targets of issue 28 (a bench's full id, or its prefix, → target in ms).
TARGETS = {
    "curve100_s1000/full (setup + fair)": "0.150",
    "curve100_s1000/re-fair after tolerance change": "0.060",
    "curve100_s1000/re-fair after target edit": "0.060",
    "curve100_s1000/draft": "0.030",
    "surface fair/30x30 full": "5 (2 threads)",
    "surface fair/100x100 full": "45 (2 threads)",
    "surface draft/30x30": "4 (2 threads)",
}


def fmt(ns):
    ms = ns / 1e6
    return f"{ms:.3f} ms" if ms < 100 else f"{ms:.0f} ms"


def main():
    rows = {}
    for dirpath, _, files in os.walk(ROOT):
        if os.path.basename(dirpath) != "new" or "benchmark.json" not in files:
            continue
        b = json.load(open(os.path.join(dirpath, "benchmark.json")))
        e = json.load(open(os.path.join(dirpath, "estimates.json")))["mean"]
        group = b.get("group_id") or ""
        name = b.get("function_id") or ""
        if not name:
            # a bench outside a group: "curve100_s1000/full (setup + fair)" → group curve100_s1000
            group, _, name = group.partition("/")
        if b.get("value_str"):
            name = f"{name} {b['value_str']}".strip()
        ci = e["confidence_interval"]
        rows.setdefault(group, []).append((name, b.get("full_id", ""), e["point_estimate"], ci["lower_bound"], ci["upper_bound"]))
    if not rows:
        sys.exit(f"no criterion results under {ROOT}: run the benches first (scripts/perf-tables.sh)")
    print(f"Host: {platform.machine()}, {os.cpu_count()} cores, {platform.platform()}; "
          f"criterion means with their 95 % interval.\n")
    for group in sorted(rows):
        print(f"### {group}\n")
        print("| bench | mean | interval | target |")
        print("|---|---|---|---|")
        for name, full, mean, lo, hi in sorted(rows[group], key=lambda r: (len(r[0]), r[0])):
            target = next((t for k, t in TARGETS.items() if full.startswith(k)), "")
            print(f"| {name} | **{fmt(mean)}** | {fmt(lo)} – {fmt(hi)} | {target} |")
        print()


main()
