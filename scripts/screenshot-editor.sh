#!/bin/sh
# Screenshot of the editor under Xvfb with mesa's software renderer (llvmpipe):
#   scripts/screenshot-editor.sh [editor args...]     -> docs/screenshot-editor.png
# BIN picks the binary (default target/release/fairway-editor, built if missing),
# WAIT the seconds to wait before the shot, OUT the output file.
set -eu
cd "$(dirname "$0")/.."
BIN=${BIN:-target/release/fairway-editor}
OUT=${OUT:-docs/screenshot-editor.png}
[ -x "$BIN" ] || cargo build --release -p fairway-editor
mkdir -p /tmp/xdg "$(dirname "$OUT")" && chmod 700 /tmp/xdg
# a fresh data dir: settings saved by earlier runs (eframe storage) do not leak into the shot
DATA=$(mktemp -d)
XDG_DATA_HOME=$DATA XDG_RUNTIME_DIR=/tmp/xdg WGPU_BACKEND=${WGPU_BACKEND:-vulkan} xvfb-run -a -s "-screen 0 1500x950x24" \
  sh -c "\"$BIN\" $* & pid=\$!; sleep ${WAIT:-12}; import -window root \"$OUT\"; kill \$pid"
rm -rf "$DATA"
echo "wrote $OUT"
