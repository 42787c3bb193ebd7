#!/usr/bin/env bash
# rtt render --camera-path in one process: one frame per view, each byte for
# byte the render through that view (--view); with --path-frames the key
# frames' own cameras at the path's ends and where a frame meets a key, a
# camera between them elsewhere; the output patterns and the options that
# do not go with a path refused (exit 2); a bad path file is one line, exit
# 1, nothing written.
set -u
rtt=$(realpath "$1")
src=$(realpath "$2")
path="$src/tests/data/demo_path.json"
scene="$src/scenes/demo.json"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
failures=0
fail() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}
size=(--width 48 --height 36)

"$rtt" render "$scene" "${size[@]}" --camera-path "$path" -o view_%d.png -o view_%03d.exr ||
    fail "a three-view path failed"
for pair in 0:front 1:left 2:above; do
    frame=${pair%:*} name=${pair#*:}
    "$rtt" render "$scene" "${size[@]}" --view "$path:$name" -o "$name.png" || fail "--view $name failed"
    cmp -s "view_$frame.png" "$name.png" || fail "frame $frame is not the render through view $name"
    [ -s "view_00$frame.exr" ] || fail "frame $frame: no view_00$frame.exr"
done

"$rtt" render "$scene" "${size[@]}" --camera-path "$path" --path-frames 5 -o key_%d.png || fail "--path-frames 5 failed"
cmp -s key_0.png front.png || fail "key frame path: frame 0 is not the first view"
cmp -s key_2.png left.png || fail "key frame path: frame 2 (s = 1) is not the second view"
cmp -s key_4.png above.png || fail "key frame path: frame 4 is not the last view"
cmp -s key_1.png front.png && fail "key frame path: frame 1 did not move from the first view"
cmp -s key_1.png left.png && fail "key frame path: frame 1 is already at the second view"
[ -e key_5.png ] && fail "key frame path: a sixth frame"

expect_exit() { # CODE WHAT ARGS...
    local code="$1" what="$2"
    shift 2
    "$rtt" render "$scene" "${size[@]}" "$@" >out.log 2>&1
    local rc=$?
    [ "$rc" = "$code" ] || fail "$what: exit $rc, not $code: $(head -2 out.log)"
    [ "$(wc -l <out.log)" -le 2 ] || fail "$what: more than a line or two: $(cat out.log)"
}
expect_exit 2 "a path with an output without a frame number" --camera-path "$path" -o same.png
expect_exit 2 "a pattern with two numbers" --camera-path "$path" -o "f%d_%d.png"
expect_exit 2 "a pattern with %s" --camera-path "$path" -o "f%s.png"
expect_exit 2 "--path-frames without a path" --path-frames 4 -o f.png
expect_exit 2 "--eye with a path" --camera-path "$path" --eye 0,1,3 -o "f%d.png"
expect_exit 2 "--view with a path" --camera-path "$path" --view "$path:front" -o "f%d.png"
expect_exit 2 "--path-frames 0" --camera-path "$path" --path-frames 0 -o "f%d.png"
expect_exit 1 "a missing path file" --camera-path "$work/none.json" -o "missing_%d.png"
grep -q "none.json" out.log || fail "a missing path file: the message does not name it: $(cat out.log)"
printf '{"a": {"camera": {"eye": [0, 1, 3], "look_at": [0, 1, 3]}}}\n' >same_point.json
expect_exit 1 "a view looking at its own eye" --camera-path same_point.json -o "bad_%d.png"
ls missing_* bad_* >/dev/null 2>&1 && fail "a bad path left an output"
echo -n 'a literal percent sign in a pattern: ' && "$rtt" render "$scene" "${size[@]}" --camera-path "$path" -o "pct%%_%d.png" &&
    [ -s "pct%_1.png" ] && echo ok || fail "%% in a pattern is not a %"

[ "$failures" = 0 ] || { echo "camera_path: $failures failure(s)"; exit 1; }
echo "camera_path: ok"
