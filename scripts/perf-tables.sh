#!/usr/bin/env bash
# Refresh the current figures of docs/PERFORMANCE.md: run the criterion benches (short runs: 1 s warm-up,
# 3 s measurement), then print one markdown table per bench group (scripts/perf-tables.py). Paste the
# output into the "Current figures" section, with the date. Takes about 10 minutes on 2 cores; run it
# on an otherwise idle machine.
#
# Usage: bash scripts/perf-tables.sh [FILTER]   (FILTER: a criterion name filter, default all)
set -euo pipefail
cd "$(dirname "$0")/.."
FILTER=${1:-}
for bench in fairing surface_fairing geometry; do
    cargo bench --quiet -p fairway --bench "$bench" -- --warm-up-time 1 --measurement-time 3 ${FILTER:+"$FILTER"} >&2
done
python3 scripts/perf-tables.py
