#!/usr/bin/env bash
# Hostile input: files made to break rtt, bad outputs and interrupted runs.
# Each case must exit with its code (1 bad input, 130/143 interrupted),
# print exactly its one expected line on stderr, leave no file behind (the
# work directory is compared before and after), and stay under 100 MB of
# resident memory and 5 seconds.  The inputs are tests/data/hostile/ (see
# its README.md) plus FIFOs and devices made here.
set -u
rtt="$1"
src="$2"
if [ ! -x /usr/bin/time ] || ! command -v timeout >/dev/null; then
    echo "hostile_input: needs /usr/bin/time and timeout"
    exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$src"/tests/data/hostile/* "$work"/
cd "$work" || exit 1
mkfifo fifo.json fifo.off fifo.obj fifo.mtl fifo.bin fifo.kdt fifo.exr fifo_out.png
"$rtt" triangles tetra.off -o tetra.bin || exit 1
head -c 64 /dev/zero >rays.bin
"$rtt" render tetra.off -o tetra.exr --width 8 --height 8 || exit 1
"$rtt" bake tetra.off -o tetra.kdt || exit 1
mkdir -p readonly && chmod 555 readonly
failures=0
cases=0
MAX_KB=102400
# a sanitizer build (ci/sanitize.sh) carries shadow memory and quarantine on
# top of what rtt itself takes: the 100 MB bound is the release build's
if ldd "$rtt" 2>/dev/null | grep -qE 'lib(asan|tsan)'; then MAX_KB=$((4 * MAX_KB)); fi
MAX_SECONDS=5

snapshot() { find . -mindepth 1 -printf '%p %s\n' | LC_ALL=C sort; }

# check NAME CODE LINE -- ARGS...: rtt ARGS exits CODE with LINE as its only
# stderr line, in bounded memory and time, and leaves the directory as it was.
check() {
    local name="$1" code="$2" line="$3"
    shift 4
    cases=$((cases + 1))
    local before after got kb seconds
    before=$(snapshot)
    timeout -s KILL $((MAX_SECONDS + 5)) /usr/bin/time -f '%M %e' -o ../time.$$ "$rtt" "$@" >/dev/null 2>../err.$$
    got=$?
    read -r kb seconds < <(tail -n 1 ../time.$$ 2>/dev/null || echo "0 0")
    after=$(snapshot)
    local problem=""
    [ "$got" -eq "$code" ] || problem="exit $got, not $code"
    [ "$(cat ../err.$$)" = "$line" ] || problem="${problem:+$problem; }stderr is not the expected line"
    [ "${kb:-0}" -le "$MAX_KB" ] || problem="${problem:+$problem; }${kb} KB resident"
    awk -v s="${seconds:-99}" -v m="$MAX_SECONDS" 'BEGIN { exit !(s <= m) }' || problem="${problem:+$problem; }${seconds} s"
    [ "$before" = "$after" ] || problem="${problem:+$problem; }files changed: $(diff <(echo "$before") <(echo "$after") | grep '^[<>]' | tr '\n' ' ')"
    if [ -n "$problem" ]; then
        echo "FAIL $name: rtt $* -> $problem"
        echo "    want: $line"
        sed 's/^/    got:  /' ../err.$$
        failures=$((failures + 1))
    fi
    rm -f ../err.$$ ../time.$$
}

# ---- mesh files checked against themselves ----
check off_truncated 1 "rtt: truncated.off: the file ends in face 2 of the 4 the header declares" -- info truncated.off
check off_index_out_of_range 1 "rtt: index_out_of_range.off: face 2: vertex index 9 is out of range (4 vertices)" -- info index_out_of_range.off
check off_huge_header 1 "rtt: huge_header.off: header: 1000000000 vertices and 1 faces cannot fit in 33 bytes" -- render huge_header.off -o never.png
check ply_truncated_ascii 1 "rtt: truncated_ascii.ply: the file ends in face 2 of the 4 the header declares" -- info truncated_ascii.ply
check ply_truncated_binary 1 "rtt: truncated_binary.ply: the file ends in face 2 of the 4 the header declares" -- info truncated_binary.ply
check ply_index_out_of_range 1 "rtt: index_out_of_range.ply: face 3: vertex index 4 is out of range (4 vertices)" -- info index_out_of_range.ply
check ply_huge_count 1 "rtt: huge_count.ply: the file ends in vertex 1 of the 4000000000 the header declares" -- info huge_count.ply
check stl_count_mismatch 1 "rtt: count_mismatch.stl: binary STL header declares 1000 triangles (50084 bytes) but the file has 134 bytes" -- info count_mismatch.stl
check stl_facet_two_vertices 1 "rtt: facet_two_vertices.stl: facet 0: 2 vertices (a facet has 3)" -- info facet_two_vertices.stl
check gltf_buffer_too_long 1 "rtt: buffer_too_long.gltf: buffers[0]: byteLength 36000000 but only 36 bytes are there" -- info buffer_too_long.gltf
check gltf_accessor_overrun 1 "rtt: accessor_overrun.gltf: accessors[0]: 3000000 elements of 12 bytes from byte 0 overrun bufferViews[0] (36 bytes)" -- info accessor_overrun.gltf
check glb_length_mismatch 1 "rtt: length_mismatch.glb: GLB header declares 999999 bytes but the file has 52" -- info length_mismatch.glb

# ---- bounded resources ----
check spheres_over_budget 1 "rtt: spheres_65m.json: needs about 39.1 GiB for 65536000 triangles, over the memory budget of 1.0 GiB" -- render spheres_65m.json -o never.png --max-memory 1G
check spheres_over_machine 1 "rtt: spheres_65m.json: needs about 39.1 GiB for 65536000 triangles, over the memory budget of 20.0 GiB" -- info spheres_65m.json --max-memory 20G
check mesh_over_budget 1 "rtt: tetra.off: needs about 2.5 KiB for 4 triangles, over the memory budget of 1.0 KiB" -- info tetra.off --max-memory 1K
check mesh_in_scene_over_budget 1 "rtt: tetra.json:1: meshes[0].file: tetra.off: needs about 2.5 KiB for 4 triangles, over the memory budget of 2.0 KiB" -- bake tetra.json -o never.kdt --max-memory 2K
check tris_over_budget 1 "rtt: tetra.bin: needs about 2.5 KiB for 4 triangles, over the memory budget of 1.0 KiB" -- trace tetra.bin --rays rays.bin -o never.bin --max-memory 1K

# ---- only regular files are read ----
check fifo_scene 1 "rtt: fifo.json: not a regular file (a FIFO)" -- render fifo.json -o never.png
check fifo_mesh 1 "rtt: fifo.off: not a regular file (a FIFO)" -- info fifo.off
check fifo_mesh_in_scene 1 "rtt: fifo_mesh.json:1: meshes[0].file: fifo.obj: not a regular file (a FIFO)" -- info fifo_mesh.json
check fifo_mtl 1 "rtt: ./fifo.mtl: not a regular file (a FIFO)" -- info ./mtl_fifo.obj
check fifo_rays 1 "rtt: fifo.bin: not a regular file (a FIFO)" -- trace tetra.off --rays fifo.bin -o never.bin
check fifo_kdt 1 "rtt: fifo.kdt: not a regular file (a FIFO)" -- render fifo.kdt -o never.png
check fifo_compare 1 "rtt: fifo.exr: not a regular file (a FIFO)" -- compare fifo.exr tetra.exr
check fifo_views 1 "rtt: fifo.json: not a regular file (a FIFO)" -- bench tetra.off --views fifo.json --quick --no-embree
check device_scene 1 "rtt: /dev/zero: not a regular file (a character device)" -- info /dev/zero
check directory_scene 1 "rtt: readonly: is a directory" -- info readonly

# ---- outputs checked before the work, all or nothing ----
check output_missing_directory 1 "rtt: missing/out.png: cannot write in missing: No such file or directory" -- render tetra.off -o missing/out.png
check output_second_missing 1 "rtt: missing/b.exr: cannot write in missing: No such file or directory" -- render tetra.off -o a.png -o missing/b.exr
if [ "$(id -u)" -ne 0 ]; then
    check output_read_only 1 "rtt: readonly/out.png: cannot write in readonly: Permission denied" -- render tetra.off -o readonly/out.png
fi
check output_is_directory 1 "rtt: readonly/: not a file name" -- triangles tetra.off -o readonly/
check output_is_fifo 1 "rtt: fifo_out.png: cannot write: it is a FIFO" -- render tetra.off -o fifo_out.png
check output_twice 1 "rtt: a.png: given twice as an output" -- render tetra.off -o a.png -o a.png
check triangles_over_input 1 "rtt: tetra.off: is an input of this command; an input is never written" -- triangles tetra.off -o tetra.off
check trace_over_rays 1 "rtt: rays.bin: is an input of this command; an input is never written" -- trace tetra.off --rays rays.bin -o rays.bin
check trace_over_scene 1 "rtt: ./tetra.bin: is the input tetra.bin; an input is never written" -- trace tetra.bin --rays rays.bin -o ./tetra.bin
check bake_over_input 1 "rtt: tetra.kdt: is an input of this command; an input is never written" -- bake tetra.kdt -o tetra.kdt
check bench_markdown_over_input 1 "rtt: tetra.off: is an input of this command; an input is never written" -- bench tetra.off --markdown tetra.off --quick --no-embree
check bench_tsv_over_input 1 "rtt: tetra.json: is an input of this command; an input is never written" -- bench tetra.json --tsv tetra.json --quick --no-embree
check bench_images_missing 1 "rtt: --images: cannot write in missing: No such file or directory" -- bench tetra.off --images missing --quick --no-embree --only render
check bench_markdown_missing 1 "rtt: missing/t.md: cannot write in missing: No such file or directory" -- bench tetra.off --markdown missing/t.md --quick --no-embree

# ---- interrupted runs: SIGTERM and SIGINT remove the temporaries ----
# interrupt SIGNAL CODE: a render big enough to be caught writing its EXR;
# the signal goes when the temporary appears (or, on a fast machine, during
# the render), and nothing may be left behind.
interrupt() {
    local signal="$1" code="$2"
    cases=$((cases + 1))
    local before
    before=$(snapshot)
    "$rtt" render tetra.off -o big.exr -o big.png --width 2048 --height 2048 --threads 1 2>../err.$$ &
    local pid=$! waited=0
    while [ $waited -lt 500 ] && ! compgen -G "big.*.tmp.*" >/dev/null && kill -0 $pid 2>/dev/null; do
        sleep 0.01
        waited=$((waited + 1))
    done
    local caught=no
    compgen -G "big.*.tmp.*" >/dev/null && caught=yes
    kill -s "$signal" $pid 2>/dev/null
    wait $pid
    local got=$?
    # nothing on stderr but progress (a slow, e.g. sanitizer, build renders past the 2 s after which it shows)
    if [ "$got" -ne "$code" ] || [ "$before" != "$(snapshot)" ] ||
        grep -qvE '^rtt: [a-z ]+: [0-9]+% after ' ../err.$$; then
        echo "FAIL interrupted_$signal: exit $got (want $code), temporary seen: $caught, left: $(ls big.* 2>/dev/null | tr '\n' ' ')"
        sed 's/^/    stderr: /' ../err.$$
        failures=$((failures + 1))
    fi
    rm -f big.* ../err.$$
}
interrupt TERM 143
interrupt INT 130

# ---- --threads bounds every stage (no worker thread is started under --threads 1;
# the progress watcher, which computes nothing, names itself rtt-progress) ----
if command -v strace >/dev/null && strace -f -qq -e trace=clone,clone3 -o ../trace.$$ true 2>/dev/null; then
    for command in "render --threads 1 -o t1.png --width 16 --height 16 $src/tests/data/import/pyramid.off" \
                   "bake --threads 1 -o t1.kdt tetra.off" "info --threads 1 tetra.off" \
                   "trace --threads 1 tetra.off --rays rays.bin -o t1.bin"; do
        cases=$((cases + 1))
        # shellcheck disable=SC2086
        # LeakSanitizer cannot run under ptrace: off for these runs of a sanitizer build
        ASAN_OPTIONS=detect_leaks=0 strace -f -qq -e trace=clone,clone3,prctl -o ../trace.$$ "$rtt" $command >/dev/null
        # strace splits a call interrupted by another thread into "unfinished" and "resumed" lines
        clones=$(( $(grep -v 'resumed>' ../trace.$$ | grep -c 'clone') - $(grep -c 'PR_SET_NAME, "rtt-progress"' ../trace.$$) ))
        if [ "$clones" -ne 0 ]; then
            echo "FAIL threads_one: rtt $command started $clones threads"
            failures=$((failures + 1))
        fi
    done
    rm -f ../trace.$$ t1.*
fi

if [ $failures -ne 0 ]; then
    echo "hostile_input: $failures of $cases cases failed"
    exit 1
fi
echo "hostile_input: all $cases cases passed"
