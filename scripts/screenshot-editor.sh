#!/bin/sh
# Screenshot of the editor under Xvfb with mesa's software renderer (llvmpipe):
#   scripts/screenshot-editor.sh [editor args...]     -> docs/screenshot-editor.png
# (e.g. `--region U1 U2 --tolerance M`; on a closed curve U1 > U2 selects the region across the seam)
# BIN picks the binary (default target/release/fairway-editor, built if missing),
# WAIT the seconds to wait before the shot, OUT the output file, W and H the
# window size (default 1500x1150: the side panel's measures fit without scrolling).
set -eu
cd "$(dirname "$0")/.."
BIN=${BIN:-target/release/fairway-editor}
OUT=${OUT:-docs/screenshot-editor.png}
W=${W:-1500}
H=${H:-1150}
[ -x "$BIN" ] || cargo build --release -p fairway-editor
mkdir -p /tmp/xdg "$(dirname "$OUT")" && chmod 700 /tmp/xdg
# a fresh data dir: settings saved by earlier runs (eframe storage) do not leak into the shot,
# and a fresh autosave dir: the autosave of an earlier (killed) shot does not raise the
# "Restore unsaved work?" prompt
DATA=$(mktemp -d)
export FAIRWAY_AUTOSAVE_DIR="$DATA/autosave"
# The screen is twice the window (WxH at the top left, no window manager):
# Xvfb parks the pointer at the screen's centre, outside the window, so no
# hover tooltip or cursor covers the shot; the shot is cropped to the window.
XDG_DATA_HOME=$DATA XDG_RUNTIME_DIR=/tmp/xdg WGPU_BACKEND=${WGPU_BACKEND:-vulkan} xvfb-run -a -s "-screen 0 $((2 * W))x$((2 * H))x24" \
  sh -c "\"$BIN\" --window-size $W $H $* & pid=\$!; sleep ${WAIT:-12}; import -window root -crop ${W}x${H}+0+0 +repage \"$OUT\"; kill \$pid"
rm -rf "$DATA"
echo "wrote $OUT"
