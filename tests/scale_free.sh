#!/usr/bin/env bash
# Scale-free shading: one lit triangle over a floor (point light, no
# attenuation), scaled by 1e-20 and 1e20 (camera and light with it), renders
# the scale-1 image within the golden tolerance (rmse 1e-3 here, no pixel
# off by more than 1/255), with the optimized engine and the reference.
# Not checked here: the same scene moved 1e5 from the origin, whose camera
# and light the schema still reads in float (0.008 spacing at 1e5: the view
# itself moves; 3 pixels off today).
set -u
rtt="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
for variant in 1:0 1e-20:0 1e20:0; do
    python3 - "$variant" "$work" <<'PY'
import json, sys
scale, offset = (float(x) for x in sys.argv[1].split(":"))
p = lambda x, y, z: [x * scale + offset, y * scale + offset, z * scale + offset]
scene = {"camera": {"eye": p(0.3, 0.8, 3), "look_at": p(0, 0, 0), "fov": 40}, "image": {"width": 64, "height": 64},
         "lights": [{"type": "point", "position": p(0.5, 1.5, 2), "color": [1, 1, 1], "intensity": 1}],
         "meshes": [{"vertices": [p(-1, -1, 0), p(1, -1, 0), p(0, 1, 0)], "triangles": [[0, 1, 2]]},
                    {"vertices": [p(-2, -1, -2), p(2, -1, -2), p(2, -1, 2), p(-2, -1, 2)], "triangles": [[0, 1, 2], [0, 2, 3]]}]}
json.dump(scene, open(f"{sys.argv[2]}/scene_{sys.argv[1]}.json", "w"))
PY
    for engine in optimized reference; do
        "$rtt" render "$work/scene_$variant.json" --engine "$engine" -o "$work/${engine}_$variant.exr" ||
            { echo "FAIL: render $variant $engine"; failures=$((failures + 1)); }
    done
done
for variant in 1e-20:0 1e20:0; do
    for engine in optimized reference; do
        out=$("$rtt" compare "$work/${engine}_1:0.exr" "$work/${engine}_$variant.exr" --json) || true
        python3 - "$out" "$variant" "$engine" <<'PY' || failures=$((failures + 1))
import json, sys
r = json.loads(sys.argv[1])
ok = r["rmse"] <= 1e-3 and r["pixels_over_1_255"] == 0
print(f"{sys.argv[3]} at {sys.argv[2]}: rmse {r['rmse']:.3g}, pixels off {r['pixels_over_1_255']}: {'ok' if ok else 'FAIL'}")
sys.exit(0 if ok else 1)
PY
    done
done
exit $((failures > 0))
