#!/usr/bin/env bash
# The paper's Figure 4: runs the four Figure-4 scenes (the same raster, four process set-ups, and
# the painting one again with an HVLP gun),
# collects each wall's heatmaps and a 3D view with the particles in flight (16 s into the
# raster), then renders the default scene as an animated GIF. docs/examples.md shows them.
#
# Needs: the command's `render` feature (3D views), which this script builds first with
# `cargo build --release --features render` (about five more minutes of build the first time),
# and a graphics adapter (any GPU, or Mesa's software drivers: docs/3d.md). It checks both
# before the runs and stops saying what is missing. python3 prints each run's metrics (skipped
# without it).
#
# Usage: bash examples/figure4.sh [--update-docs]
# Writes the runs to out/figure4/SCENE/ and the figures to out/figure4/images/. With
# --update-docs it also copies the figures over the tracked images in docs/images/figure4/
# and docs/images/default_3d.gif.
set -euo pipefail
cd "$(dirname "$0")/.."
source examples/common.sh
parse_args "$@"
out=out/figure4
mkdir -p "$out/images"
require_render "$out"
# The camera of the 3D views: in front of the wall, to its left and above, looking at its centre.
view=(--set 'output.render={at=[16.0], size=[640,400], eye=[-2.6,-1.8,2.1], target=[-0.2,0.0,0.95]}')
# figure4c_painting_hvlp re-runs (c) with an HVLP gun: its droplets in the gun's air, and the dry film.
for scene in figure4a_shotcrete_rebar figure4b_shotcrete figure4c_painting figure4c_painting_hvlp figure4d_blasting; do
    "$bin" run "examples/$scene.toml" -o "$out/$scene" -q "${view[@]}"
    cp "$out/$scene/view_16.000s.png" "$out/images/${scene}_3d.png"
    cp "$out/$scene/wall_hits.png" "$out/images/${scene}_hits.png"
    # Maps that have something to show: a deposit, or the coat left and the steel worn.
    for map in thickness dry_thickness coating erosion; do
        if [ -f "$out/$scene/wall_$map.png" ]; then
            cp "$out/$scene/wall_$map.png" "$out/images/${scene}_$map.png"
        fi
    done
    python3 - "$out/$scene/metrics.json" "$scene" <<'PY' 2>/dev/null || true
import json, sys
m = json.load(open(sys.argv[1]))
w = m["targets"][0]
pct = lambda x: "n/a" if x is None else f"{100 * x:.1f} %"
print(f"{sys.argv[2]}: transfer efficiency {pct(m['transfer_efficiency'])}, rebound {pct(m['rebound_ratio'])}, "
      f"wall mean {1e3 * w['thickness']['mean']:.2f} mm, hits {w['hits']}, failures {len(m['failures']['events'])}"
      + (f", cleaned {100 * w['erosion']['cleaned_fraction']:.1f} % of the wall" if w.get('erosion') and w['erosion']['cleaned_fraction'] is not None else ""))
PY
done
# The default scene as an animation: 30 frames over its 2 s.
"$bin" render -o "$out/default_3d" --frames 30 --size 480x300 --at end -q
cp "$out/default_3d/animation.gif" "$out/images/default_3d.gif"
if [ "$update_docs" = 1 ]; then
    mkdir -p docs/images/figure4
    cp "$out"/images/figure4*.png docs/images/figure4/
    cp "$out/images/default_3d.gif" docs/images/default_3d.gif
    echo "updated docs/images/figure4/ and docs/images/default_3d.gif"
else
    echo "figures in $out/images/ (bash examples/figure4.sh --update-docs copies them into docs/images/)"
fi
