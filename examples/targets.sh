#!/usr/bin/env bash
# Real parts: runs the three real-part examples (a tunnel lining on a cylinder shell, a wall
# with a window and a door, a painted car-door panel from a mesh), collects their maps, and
# renders the painted panel's deposit in 3D (the triangle mesh its exports hold); prints each
# run's metrics. docs/examples.md shows them.
#
# Needs: the command's `render` feature (the panel's 3D view), which this script builds first
# with `cargo build --release --features render` (about five more minutes of build the first
# time), and a graphics adapter (any GPU, or Mesa's software drivers: docs/3d.md). It checks
# both before the runs and stops saying what is missing. python3 prints each run's metrics
# (skipped without it).
#
# Usage: bash examples/targets.sh [--update-docs]
# Writes the runs to out/targets/SCENE/ and the figures to out/targets/images/. With
# --update-docs it also copies the figures over the tracked images in docs/images/targets/.
set -euo pipefail
cd "$(dirname "$0")/.."
source examples/common.sh
parse_args "$@"
out=out/targets
mkdir -p "$out/images"
require_render "$out"
for scene in tunnel_lining wall_with_window door_panel; do
    "$bin" run "examples/$scene.toml" -o "$out/$scene" -q
    python3 - "$out/$scene/metrics.json" "$scene" <<'PY' 2>/dev/null || true
import json, sys
m = json.load(open(sys.argv[1]))
t = m["targets"][0]
s = t["thickness"]
pct = lambda x: "n/a" if x is None else f"{100 * x:.1f} %"
unit, k = ("µm", 1e6) if s["max"] < 1e-3 else ("mm", 1e3)
print(f"{sys.argv[2]}: {t['name']} mean {k * s['mean']:.1f} {unit}, CV {pct(s['cv'])}, "
      f"in tolerance {pct(s['in_tolerance'])} of {s['area']:.2f} m², "
      f"transfer efficiency {pct(m['transfer_efficiency'])}, rebound {pct(m['rebound_ratio'])}")
PY
done
cp "$out/tunnel_lining/arch_thickness.png" "$out/images/tunnel_arch_thickness.png"
cp "$out/wall_with_window/wall_thickness.png" "$out/images/wall_with_window_thickness.png"
"$bin" render examples/door_panel.toml -o "$out/door_panel_view" --camera iso -q
cp "$out/door_panel_view/view_end.png" "$out/images/door_panel_3d.png"
if [ "$update_docs" = 1 ]; then
    mkdir -p docs/images/targets
    cp "$out"/images/*.png docs/images/targets/
    echo "updated docs/images/targets/"
else
    echo "figures in $out/images/ (bash examples/targets.sh --update-docs copies them into docs/images/)"
fi
