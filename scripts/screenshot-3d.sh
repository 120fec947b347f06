#!/bin/sh
# Screenshots of the 3D views under Xvfb with mesa's software renderer:
#   scripts/screenshot-3d.sh   -> docs/screenshot-isophotes.png, docs/screenshot-curvature.png,
#                                 docs/screenshot-extrusion.png
# The bumpy sample surface, before and after fairing side by side. BIN picks
# the editor binary (default target/release/fairway-editor).
set -eu
cd "$(dirname "$0")/.."
export BIN=${BIN:-target/release/fairway-editor}
REGION="--region-uv 0.1 0.9 0.1 0.9 --tolerance 0.006 --side-by-side"
OUT=docs/screenshot-isophotes.png scripts/screenshot-editor.sh assets/bumpy_surface.json $REGION --shade isophotes
OUT=docs/screenshot-curvature.png scripts/screenshot-editor.sh assets/bumpy_surface.json $REGION --shade mean
OUT=docs/screenshot-extrusion.png scripts/screenshot-editor.sh assets/car_roof.ron --region 0.1 0.9 --extrusion
