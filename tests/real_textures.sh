#!/usr/bin/env bash
# The OpenArena maps of the data cache textured from the cached pk3 archives
# (bench/fetch-scenes.sh): every map loads with no texture missing, at least
# one texture per ten materials, and renders from its bench view in both
# engines with the images agreeing.  Exits 77 (skipped) when the cache lacks
# the maps or the archives.
set -u
rtt="$1"
src="$2"
data="${RTT_DATA_DIR:-$HOME/.cache/rtt-data}"
for f in maps/oa_dm4.bsp maps/ctf_inyard.bsp maps/czest3ctf.bsp pk3/pak0.pk3 pk3/pak4-textures.pk3; do
    [ -s "$data/$f" ] || { echo "real_textures: $data/$f is missing (bench/fetch-scenes.sh fetches it): skipped"; exit 77; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
for map in oa_dm4 ctf_inyard czest3ctf; do
    "$rtt" info "$data/maps/$map.bsp" >"$work/info" 2>"$work/err" || { fail "$map: info failed"; continue; }
    [ -s "$work/err" ] && fail "$map: $(cat "$work/err")"
    materials=$(sed -n 's/^  materials   \([0-9]*\):.*/\1/p' "$work/info")
    textures=$(sed -n 's/^  textures    \([0-9]*\),.*/\1/p' "$work/info")
    [ -n "$textures" ] && [ "$textures" -gt 0 ] && [ $((textures * 10)) -ge "$materials" ] ||
        fail "$map: $textures textures for $materials materials"
    echo "# $map: $materials materials, $textures textures"
done
# oa_dm4 from its bench view: optimized against the reference
python3 - "$src/bench/views.json" "$data/maps/oa_dm4.bsp" >"$work/oa_dm4.json" <<'PY'
import json, sys
view = json.load(open(sys.argv[1]))["oa_dm4"]
light = view["light"]
print(json.dumps({"camera": view["camera"], "ambient": 0.2,
                  "lights": [{"position": light["position"], "intensity": light.get("intensity", 1)}],
                  "meshes": [{"file": sys.argv[2]}]}))
PY
"$rtt" render "$work/oa_dm4.json" --engine reference --width 96 --height 72 -o "$work/ref.exr" || fail "reference render"
"$rtt" render "$work/oa_dm4.json" --width 96 --height 72 -o "$work/opt.exr" || fail "optimized render"
"$rtt" compare "$work/ref.exr" "$work/opt.exr" --json >"$work/cmp" || fail "compare"
python3 - "$work/cmp" <<'PY' || failures=$((failures + 1))
import json, sys
m = json.load(open(sys.argv[1]))
print("# oa_dm4 textured, optimized vs reference:", m)
sys.exit(0 if m["rmse"] < 1e-3 and m["share_over_1_255"] < 0.01 else 1)
PY
[ "$failures" -eq 0 ] && echo "real_textures: ok"
[ "$failures" -eq 0 ]
