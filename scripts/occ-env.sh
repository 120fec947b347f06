# Sourced by the OpenCASCADE comparison scripts (step_roundtrip_occ.sh, step_assembly_occ.sh): a
# throw-away venv with cadquery-ocp at VENV (the script's first argument, default /tmp/occ-venv), the
# release `fairway` binary in FAIRWAY (built here unless FAIRWAY names one), and a scratch folder WORK removed on exit.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${1:-/tmp/occ-venv}
if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c 'import OCP' 2>/dev/null; then
    python3 -m venv "$VENV"
    "$VENV/bin/pip" install --quiet cadquery-ocp
fi
# FAIRWAY=/path/to/fairway uses that binary as it is (no build)
if [ -z "${FAIRWAY:-}" ]; then
    cargo build --release --quiet -p fairway-cli
    FAIRWAY=${CARGO_TARGET_DIR:-$PWD/target}/release/fairway
fi
WORK=$(mktemp -d /tmp/fairway-occ-XXXXXX)
trap 'rm -rf "$WORK"' EXIT
