#!/usr/bin/env bash
# Runs the four Figure-4 scenes (same raster, four process set-ups) and copies their wall
# heatmaps and a 3D view of each with particles in flight (16 s into the raster) to
# docs/images/figure4/, where the README shows them side by side; then renders the animated GIF
# of the default scene. Needs the `render` feature (3D views) and a graphics adapter (Mesa's
# software drivers will do).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --features render
mkdir -p docs/images/figure4
# The camera of the 3D views: in front of the wall, to its left and above, looking at its centre.
view=(--set 'output.render={at=[16.0], size=[640,400], eye=[-2.6,-1.8,2.1], target=[-0.2,0.0,0.95]}')
for scene in figure4a_shotcrete_rebar figure4b_shotcrete figure4c_painting figure4d_blasting; do
    ./target/release/spraysim run "examples/$scene.toml" -o "out/$scene" -q "${view[@]}"
    cp "out/$scene/view_16.000s.png" "docs/images/figure4/${scene}_3d.png"
    cp "out/$scene/wall_hits.png" "docs/images/figure4/${scene}_hits.png"
    # Maps that have something to show: a deposit, or the coat left and the steel worn.
    for map in thickness coating erosion; do
        if [ -f "out/$scene/wall_$map.png" ]; then
            cp "out/$scene/wall_$map.png" "docs/images/figure4/${scene}_$map.png"
        fi
    done
    python3 - "out/$scene/metrics.json" "$scene" <<'PY' 2>/dev/null || true
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
./target/release/spraysim render -o out/default_3d --frames 30 --size 480x300 --at end -q
cp out/default_3d/animation.gif docs/images/default_3d.gif
