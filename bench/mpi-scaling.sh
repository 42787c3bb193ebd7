#!/usr/bin/env bash
# rtt render over MPI on this machine: ranks 1 to 4 against one process.
#
#   bench/mpi-scaling.sh [RTT]     RTT: the rtt binary (default build/cli/rtt)
#
# Renders RTT_MPI_SCENE (default the oa_dm4 map of ${RTT_DATA_DIR:-~/.cache/
# rtt-data}) at RTT_MPI_SIZE (default 1280x720) with RTT_MPI_THREADS threads
# a rank (default "1 2"): one process without mpirun, then mpirun -np 1..4.
# Each row is the median over RTT_MPI_RUNS runs (default 3) of the frame
# time on rank 0 (`--stats` "time: total": the render with every rank's
# pixels gathered, not the start-up, load or tree build), of the whole
# command's wall time and of its CPU seconds (user + system of the command
# and every rank: start-up, load, every rank's tree build, render; the work
# done, whatever the machine's load), the tiles each rank rendered in the median run, and
# a check that the image is byte for byte the one-process image.  Prints a
# markdown table (bench/results/mpi.md quotes it).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
rtt=$(realpath "${1:-${RTT:-$root/build/cli/rtt}}")
data=${RTT_DATA_DIR:-$HOME/.cache/rtt-data}
scene=${RTT_MPI_SCENE:-$data/maps/oa_dm4.bsp}
size=${RTT_MPI_SIZE:-1280x720}
runs=${RTT_MPI_RUNS:-3}
threads_list=${RTT_MPI_THREADS:-1 2}
width=${size%x*} height=${size#*x}
[ -s "$scene" ] || { echo "mpi-scaling: $scene is missing (run bench/fetch-scenes.sh)" >&2; exit 1; }
command -v mpirun >/dev/null || { echo "mpi-scaling: no mpirun" >&2; exit 1; }
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }

# run LABEL COMMAND...: prints "frame wall shares same" for the median run
run() {
    local label="$1"
    shift
    : >"$work/frames"
    : >"$work/walls"
    for i in $(seq "$runs"); do
        local start end
        start=$(date +%s.%N)
        /usr/bin/time -f "%U %S" -o "$work/cpu" \
            "$@" "$scene" --width "$width" --height "$height" -o "$work/$label.$i.png" --stats >"$work/$label.$i.log"
        end=$(date +%s.%N)
        frame=$(awk '/^time: total/ {print $3}' "$work/$label.$i.log")
        # user + system seconds of the command and every rank (mpirun waits for its ranks)
        cpu=$(awk '{printf "%.2f", $1 + $2}' "$work/cpu")
        echo "$frame $i $cpu" >>"$work/frames"
        echo "$end - $start" | bc -l >>"$work/walls"
    done
    local mid
    mid=$(sort -g "$work/frames" | awk '{r[NR] = $2} END {print r[int((NR + 1) / 2)]}')
    local cpu
    cpu=$(cut -d' ' -f3 "$work/frames" | median)
    local shares same=yes
    shares=$(sed -n 's/^tiles per rank: \([0-9 ]*\).*/\1/p' "$work/$label.$mid.log")
    for i in $(seq "$runs"); do cmp -s "$work/reference.png" "$work/$label.$i.png" || same=no; done
    printf '%s %s %s %s|%s\n' "$(cut -d' ' -f1 "$work/frames" | median)" "$(median <"$work/walls")" "$same" "$cpu" \
        "${shares:--}"
}

"$rtt" render "$scene" --width "$width" --height "$height" --threads 1 -o "$work/reference.png"
echo "scene $(basename "$scene"), ${width}x$height, median of $runs runs; load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| ranks x threads | frame time (s) | speed-up | whole command (s) | CPU, all ranks (s) | same bytes | tiles per rank |"
echo "|---|---|---|---|---|---|---|"
for threads in $threads_list; do
    read -r base_frame base_wall same cpu rest <<<"$(run "one.t$threads" "$rtt" render --threads "$threads" | tr '|' ' ')"
    printf "| 1 process (no mpirun) x %s | %s | 1.00 | %.2f | %s | %s | - |\n" "$threads" "$base_frame" "$base_wall" \
        "$cpu" "$same"
    for ranks in 1 2 3 4; do
        line=$(run "np$ranks.t$threads" mpirun --oversubscribe -np "$ranks" "$rtt" render --threads "$threads")
        read -r frame wall same cpu <<<"${line%%|*}"
        shares=${line#*|}
        speedup=$(echo "$base_frame / $frame" | bc -l)
        printf '| %s x %s | %s | %.2f | %s | %s | %s | %s |\n' "$ranks" "$threads" "$frame" "$speedup" \
            "$(printf %.2f "$wall")" "$cpu" "$same" "$shares"
    done
done
echo
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
