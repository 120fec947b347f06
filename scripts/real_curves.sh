#!/usr/bin/env bash
# Fairness on real CAD curves (issue 25): downloads public IGES data — the impeller and sample models that
# ship in the `pyiges` package on PyPI (MIT licence) — into a throw-away folder and runs
# `examples/real_curves.rs` on it: every distinct B-spline curve with 8 or more control points, faired at
# 5e-4 × its bounding-box diagonal by the reference smoother and by Fairway's default.
# Not part of CI (it needs the network); nothing downloaded is committed.
#
#   bash scripts/real_curves.sh [--markdown]
set -euo pipefail
cd "$(dirname "$0")/.."
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 -m pip download --quiet --no-deps --dest "$dir" 'pyiges==0.3.4'
python3 -m zipfile -e "$dir"/pyiges-0.3.4-py3-none-any.whl "$dir/x"
cargo run --quiet --release -p fairway --example real_curves -- \
    "$dir/x/pyiges/examples/impeller.igs" "$dir/x/pyiges/examples/sample.igs" "$@"
