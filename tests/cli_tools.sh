#!/usr/bin/env bash
# What the camera options, --spp, --stats, progress, rtt rays, rtt compare
# and --version do when they succeed (their refusals are cli_errors.sh's).
set -euo pipefail
rtt="$1"
src="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scene="$src/scenes/demo.json"
fail() { echo "cli_tools: $*"; exit 1; }

"$rtt" --version | grep -Eq '^rtt [0-9]+\.[0-9]+\.[0-9]+$' || fail "--version"

# --view and the same camera given piece by piece render the same image;
# rtt info prints the camera a render uses and where it comes from
printf '{ "demo": { "camera": { "eye": [1, 1.5, 4], "look_at": [0, 0.5, 0], "fov": 45 } } }\n' >"$work/views.json"
"$rtt" render "$scene" --view "$work/views.json" --width 48 --height 48 -o "$work/view.exr"
"$rtt" render "$scene" --eye 1,1.5,4 --look-at 0,0.5,0 --up 0,1,0 --fov 45 --width 48 --height 48 -o "$work/eye.exr"
"$rtt" compare "$work/view.exr" "$work/eye.exr" --max-error 0
"$rtt" render "$scene" --width 48 --height 48 -o "$work/own.exr"
if "$rtt" compare "$work/own.exr" "$work/eye.exr" --max-error 0 2>/dev/null; then fail "--eye changed nothing"; fi
"$rtt" info "$scene" --engine reference --view "$work/views.json:demo" >"$work/info"
grep -q "camera      eye (1, 1.5, 4), look-at (0, 0.5, 0), up (0, 1, 0), fov 45 (the command line)" "$work/info" ||
    fail "info does not print the --view camera: $(grep camera "$work/info")"
"$rtt" info "$scene" --engine reference --lights camera | grep -q "lights      1 (0 sphere, 0 quad, 1 point) from one point light at the camera" ||
    fail "--lights camera"
# --lights view: the view's one light, as rtt bench lights it
printf '{ "lit": { "camera": { "eye": [1, 1.5, 4], "look_at": [0, 0.5, 0] }, "light": { "position": [1, 4, 2], "radius": 0.5 } } }\n' >"$work/lit.json"
"$rtt" info "$scene" --engine reference --view "$work/lit.json:lit" --lights view >"$work/info"
grep -q "lights      1 (1 sphere, 0 quad, 0 point) from the command line" "$work/info" &&
    grep -q "sphere at (1, 4, 2), colour (1, 1, 1), intensity 1, attenuation \[1, 0, 0\], radius 0.5" "$work/info" ||
    fail "--lights view: $(grep -A1 'lights ' "$work/info")"

# a bare mesh's default light follows the camera
"$rtt" info "$src/scenes/meshes/cube.obj" --engine reference --eye 3,2,1 >"$work/mesh.info"
grep -q "point  at (3, 2, 1)" "$work/mesh.info" || fail "the default light did not move with --eye"

# --stats: the wall times of every stage
"$rtt" render "$scene" --width 32 --height 32 --stats -o "$work/s.png" | grep -Eq "^stages \(wall\): load [0-9.]+ s, build [0-9.]+ s, render [0-9.]+ s, write [0-9.]+ s" ||
    fail "--stats has no stage times"

# progress past the threshold (2 s; RTT_PROGRESS_AFTER moves it), as lines when stderr is not a terminal
RTT_PROGRESS_AFTER=0.05 "$rtt" render "$scene" --width 160 --height 160 --spp 96 --engine reference --threads 1 -o "$work/slow.png" 2>"$work/progress"
grep -Eq "^rtt: rendering: [0-9]+% after [0-9.]+ s, about [0-9.]+ s left$" "$work/progress" ||
    fail "no progress lines: $(cat "$work/progress")"
grep -Eq "^rtt: rendering: done in [0-9.]+ s$" "$work/progress" || fail "no closing progress line"

# rtt rays: every kind, 32 bytes a ray, the same seed the same file
for kind in primary shadow random axis surface inside vertex split-planes extreme; do
    "$rtt" rays "$scene" --kind "$kind" -n 500 --seed 7 -o "$work/$kind.bin" >/dev/null
    size=$(stat -c %s "$work/$kind.bin")
    [ "$size" -gt 0 ] && [ $((size % 32)) -eq 0 ] && [ "$size" -le $((500 * 32)) ] || fail "rays $kind: $size bytes"
    "$rtt" rays "$scene" --kind "$kind" -n 500 --seed 7 -o "$work/$kind.again" >/dev/null
    cmp -s "$work/$kind.bin" "$work/$kind.again" || fail "rays $kind: not deterministic"
    "$rtt" trace "$scene" --rays "$work/$kind.bin" -o "$work/$kind.hits" >/dev/null
done
"$rtt" rays "$scene" --kind random -n 500 --seed 8 -o "$work/other.bin" >/dev/null
if cmp -s "$work/random.bin" "$work/other.bin"; then fail "rays random: the seed changes nothing"; fi

# compare: PNG with PNG and with the EXR it was written beside
"$rtt" render "$scene" --width 48 --height 48 -o "$work/both.exr" -o "$work/both.png"
"$rtt" compare "$work/both.png" "$work/both.png" --max-error 0
"$rtt" compare "$work/both.exr" "$work/both.png" --max-rmse 0.003 --max-error 0.005
echo "cli_tools: ok"
