#!/usr/bin/env bash
# Every error path of the rtt command line: each bad call must exit with the
# documented code (1 bad input, 2 bad usage), print exactly one line on
# stderr naming the file/option, and leave no output file behind.
set -u
rtt="$1"
src="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
scene="$src/scenes/mat_diffuse.json"

# expect CODE PATTERN -- ARGS...: runs rtt ARGS, checks exit code and that
# stderr is one line matching PATTERN (grep -E).
expect() {
    local code="$1" pattern="$2"
    shift 3
    "$rtt" "$@" >"$work/out" 2>"$work/err"
    local got=$?
    local lines
    lines=$(wc -l <"$work/err")
    if [ "$got" -ne "$code" ] || [ "$lines" -ne 1 ] || ! grep -Eq -- "$pattern" "$work/err"; then
        echo "FAIL: rtt $* -> exit $got (want $code), stderr ($lines lines):"
        sed 's/^/    /' "$work/err"
        failures=$((failures + 1))
    fi
}

# no file left behind at PATH
expect_absent() {
    if [ -e "$1" ]; then
        echo "FAIL: $1 exists after a failed command"
        failures=$((failures + 1))
    fi
}

printf '{ "meshes": [ }' >"$work/syntax.json"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' >"$work/badindex.obj"
printf 'v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n' >"$work/nan.obj"
printf 'not a kd tree' >"$work/corrupt.kdt"
printf 'IBSP' >"$work/short.bsp"
head -c 33 /dev/zero >"$work/rays33.bin"
head -c 64 /dev/zero >"$work/rays.bin"
head -c 10 /dev/zero >"$work/tris10.bin"
printf 'x' >"$work/notexr.exr"

# usage errors (exit 2)
expect 2 "usage|unknown command" -- frobnicate
expect 2 "no SCENE" -- render
expect 2 "unknown option" -- render "$scene" --bogus
expect 2 "--engine warp" -- render "$scene" --engine warp
expect 2 "traversal \"zigzag\"" -- render "$scene" --traversal zigzag
expect 2 "--tile 7" -- render "$scene" --tile 7
expect 2 "--shadows multi:0" -- render "$scene" --shadows multi:0
expect 2 "--shadows multi:257" -- render "$scene" --shadows multi:257
expect 2 "--shadows soft" -- render "$scene" --shadows soft
expect 2 "--shadows interleaved:64: .*from 4 to 32" -- render "$scene" --shadows interleaved:64
expect 2 "--shadows interleaved:16:blur" -- render "$scene" --shadows interleaved:16:blur
quad="$src/scenes/light_quad.json"
expect 1 "light_quad.json: light 0 is a quad light: edgewidth shadows draw sphere and point lights only" -- \
    render "$quad" --shadows edgewidth -o "$work/quad.png"
expect_absent "$work/quad.png"
expect 1 "light_quad.json: light 0 is a quad light: the .kdt format stores point and sphere lights only" -- \
    bake "$quad" -o "$work/quad.kdt"
expect_absent "$work/quad.kdt"
expect 2 "--threads 0" -- render "$scene" --threads 0
expect 2 "--width abc" -- render "$scene" --width abc
expect 2 "--aov colour" -- render "$scene" --aov colour
expect 2 "unknown image format" -- render "$scene" -o "$work/out.jpg"
expect 2 "needs a value" -- render "$scene" --tile
expect 2 "no output" -- triangles "$scene"
expect 2 "no rays" -- trace "$scene" -o "$work/hits.bin"
expect 2 "--engine warp" -- trace "$scene" --rays "$work/rays.bin" -o "$work/hits.bin" --engine warp
expect 2 "expected two images" -- compare "$work/notexr.exr"
expect 2 "no SCENE" -- info
expect 2 "no SCENE|usage" -- bake
expect 2 "usage|SCENE" -- conform
expect 2 "usage|SCENE" -- bench

# option syntax: --opt=value, repeats, values on flags (exit 2)
expect 2 "--bogus=1: unknown option" -- render "$scene" --bogus=1
expect 2 "--stats: takes no value" -- render "$scene" --stats=yes
expect 2 "--tile 16: given more than once" -- render "$scene" --tile 8 --tile 16
expect 2 "--tile 7: expected 4, 8, 16 or 32" -- render "$scene" --tile=7
expect 2 "--width: expected a whole number" -- render "$scene" --width=
expect 2 "-o x\.jpg: unknown image format" -- render "$scene" -o=x.jpg
expect 2 "--output x\.jpg: unknown image format" -- render "$scene" --output=x.jpg
expect 2 "--isa bogus: expected auto or one of sse4" -- render "$scene" --isa bogus
expect 2 "--isa bogus: expected" -- render "$scene" --isa=bogus
expect 2 "--accel grid: expected one of kd, bvh" -- render "$scene" --accel grid
expect 2 "cone shadows need the kd-tree" -- render "$scene" --accel bvh --shadows cone:8
expect 2 "unknown bvh traversal \"mft\": expected bvh-mono, bvh-packet, bvh-mft" -- render "$scene" --accel bvh --traversal mft
expect 2 "--max-bounces 65: expected a whole number from 0 to 64" -- render "$scene" --max-bounces 65
expect 2 "--max-bounces -1: expected" -- render "$scene" --max-bounces=-1
expect 2 "--max-depth 65: expected a whole number from 1 to 64" -- render "$scene" --max-depth 65
expect 2 "more than one SCENE" -- render "$scene" "$scene"
expect 2 "--engine warp: expected both, optimized or reference" -- info "$scene" --engine warp
expect 2 "-o x\.png: the output must end in \.kdt" -- bake "$scene" -o x.png
expect 2 "--threads 0,1: expected up to" -- bench "$scene" --threads 0,1
expect 2 "--only gpu: expected a comma list" -- bench "$scene" --only gpu
expect 2 "--rays lasers: expected primary" -- conform "$scene" --rays lasers
expect 2 "--max-rmse -1: expected a number of at least 0" -- compare a.exr b.exr --max-rmse=-1
expect 2 "expected two images" -- compare a.exr b.exr c.exr
RTT_ISA=bogus expect 2 "RTT_ISA=bogus: expected" -- render "$scene"

# options that do not apply are refused, naming the option and the reason (exit 2)
expect 2 "--tile 16: engine \"reference\" does not use a tile size" -- render "$scene" --engine reference --tile 16
expect 2 "--isa sse4: engine \"reference\" does not use an instruction-set" -- \
    render "$scene" --engine reference --isa sse4
expect 2 "--traversal mft: engine \"reference\" does not use a traversal kernel" -- \
    render "$scene" --engine reference --traversal mft
if "$rtt" render --help | grep -q " embree ("; then # a build with Embree
    expect 2 "--traversal cone: engine \"embree\" does not use a traversal kernel" -- \
        render "$scene" --engine embree --traversal cone --stats
    expect 2 "--leaf-culling off: engine \"embree\" does not use a leaf-culling" -- \
        render "$scene" --engine embree --leaf-culling off
    expect 2 "--accel kd: engine \"embree\" does not use an acceleration" -- render "$scene" --engine embree --accel kd
    expect 2 "--max-depth 12: engine \"embree\" does not use a tree depth" -- \
        render "$scene" --engine embree --max-depth 12
    expect 2 "--tile 8: engine \"embree\" does not use a tile size" -- \
        trace "$scene" --rays "$work/rays.bin" -o "$work/h.bin" --engine embree --tile 8
fi
expect 2 "--shadows cone:16: engine \"reference\" does not render cone shadows" -- \
    render "$scene" --engine reference --shadows cone:16
expect 2 "--aov depth: PNG output .*x\.png has no AOV channels; write an \.exr" -- \
    render "$scene" --aov depth -o "$work/x.png"
expect 2 "--aov depth: PNG output render\.png \(the default\)" -- render "$scene" --aov depth
expect 2 "--edge-leak-fix: applies to --shadows edgewidth only" -- render "$scene" --edge-leak-fix
expect 2 "--edge-leak-fix: applies to --shadows edgewidth only \(shadows are multi\)" -- \
    render "$scene" --shadows multi:4 --edge-leak-fix
expect 2 "--traversal mono: engine \"reference\"" -- \
    trace "$scene" --rays "$work/rays.bin" -o "$work/h.bin" --engine reference --traversal mono
expect 2 "--accel kd: engine \"reference\" does not use an acceleration" -- info "$scene" --accel kd
expect 2 "--isa sse4: none of the engines reference reads an instruction-set choice" -- \
    conform "$scene" --engines reference --isa sse4
expect 2 "--rays primary: --extremes traces rays of its own" -- conform --extremes --rays primary
expect 2 "--seed 3: --extremes has no random rays" -- conform --extremes --seed 3
expect 2 "--extremes: builds its own scenes" -- conform "$scene" --extremes
expect 2 "--meshes .*: only --extremes reads meshes" -- conform "$scene" --meshes "$work"
expect 2 "--frames 3: --quick times one frame" -- bench "$scene" --quick --frames 3
expect 2 "--warmup 2: --quick warms up none" -- bench "$scene" --quick --warmup 2
expect 2 "--images .*: --only leaves out the render rows" -- bench "$scene" --only primary --images "$work"

# cameras and lights (--eye, --look-at, --up, --fov, --view, --lights)
printf '{ "mat_diffuse": { "camera": { "eye": [0, 1, 3], "look_at": [0, 1, 0] } },\n  "near": { "camera": { "eye": [0, 1, 2], "look_at": [0, 1, 0] } } }\n' >"$work/views.json"
printf '{ "ok": { "camera": { "eye": [0, 1, 3], "look_at": [0, 1, 0] } },\n  "wide": { "camera": { "eye": [0, 1, 3], "look_at": [0, 1, 0], "fov": 200 } } }\n' >"$work/wide.json"
printf '{ "a": { "camera": { "eye": [0, 1, 3] } } }\n' >"$work/noat.json"
printf '{ "a": { "camera": { "eye": [0, 1, 3], "look_at": [0, 0, 0] }, "colour": 1 } }\n' >"$work/unknown.json"
expect 2 "--eye 1,2: expected three finite numbers" -- render "$scene" --eye 1,2
expect 2 "--eye 1,2,x: expected three" -- render "$scene" --eye 1,2,x
expect 2 "--look-at 1,2,3,4: expected three" -- render "$scene" --look-at 1,2,3,4
expect 2 "--up nan,1,0: expected three" -- render "$scene" --up nan,1,0
expect 2 "--fov 0: expected a number of at least 1" -- render "$scene" --fov 0
expect 2 "--fov 180: must be between 1 and 179" -- render "$scene" --fov 180
expect 2 "--look-at 0,0,0: the eye and the look-at point are the same" -- \
    render "$scene" --eye 0,0,0 --look-at 0,0,0 -o "$work/cam.png"
expect_absent "$work/cam.png"
expect 2 "--up 0,0,0: the up vector is zero" -- render "$scene" --up 0,0,0
expect 2 "--up 0,0,1: the up vector is parallel" -- render "$scene" --eye 0,0,5 --look-at 0,0,0 --up 0,0,1
expect 2 "--eye 0,0,1: does not go with --view" -- render "$scene" --view "$work/views.json" --eye 0,0,1
expect 2 "--view .*views.json:nosuch: .*has no view named \"nosuch\" \(it has mat_diffuse, near\)" -- \
    render "$scene" --view "$work/views.json:nosuch"
expect 1 "wide.json:2: wide.camera.fov must be a number between 1 and 179" -- \
    info "$scene" --view "$work/wide.json:ok"
expect 1 "noat.json:1: a.camera: missing \"look_at\"" -- render "$scene" --view "$work/noat.json:a"
expect 1 "unknown.json:1: a: unknown key \"colour\"" -- render "$scene" --view "$work/unknown.json:a"
expect 1 "syntax.json:1: JSON syntax error" -- render "$scene" --view "$work/syntax.json"
expect 1 "missing.json: cannot open" -- render "$scene" --view "$work/missing.json"
expect 2 "--lights map: only a Quake III map \(.bsp\)" -- render "$scene" --lights map
expect 2 "--lights sun: expected map, camera or view" -- render "$scene" --lights sun
expect 2 "--lights view: view takes the light of --view's view, and no --view is given" -- render "$scene" --lights view
expect 2 "--lights view: view \"near\" of .*views.json has no light" -- \
    render "$scene" --view "$work/views.json:near" --lights view
expect 2 "--eye 0,0,1: --extremes builds its own scenes and cameras" -- conform --extremes --eye 0,0,1
expect 2 "--views .*: does not go with --view" -- bench "$scene" --views "$work/views.json" --view "$work/views.json"

# anti-aliasing, rays, compare, --version
expect 2 "--spp 0: expected a whole number from 1 to 256" -- render "$scene" --spp 0
expect 2 "--spp 257: expected a whole number from 1 to 256" -- render "$scene" --spp 257
expect 2 "no --kind given" -- rays "$scene" -o "$work/r.bin"
expect 2 "--kind sideways: expected one of primary, shadow, random" -- rays "$scene" --kind sideways -o "$work/r.bin"
expect 2 "no output given" -- rays "$scene" --kind random
expect 2 "-n 0: expected a whole number from 1" -- rays "$scene" --kind random -n 0 -o "$work/r.bin"
expect_absent "$work/r.bin"
expect 1 "missing\.json" -- rays "$work/missing.json" --kind random -o "$work/r.bin"
expect_absent "$work/r.bin"
printf 'not a png' >"$work/notpng.png"
expect 1 "notpng\.png: cannot read as PNG" -- compare "$work/notpng.png" "$work/notpng.png"
expect 1 "rays33\.bin: unknown image format" -- compare "$work/rays33.bin" "$work/notpng.png"
expect 2 "unknown command \"--versions\"" -- --versions

# a baked .kdt: its tree is adopted as is and its patches are tessellated
"$rtt" bake "$scene" -o "$work/baked.kdt" || { echo "FAIL: rtt bake"; failures=$((failures + 1)); }
expect 2 "--max-depth 10: engine \"optimized\" adopts the tree baked into .*baked\.kdt as is; rebake" -- \
    render "$work/baked.kdt" --max-depth 10 -o "$work/k.png"
expect_absent "$work/k.png"
expect 2 "--bezier-level 2: .*baked\.kdt holds triangles.*rebake" -- render "$work/baked.kdt" --bezier-level 2
expect 2 "--max-depth 10: engine \"optimized\" adopts" -- info "$work/baked.kdt" --max-depth 10
expect 2 "--max-depth 10: engine \"optimized\" adopts" -- bench "$work/baked.kdt" --max-depth 10
expect 2 "--max-depth 10: engine \"optimized\" adopts" -- \
    trace "$work/baked.kdt" --rays "$work/rays.bin" -o "$work/h.bin" --max-depth 10
expect 2 "--bezier-level 2: .*baked\.kdt holds triangles" -- bake "$work/baked.kdt" -o "$work/b2.kdt" --bezier-level 2
expect 2 "--bezier-level 2: .*cube\.obj is a mesh file: it has no Quake III patches" -- \
    triangles "$src/scenes/meshes/cube.obj" -o "$work/t.bin" --bezier-level 2

# what works: --opt=value is --opt value; --isa=sse4; --max-bounces 0; the
# reference builds its own tree from a .kdt, so --max-depth applies there
# expect_ok ARGS...: exit 0, nothing on stderr
expect_ok() {
    "$rtt" "$@" >"$work/out" 2>"$work/err"
    local got=$?
    if [ "$got" -ne 0 ] || [ -s "$work/err" ]; then
        echo "FAIL: rtt $* -> exit $got (want 0), stderr:"
        sed 's/^/    /' "$work/err"
        failures=$((failures + 1))
    fi
}
small=(--width 16 --height 16 --threads 1 --stats)
expect_ok render "$scene" "${small[@]}" --tile=16 --leaf-culling=off --traversal=frustum -o="$work/eq.png"
head -1 "$work/out" >"$work/eq.stats"
expect_ok render "$scene" "${small[@]}" --tile 16 --leaf-culling off --traversal frustum -o "$work/sp.png"
head -1 "$work/out" >"$work/sp.stats"
if ! cmp -s "$work/eq.png" "$work/sp.png" || ! cmp -s "$work/eq.stats" "$work/sp.stats" ||
    ! grep -q "kernel frustum/.*tile 16, leaf culling off" "$work/sp.stats"; then
    echo "FAIL: --opt=value and --opt value differ: $(cat "$work/eq.stats") / $(cat "$work/sp.stats")"
    failures=$((failures + 1))
fi
expect_ok render "$scene" "${small[@]}" --isa=sse4 -o "$work/sse4.png"
grep -q "^engine optimized, accel kd, kernel mft/sse4, tile 8, leaf culling on$" "$work/out" ||
    { echo "FAIL: --isa=sse4 --stats: $(head -1 "$work/out")"; failures=$((failures + 1)); }
expect_ok render "$scene" "${small[@]}" --engine=reference -o "$work/ref.png"
grep -q "^engine reference, accel kd (its own), no kernel choice$" "$work/out" ||
    { echo "FAIL: --engine=reference --stats: $(head -1 "$work/out")"; failures=$((failures + 1)); }
expect_ok render "$scene" "${small[@]}" --max-bounces 0 -o "$work/mb0.png"
expect_ok render "$work/baked.kdt" "${small[@]}" --engine reference --max-depth 10 -o "$work/kref.png"
expect_ok conform "$scene" --engines optimized/mft --isa=sse4 --rays primary --max-rays 64

# bad input (exit 1), one line naming the file
expect 1 "missing\.json" -- render "$work/missing.json" -o "$work/a.png"
expect_absent "$work/a.png"
expect 1 "syntax\.json:1" -- render "$work/syntax.json" -o "$work/b.png"
expect_absent "$work/b.png"
expect 1 "badindex\.obj.*out of range" -- render "$work/badindex.obj" -o "$work/c.png"
expect_absent "$work/c.png"
expect 1 "nan\.obj.*NaN or infinite" -- render "$work/nan.obj" -o "$work/d.exr"
expect_absent "$work/d.exr"
expect 1 "corrupt\.kdt" -- render "$work/corrupt.kdt" -o "$work/e.png"
expect_absent "$work/e.png"
expect 1 "short\.bsp" -- info "$work/short.bsp"
expect 1 "rays33\.bin.*multiple of 32" -- trace "$scene" --rays "$work/rays33.bin" -o "$work/hits.bin"
expect_absent "$work/hits.bin"
expect 1 "tris10\.bin.*multiple of 36" -- trace "$work/tris10.bin" --rays "$work/rays.bin" -o "$work/hits2.bin"
expect_absent "$work/hits2.bin"
expect 1 "notexr\.exr" -- compare "$work/notexr.exr" "$work/notexr.exr"
expect 1 "missing\.json" -- bake "$work/missing.json" -o "$work/x.kdt"
expect_absent "$work/x.kdt"
expect 1 "missing\.json" -- triangles "$work/missing.json" -o "$work/t.bin"
expect_absent "$work/t.bin"

# an existing output survives a failed render untouched
echo keep >"$work/keep.png"
expect 1 "missing\.json" -- render "$work/missing.json" -o "$work/keep.png"
if [ "$(cat "$work/keep.png")" != keep ]; then
    echo "FAIL: existing output was modified by a failed render"
    failures=$((failures + 1))
fi

# --help on every command: exit 0, usage on stdout
for command in render bake info triangles trace conform compare bench rays; do
    if ! "$rtt" "$command" --help >"$work/help" 2>&1 || ! grep -q "usage: rtt $command" "$work/help"; then
        echo "FAIL: rtt $command --help"
        failures=$((failures + 1))
    fi
done

if [ "$failures" -ne 0 ]; then
    echo "$failures CLI error-path checks failed"
    exit 1
fi
echo "all CLI error paths behave"
