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
for command in render bake info triangles trace conform compare bench; do
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
