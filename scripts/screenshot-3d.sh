#!/bin/sh
# Screenshots of the 3D views under Xvfb with mesa's software renderer:
#   scripts/screenshot-3d.sh   -> docs/screenshot-isophotes.png, docs/screenshot-curvature.png,
#                                 docs/screenshot-extrusion.png, docs/screenshot-comb3d.png
# The bumpy sample surface faired as a whole (m = 4e-3), before and after side
# by side; the car roof's extrusion isophotes (1 degree stripes) before and after
# fairing u in [0.1, 0.9] at the document's 2 mm; the spatial curve's 3D comb
# with u in [0.2, 0.8] faired at the default tolerance. BIN picks the editor
# binary (default target/release/fairway-editor), WAIT the seconds before each
# shot (a debug build needs ~40 for the surfaces).
set -eu
cd "$(dirname "$0")/.."
export BIN=${BIN:-target/release/fairway-editor}
REGION="--region-uv 0 1 0 1 --tolerance 0.004 --side-by-side"
OUT=docs/screenshot-isophotes.png scripts/screenshot-editor.sh assets/bumpy_surface.json $REGION --shade isophotes
OUT=docs/screenshot-curvature.png scripts/screenshot-editor.sh assets/bumpy_surface.json $REGION --shade mean
OUT=docs/screenshot-extrusion.png scripts/screenshot-editor.sh assets/car_roof.ron --region 0.1 0.9 --extrusion --stripe 1
OUT=docs/screenshot-comb3d.png scripts/screenshot-editor.sh assets/spatial_curve.json --region 0.2 0.8 --view3d
