#!/usr/bin/env bash
# mpirun -np N rtt render (dist/) on one machine, oversubscribed: the image
# byte for byte the one-process render for 2, 3 and 4 ranks (EXR with every
# AOV and PNG, one and two threads a rank, both engines, the demo, its baked
# .kdt and a Quake III map) and of sequences (whole frames to the ranks, and
# tiles); a rank that cannot read its scene, and a rank out of memory, end
# the job with exit 1, one line from rank 0 naming the rank and its error,
# and no output; a rank killed in the middle of a frame ends the job
# non-zero within 10 s with no output.
# Skipped (77) when mpirun is absent or rtt was built without MPI.
set -u
rtt=$(realpath "$1")
src=$(realpath "$2")
data="${RTT_DATA_DIR:-$HOME/.cache/rtt-data}"
command -v mpirun >/dev/null || { echo "mpi_render: no mpirun here: skipped"; exit 77; }
# mpirun refuses root unless told; CI runs as root on some machines
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
# An AddressSanitizer build under mpirun: LeakSanitizer reports what Open MPI
# (and OpenEXR, loaded beside it) still hold at exit, with stacks cut short in
# the uninstrumented libraries, so leaks are not checked here; memory errors
# and UBSan are.  (rtt's own code is leak-checked by the one-process tests.)
if ldd "$rtt" | grep -q libasan; then export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"; fi
# one machine, no network: keep Open MPI on the loopback and shared memory
export OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
failures=0
fail() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}
run_mpi() { # N ARGS...: mpirun with N ranks
    local ranks="$1"
    shift
    mpirun --oversubscribe -np "$ranks" "$@"
}

if run_mpi 2 "$rtt" render "$src/scenes/demo.json" --width 8 --height 8 -o probe.png 2>probe.err; then :; else
    grep -q "built without MPI" probe.err && { echo "mpi_render: rtt built without MPI: skipped"; exit 77; }
    fail "a two-rank render of the demo failed: $(head -3 probe.err)"
fi

# byte for byte: ranks x threads x engines x scenes (each mpirun costs a
# second or two of start-up: the demo takes every pair, the others a few)
compare_ranks() { # NAME "RANKSxTHREADS..." SCENE ARGS...
    local name="$1" pairs="$2" scene="$3"
    shift 3
    "$rtt" render "$scene" "$@" -o "$name.one.exr" -o "$name.one.png" || { fail "$name: one-process render"; return; }
    for pair in $pairs; do
        ranks=${pair%x*} threads=${pair#*x}
        out="$name.np$ranks.t$threads"
        if ! run_mpi "$ranks" "$rtt" render "$scene" "$@" --threads "$threads" -o "$out.exr" -o "$out.png" \
             --stats >"$out.log" 2>&1; then
            fail "$name: $ranks ranks x $threads threads failed: $(tail -3 "$out.log")"
            continue
        fi
        cmp -s "$name.one.exr" "$out.exr" || fail "$name: $ranks ranks x $threads threads: EXR differs"
        cmp -s "$name.one.png" "$out.png" || fail "$name: $ranks ranks x $threads threads: PNG differs"
        shares=$(grep "^tiles per rank:" "$out.log") || fail "$name: $ranks ranks: no tiles per rank"
        # rank 0 may take a small frame alone; over the runs the others must have rendered
        read -r -a counts <<<"${shares#tiles per rank: }"
        for r in $(seq 1 $((ranks - 1))); do [ "${counts[$r]}" -gt 0 ] && remote_tiles=1; done
    done
}
remote_tiles=0
compare_ranks demo "2x1 2x2 3x1 3x2 4x1 4x2" "$src/scenes/demo.json" --width 96 --height 64 --aov depth,prim,normal
compare_ranks demo-reference "3x2" "$src/scenes/demo.json" --engine reference --width 72 --height 40 --aov depth,prim
compare_ranks demo-tile4 "4x1" "$src/scenes/demo.json" --traversal omni --tile 4 --width 50 --height 30 --shadows cone:8
# every rank adopts a baked tree instead of building one
"$rtt" bake "$src/scenes/demo.json" -o demo.kdt || fail "rtt bake failed"
compare_ranks demo-kdt "3x2" demo.kdt --width 64 --height 40
if [ -s "$data/maps/oa_dm4.bsp" ]; then
    compare_ranks map "2x2 4x2" "$data/maps/oa_dm4.bsp" --width 80 --height 60 --aov depth
else
    fail "$data/maps/oa_dm4.bsp is missing (run bench/fetch-scenes.sh)"
fi

[ "$remote_tiles" = 1 ] || fail "no rank but 0 rendered a tile in any run: the comparisons tested nothing"

# sequences: more frames than ranks (whole frames to the ranks: 5 frames,
# 2 ranks) and no more (each frame's tiles over the ranks: 3 frames, 4
# ranks), byte for byte the one-process frames
path="$src/tests/data/demo_path.json"
for pair in 2:5 4:3; do
    ranks=${pair%:*} count=${pair#*:}
    seq=(render "$src/scenes/demo.json" --width 40 --height 30 --camera-path "$path" --path-frames "$count" --aov depth)
    "$rtt" "${seq[@]}" -o "one$count"_%d.exr -o "one$count"_%d.png || fail "a one-process sequence failed"
    run_mpi "$ranks" "$rtt" "${seq[@]}" -o "np$ranks"_%d.exr -o "np$ranks"_%d.png --stats >"seq$ranks.log" 2>&1 ||
        fail "a sequence over $ranks ranks failed: $(tail -3 "seq$ranks.log")"
    for f in $(seq 0 $((count - 1))); do
        cmp -s "one${count}_$f.exr" "np${ranks}_$f.exr" || fail "sequence over $ranks ranks: frame $f EXR differs"
        cmp -s "one${count}_$f.png" "np${ranks}_$f.png" || fail "sequence over $ranks ranks: frame $f PNG differs"
    done
done
grep -q "^frames per rank:" seq2.log || fail "5 frames over 2 ranks were not shared as whole frames"
grep -q "^tiles per rank:" seq4.log || fail "3 frames over 4 ranks were not shared by tiles"

# a rank that cannot read its scene (seen on one node only)
rank_scene='s="$1"; [ "$OMPI_COMM_WORLD_RANK" = 2 ] && s=/nonexistent/demo.json; shift; exec "$@" "$s"'
run_mpi 3 sh -c "$rank_scene" sh "$src/scenes/demo.json" "$rtt" render --width 64 --height 48 -o unread.png \
    >unread.log 2>&1
rc=$?
[ "$rc" = 1 ] || fail "a rank without its scene: exit $rc, not 1"
lines=$(grep -c '^rtt: ' unread.log)
[ "$lines" = 1 ] || fail "a rank without its scene: $lines lines from rtt, not 1: $(cat unread.log)"
grep -q '^rtt: rank 2: /nonexistent/demo.json: cannot open' unread.log ||
    fail "a rank without its scene: rank 0 does not name rank 2 and its error: $(head -3 unread.log)"
ls unread.png* >/dev/null 2>&1 && fail "a rank without its scene: an output was left"

# a rank out of memory (its address space capped: an image it cannot allocate;
# an ASan or TSan build reserves more address space than any cap allows)
if ldd "$rtt" | grep -Eq 'libasan|libtsan'; then
    echo "mpi_render: a sanitizer build: the out-of-memory rank is left to the plain build"
else
    rank_capped='[ "$OMPI_COMM_WORLD_RANK" = 1 ] && ulimit -v 2000000; exec "$@"'
    run_mpi 3 sh -c "$rank_capped" sh "$rtt" render "$src/scenes/demo.json" --width 16384 --height 16000 \
        -o oom.png >oom.log 2>&1
    rc=$?
    [ "$rc" = 1 ] || fail "a rank out of memory: exit $rc, not 1"
    grep -q '^rtt: rank 1: .*out of memory' oom.log ||
        fail "a rank out of memory: rank 0 does not name it: $(head -3 oom.log)"
    [ "$(grep -c '^rtt: ' oom.log)" = 1 ] || fail "a rank out of memory: not one line from rtt: $(cat oom.log)"
    ls oom.png* >/dev/null 2>&1 && fail "a rank out of memory: an output was left"
fi

# a rank killed in the middle of a frame (the frame takes a minute on one core)
rank_pid='echo $$ >"pid.$OMPI_COMM_WORLD_RANK"; exec "$@"'
start=$(date +%s)
mpirun --oversubscribe -np 3 sh -c "$rank_pid" sh "$rtt" render "$src/scenes/demo.json" --width 1280 --height 960 \
    --shadows multi:256 --threads 1 -o killed.png >killed.log 2>&1 &
job=$!
for _ in $(seq 100); do [ -s pid.0 ] && [ -s pid.1 ] && [ -s pid.2 ] && break; sleep 0.1; done
sleep 1 # every rank past its start, in the frame
killed_at=$(date +%s)
if [ -s pid.1 ]; then kill -9 "$(cat pid.1)"; else fail "rank 1 never started"; fi
for _ in $(seq 100); do kill -0 "$job" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$job" 2>/dev/null; then
    fail "a killed rank: the job still runs 10 s later"
    kill "$job" # mpirun ends its ranks
fi
wait "$job"
rc=$?
[ "$rc" != 0 ] || fail "a killed rank: the job exited 0"
echo "mpi_render: killed rank: exit $rc, $(($(date +%s) - killed_at)) s after the kill ($((killed_at - start)) s in)"
ls killed.png* >/dev/null 2>&1 && fail "a killed rank: an output was left: $(ls killed.png*)"

[ "$failures" = 0 ] || { echo "mpi_render: $failures failure(s)"; exit 1; }
echo "mpi_render: ok"
