#!/usr/bin/env bash
# rtt view without a display: scripts played under Xvfb (xvfb-run).
#  - a screenshot of the start camera equals `rtt render` of the scene;
#  - after moving (keys held, a mouse drag) the screenshot equals `rtt render
#    --view` of the camera the viewer prints as a views.json entry;
#  - --eye/--look-at start the viewer where rtt render looks from;
#  - at rest the picture converges to rtt render --spp N's, moving restarts at 1;
#  - T, G and I change what the overlay reports (traversal, shadows, ISA),
#    Home resets the camera, resize follows the window;
#  - a bad script is one line naming file and line, exit 1.
# One Xvfb for the whole test, on a display it picks itself (-displayfd), so
# parallel runs of the suite never race for a display number as xvfb-run -a
# can.  Skipped (77) when Xvfb is missing or rtt was built without the viewer.
set -uo pipefail
rtt=$1
src=$2
if ! command -v Xvfb >/dev/null || ! command -v jq >/dev/null; then
  echo "viewer_headless: Xvfb or jq missing: skipped"; exit 77
fi
if ! "$rtt" view --help >/dev/null 2>&1; then
  echo "viewer_headless: rtt has no view command: skipped"; exit 77
fi
work=$(mktemp -d)
xvfb_pid=
trap '[ -n "$xvfb_pid" ] && kill "$xvfb_pid" 2>/dev/null; rm -rf "$work"' EXIT
fail() { echo "viewer_headless: FAIL: $*"; exit 1; }
Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>"$work/display" >"$work/xvfb.log" 2>&1 &
xvfb_pid=$!
for _ in $(seq 100); do [ -s "$work/display" ] && break; sleep 0.1; done
[ -s "$work/display" ] || fail "Xvfb did not start: $(cat "$work/xvfb.log")"
export DISPLAY=":$(cat "$work/display")"
# In a sanitizer build, the X and GL drivers SDL loads with dlopen keep
# allocations until exit that LeakSanitizer cannot attribute to a library
# (fuzz/lsan.supp cannot name them); leak checks stay on for every other test.
view() { ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" "$rtt" view "$@"; }
scene=$src/scenes/demo.json
size=(--width 96 --height 80)
one=(--spp 1) # no converging: each frame is the one-sample picture rtt render makes

# 1. the start camera: the same picture as rtt render
printf 'frames 1\n' >"$work/still.txt"
view "$scene" "${size[@]}" "${one[@]}" --script "$work/still.txt" --screenshot "$work/still.exr" >/dev/null ||
  fail "still script"
"$rtt" render "$scene" "${size[@]}" -o "$work/render.exr" || fail "render"
"$rtt" compare "$work/still.exr" "$work/render.exr" --max-error 0 >/dev/null ||
  fail "start screenshot differs from rtt render: $("$rtt" compare "$work/still.exr" "$work/render.exr")"

# 2. moved: keys held and a drag; the printed camera renders the same picture
cat >"$work/move.txt" <<'SCRIPT'
key w 6      # forward for 6 frames of 1/30 s
key d 3
key e 2
drag 25 -10  # look right and up
print-camera
SCRIPT
view "$scene" "${size[@]}" "${one[@]}" --script "$work/move.txt" --screenshot "$work/moved.exr" >"$work/move.out" ||
  fail "move script"
grep -q '^"view": {"camera": {"eye": \[' "$work/move.out" || fail "no camera printed: $(cat "$work/move.out")"
# the printed line is a views.json entry: wrapped in braces it is a views file
echo "{$(grep '^"view":' "$work/move.out")}" >"$work/views.json"
jq -e '.view.camera.eye | length == 3' "$work/views.json" >/dev/null || fail "not a views.json entry: $(cat "$work/views.json")"
"$rtt" render "$scene" "${size[@]}" --view "$work/views.json:view" -o "$work/moved_render.exr" || fail "render moved"
"$rtt" compare "$work/moved.exr" "$work/moved_render.exr" --max-error 0 >/dev/null ||
  fail "moved screenshot differs from rtt render of its camera"
if "$rtt" compare "$work/moved.exr" "$work/still.exr" --max-rmse 0.001 >/dev/null 2>&1; then
  fail "moving the camera did not change the picture"
fi

# 2b. the camera options of rtt render start the viewer there
eye=(--eye 0.3,1.2,2.5 --look-at 0,0.8,0 --fov 50)
view "$scene" "${size[@]}" "${one[@]}" "${eye[@]}" --script "$work/still.txt" --screenshot "$work/eye.exr" >/dev/null ||
  fail "--eye script"
"$rtt" render "$scene" "${size[@]}" "${eye[@]}" -o "$work/eye_render.exr" || fail "render --eye"
"$rtt" compare "$work/eye.exr" "$work/eye_render.exr" --max-error 0 >/dev/null ||
  fail "--eye screenshot differs from rtt render --eye"

# 2c. at rest the picture converges: 1, 2, 4, 8 samples per pixel, the last
# exactly rtt render --spp 8; moving starts again from one
printf 'print-overlay\nconverge\nprint-overlay\nscreenshot %s\nkey w 2\nprint-overlay\n' "$work/conv.exr" >"$work/conv.txt"
view "$scene" "${size[@]}" --spp 8 --script "$work/conv.txt" >"$work/conv.out" || fail "converge script"
"$rtt" render "$scene" "${size[@]}" --spp 8 -o "$work/conv_render.exr" || fail "render --spp 8"
"$rtt" compare "$work/conv.exr" "$work/conv_render.exr" --max-error 0 >/dev/null ||
  fail "converged screenshot differs from rtt render --spp 8"
mapfile -t conv < <(grep '^rtt view |' "$work/conv.out")
[[ "${conv[0]}" == *"| spp 1/8" ]] && [[ "${conv[1]}" == *"| spp 8/8" ]] && [[ "${conv[2]}" == *"| spp 1/8" ]] ||
  fail "converging overlay: ${conv[*]}"

# 3. the keys change what the overlay reports; Home resets; resize follows
cat >"$work/keys.txt" <<'SCRIPT'
print-overlay
key t
print-overlay
key g
print-overlay
key i
print-overlay
print-camera
key w 4
key Home
print-camera
resize 64 48
print-overlay
screenshot RESIZED
SCRIPT
sed -i "s|RESIZED|$work/resized.png|" "$work/keys.txt"
view "$scene" "${size[@]}" "${one[@]}" --isa avx2 --script "$work/keys.txt" >"$work/keys.out" 2>"$work/keys.err" ||
  fail "keys script: $(cat "$work/keys.err")"
mapfile -t overlay < <(grep '^rtt view |' "$work/keys.out")
[ "${#overlay[@]}" -eq 5 ] || fail "expected 5 overlay lines: $(cat "$work/keys.out")"
field() { echo "$1" | awk -F' [|] ' -v k="$2" '{print $k}'; }
[ "$(field "${overlay[0]}" 4)" = "kd mft/avx2" ] || fail "start overlay: ${overlay[0]}"
[ "$(field "${overlay[1]}" 4)" != "$(field "${overlay[0]}" 4)" ] || fail "T did not change the traversal"
[ "$(field "${overlay[2]}" 5)" != "$(field "${overlay[1]}" 5)" ] || fail "G did not change the shadows"
[ "$(field "${overlay[3]}" 4)" != "$(field "${overlay[2]}" 4)" ] || fail "I did not change the instruction set"
[ "$(field "${overlay[0]}" 6)" = "96x80" ] || fail "start size: ${overlay[0]}"
[ "$(field "${overlay[4]}" 6)" = "64x48" ] || fail "resize not followed: ${overlay[4]}"
mapfile -t cams < <(grep '^"view":' "$work/keys.out")
[ "${cams[0]}" = "${cams[1]}" ] || fail "Home did not reset the camera: ${cams[0]} / ${cams[1]}"
file "$work/resized.png" | grep -q '64 x 48' || fail "resized screenshot: $(file "$work/resized.png")"

# 4. a bad script: one line with file and line, exit 1
printf 'frames 1\nfly 3\n' >"$work/bad.txt"
view "$scene" "${size[@]}" --script "$work/bad.txt" >/dev/null 2>"$work/bad.err"
rc=$?
[ "$rc" -eq 1 ] || fail "bad script exit $rc"
[ "$(wc -l <"$work/bad.err")" -eq 1 ] && grep -q "bad.txt:2: unknown command \"fly\"" "$work/bad.err" ||
  fail "bad script message: $(cat "$work/bad.err")"
printf 'key NoSuchKey\n' >"$work/badkey.txt"
view "$scene" "${size[@]}" --script "$work/badkey.txt" >/dev/null 2>"$work/badkey.err"
[ $? -eq 1 ] && grep -q 'badkey.txt:1: unknown key "NoSuchKey"' "$work/badkey.err" ||
  fail "bad key message: $(cat "$work/badkey.err")"
echo "viewer_headless: ok"
