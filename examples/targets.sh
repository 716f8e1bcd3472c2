#!/usr/bin/env bash
# Runs the three real-part examples (a tunnel lining on a cylinder shell, a wall with a window
# and a door, a painted car-door panel from a mesh), copies their maps to docs/images/targets/
# and renders the painted panel's deposit in 3D (the triangle mesh its exports hold), for the
# README. Needs the command's `render` feature for the 3D view; prints each run's metrics.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet -p spraysim-cli --features render
mkdir -p docs/images/targets
bin=./target/release/spraysim
for scene in tunnel_lining wall_with_window door_panel; do
    "$bin" run "examples/$scene.toml" -o "out/$scene" -q
    python3 - "out/$scene/metrics.json" "$scene" <<'PY' 2>/dev/null || true
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
cp out/tunnel_lining/arch_thickness.png docs/images/targets/tunnel_arch_thickness.png
cp out/wall_with_window/wall_thickness.png docs/images/targets/wall_with_window_thickness.png
"$bin" render examples/door_panel.toml -o out/door_panel_view --camera iso -q
cp out/door_panel_view/view_end.png docs/images/targets/door_panel_3d.png
