#!/usr/bin/env bash
# Textures on the command line: a scene whose texture files are missing
# renders (exit 0) with exactly one warning line naming the first missing
# file and how many; a textured scene cannot be baked (exit 1, one line, no
# file left); `rtt info` reports the textures and their memory.
set -u
rtt="$1"
src="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

cat >"$work/missing.json" <<'JSON'
{
  "materials": [{"name": "a", "diffuse_map": "gone/a.tga"}, {"name": "b", "normal_map": "gone/b.png"}],
  "meshes": [
    {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "triangles": [[0, 1, 2]], "texcoords": [[0, 0], [1, 0], [0, 1]], "material": "a"},
    {"vertices": [[0, 0, 1], [1, 0, 1], [0, 1, 1]], "triangles": [[0, 1, 2]], "material": "b"}
  ]
}
JSON
"$rtt" render "$work/missing.json" --width 16 --height 16 -o "$work/m.png" 2>"$work/err"
code=$?
[ "$code" -eq 0 ] || fail "render with missing textures exited $code"
[ -s "$work/m.png" ] || fail "render with missing textures wrote no image"
[ "$(wc -l <"$work/err")" -eq 1 ] || fail "expected one warning line, got: $(cat "$work/err")"
grep -Eq "warning: .*missing\.json: 2 textures not read.*gone/a\.tga" "$work/err" ||
    fail "the warning does not name the count and the first file: $(cat "$work/err")"

"$rtt" bake "$src/scenes/tex_diffuse.json" -o "$work/t.kdt" 2>"$work/err"
code=$?
[ "$code" -eq 1 ] || fail "bake of a textured scene exited $code (want 1)"
[ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "does not carry textures" "$work/err" ||
    fail "bake of a textured scene: $(cat "$work/err")"
ls "$work"/t.kdt* >/dev/null 2>&1 && fail "bake of a textured scene left a file"

"$rtt" info "$src/scenes/tex_normal.json" >"$work/info" 2>"$work/err" || fail "info on tex_normal.json failed"
grep -Eq "^  textures    2, [0-9.]+ MiB" "$work/info" || fail "info does not list the textures: $(cat "$work/info")"
[ -s "$work/err" ] && fail "info on a complete textured scene warned: $(cat "$work/err")"

[ "$failures" -eq 0 ] && echo "cli_textures: ok"
[ "$failures" -eq 0 ]
