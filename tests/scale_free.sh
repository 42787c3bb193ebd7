#!/usr/bin/env bash
# Scale-free and place-free rendering: a scene scaled by s and moved by o
# (camera, lights and every length of the scene with it) renders the image of
# s = 1, o = 0 within the golden tolerance (rmse 1e-3 here, at most 2 pixels
# of 4096 off by more than 1/255, as golden/README.md allows at silhouettes),
# with the optimized engine and the reference.  The cases:
#   plain     one lit triangle over a floor, a point light without fall-off:
#             scales 1e-20 and 1e20, offsets 1e5 and 1e7 (scene 4 units wide)
#   atten     the same lit by a point light and a sphere light with distance
#             fall-off (attenuation over attenuation_distance, scaled with the
#             scene): scales 1e-20, 1e-12, 1e10 and 1e20, offset 1e5
#   material  a reflective backdrop, a transparent-reflective pane and a
#             diffuse block over a floor (secondary rays and shadow rays
#             through the pane, their offsets relative to the scene),
#             attenuated light: scales 1e-20 and 1e20, offset 1e5
# and plain at 1e7 with its camera given by --eye/--look-at and by a views
# file's view, which are read in double too.
set -u
rtt="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
cases="plain:1e-20:0 plain:1e20:0 plain:1:1e5 plain:1:1e7
atten:1e-20:0 atten:1e-12:0 atten:1e10:0 atten:1e20:0 atten:1:1e5
material:1e-20:0 material:1e20:0 material:1:1e5"

python3 - "$work" $cases plain:1:0 atten:1:0 material:1:0 plain:dark:0 atten:dark:0 material:dark:0 <<'PY'
import json, sys
work = sys.argv[1]
for case in sys.argv[2:]:
    name, scale, offset = case.split(":")
    dark = scale == "dark"  # the same at scale 1 with every light off: what an unlit render would be
    scale = "1" if dark else scale
    s, o = float(scale), float(offset)
    p = lambda x, y, z: [x * s + o, y * s + o, z * s + o]
    floor = {"vertices": [p(-2, -1, -2), p(2, -1, -2), p(2, -1, 2), p(-2, -1, 2)], "triangles": [[0, 1, 2], [0, 2, 3]]}
    scene = {"camera": {"eye": p(0.3, 0.8, 3), "look_at": p(0, 0, 0), "fov": 40}, "image": {"width": 64, "height": 64}}
    if name == "plain":
        scene["lights"] = [{"type": "point", "position": p(0.5, 1.5, 2), "color": [1, 1, 1], "intensity": 1.0}]
        scene["meshes"] = [{"vertices": [p(-1, -1, 0), p(1, -1, 0), p(0, 1, 0)], "triangles": [[0, 1, 2]]}, floor]
    elif name == "atten":
        scene["lights"] = [
            {"type": "point", "position": p(0.5, 1.5, 2), "intensity": 3, "attenuation": [0.5, 0.6, 0.3],
             "attenuation_distance": s},
            {"type": "sphere", "position": p(-1.5, 1, 1), "radius": 0.3 * s, "color": [1, 0.8, 0.6], "intensity": 2,
             "attenuation": [0.2, 0, 1], "attenuation_distance": 2 * s}]
        scene["meshes"] = [{"vertices": [p(-1, -1, 0), p(1, -1, 0), p(0, 1, 0)], "triangles": [[0, 1, 2]]}, floor]
    else:
        scene["background"] = [0.15, 0.18, 0.25]
        scene["materials"] = [
            {"name": "mirror", "type": "reflective", "diffuse": [0.3, 0.3, 0.5], "reflection": 0.6},
            {"name": "pane", "type": "transparent_reflective", "diffuse": [0.95, 1, 0.95], "reflection": 0.15,
             "transparency": 0.75, "ior": 1.5},
            {"name": "block", "diffuse": [0.8, 0.2, 0.15]}]
        scene["lights"] = [{"position": p(1, 2.5, 2.5), "intensity": 4, "attenuation": [0.3, 0.4, 0.3],
                            "attenuation_distance": 1.5 * s}]
        scene["meshes"] = [
            floor,
            {"vertices": [p(-2, -1, -1.5), p(2, -1, -1.5), p(2, 1.5, -1.5), p(-2, 1.5, -1.5)],
             "triangles": [[0, 1, 2], [0, 2, 3]], "material": "mirror"},
            {"vertices": [p(-0.9, -1, 0.6), p(0.7, -1, 0.9), p(-0.1, 0.8, 0.7)], "triangles": [[0, 1, 2]],
             "material": "pane"},
            {"vertices": [p(0.2, -1, -0.6), p(1.2, -1, -0.4), p(0.7, 0.4, -0.5)], "triangles": [[0, 1, 2]],
             "material": "block"}]
    for light in scene["lights"]:
        light["intensity"] = 0 if dark else light["intensity"]
    json.dump(scene, open(f"{work}/{case}.json", "w"))
PY

for case in plain:1:0 atten:1:0 material:1:0 $cases; do
    for engine in optimized reference; do
        "$rtt" render "$work/$case.json" --engine "$engine" -o "$work/${engine}_$case.exr" ||
            { echo "FAIL: render $case $engine"; failures=$((failures + 1)); }
    done
done
for case in $cases; do
    base="${case%%:*}:1:0"
    for engine in optimized reference; do
        out=$("$rtt" compare "$work/${engine}_$base.exr" "$work/${engine}_$case.exr" --json) || true
        python3 - "$out" "$case" "$engine" "$work/${engine}_$base.exr" <<'PY' || failures=$((failures + 1))
import json, sys
r = json.loads(sys.argv[1])
ok = r["rmse"] <= 1e-3 and r["pixels_over_1_255"] <= 2
print(f"{sys.argv[3]} {sys.argv[2]} (scene:scale:offset): rmse {r['rmse']:.3g}, max error {r['max_error']:.3g}, "
      f"pixels off {r['pixels_over_1_255']}: {'ok' if ok else 'FAIL'}")
sys.exit(0 if ok else 1)
PY
    done
done
# the camera from the command line and from a views file, 1e7 from the
# origin, replacing the scene file's other one: read in double as the file's
far=$(python3 -c 'import json, sys; c = json.load(open(sys.argv[1])); print(",".join(map(repr, c["camera"]["eye"])), ",".join(map(repr, c["camera"]["look_at"])))' "$work/plain:1:1e7.json")
python3 - "$work/plain:1:1e7.json" "$work/views.json" "$work/other_camera.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
json.dump({"far": {"camera": scene["camera"]}}, open(sys.argv[2], "w"))
# the scene with another camera and light, which the options replace
scene["camera"]["eye"] = [1e7 + 3, 1e7 + 2, 1e7 - 4]
json.dump(scene, open(sys.argv[3], "w"))
PY
for engine in optimized reference; do
    "$rtt" render "$work/other_camera.json" --engine "$engine" --eye "${far% *}" --look-at "${far#* }" \
        -o "$work/${engine}_eye.exr" || { echo "FAIL: render --eye $engine"; failures=$((failures + 1)); }
    "$rtt" render "$work/other_camera.json" --engine "$engine" --view "$work/views.json:far" \
        -o "$work/${engine}_view.exr" || { echo "FAIL: render --view $engine"; failures=$((failures + 1)); }
    for how in eye view; do
        out=$("$rtt" compare "$work/${engine}_plain:1:0.exr" "$work/${engine}_$how.exr" --json) || true
        python3 - "$out" "$how" "$engine" <<'PY' || failures=$((failures + 1))
import json, sys
r = json.loads(sys.argv[1])
ok = r["rmse"] <= 1e-3 and r["pixels_over_1_255"] <= 2
print(f"{sys.argv[3]} plain:1:1e7 with --{'eye/--look-at' if sys.argv[2] == 'eye' else 'view'}: rmse {r['rmse']:.3g}, "
      f"pixels off {r['pixels_over_1_255']}: {'ok' if ok else 'FAIL'}")
sys.exit(0 if ok else 1)
PY
    done
done
# the lights matter: each scale-1 image is far from the same scene unlit
for name in plain atten material; do
    "$rtt" render "$work/$name:dark:0.json" -o "$work/dark_$name.exr" || { echo "FAIL: render $name unlit"; failures=$((failures + 1)); }
    out=$("$rtt" compare "$work/optimized_$name:1:0.exr" "$work/dark_$name.exr" --json) || true
    python3 - "$out" "$name" <<'PY' || failures=$((failures + 1))
import json, sys
r = json.loads(sys.argv[1])
ok = r["rmse"] > 0.02
print(f"{sys.argv[2]} at scale 1 against unlit: rmse {r['rmse']:.3g}: {'ok (lit)' if ok else 'FAIL (the lights do not show)'}")
sys.exit(0 if ok else 1)
PY
done
[ "$failures" -eq 0 ] && echo "scale free: all cases passed"
exit $((failures > 0))
