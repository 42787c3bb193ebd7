#!/usr/bin/env bash
# Runs `rtt bench` on every real benchmark scene (bench/fetch-scenes.sh) at
# 512x512 and 1024x1024 with the views of bench/views.json, and writes
#
#   bench/results/runs/<scene>-<size>.{json,md,tsv}   each run's report (kept, so runs
#                                  of separate invocations add up: --scenes picks a subset)
#   bench/results/<date>.json      every kept run's full report, the machine and the command
#   bench/results/report.md        the thesis' tables per scene and size, Embree ratios
#                                  beside them, and a summary of the headline ratios
#   bench/results/rays-<size>.png  primary rays/s per method and tile size, one panel per scene
#   bench/results/vs-embree.png    MFT (best tile) over Embree's best coherent variant per scene
#
# Usage: bench/run-all.sh [--rtt PATH] [--sizes "512 1024"] [--scenes "oa_dm4 ..."]
#                         [--frames N] [--threads LIST] [--only KINDS] [--out DIR] [--quick]
# RTT defaults to build/cli/rtt.  Each scene and size is one `rtt bench` process;
# a failing one is reported in report.md and the others still run.
set -euo pipefail
shopt -s inherit_errexit

src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rtt="${RTT:-$src/build/cli/rtt}"
sizes="512 1024"
scenes="oa_dm4 ctf_inyard czest3ctf bunny00 armadillo refined_elephant"
frames=5
threads=1,2
out="$src/bench/results"
extra=()
command_line="bench/run-all.sh $*"

die() { echo "run-all: $*" >&2; exit 1; }
usage() { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; }

while [[ $# -gt 0 ]]; do
    case "$1" in
        --help | -h) usage; exit 0 ;;
        --rtt) rtt="${2:?--rtt needs a path}"; shift 2 ;;
        --sizes) sizes="${2:?--sizes needs a list}"; shift 2 ;;
        --scenes) scenes="${2:?--scenes needs a list}"; shift 2 ;;
        --frames) frames="${2:?--frames needs a number}"; shift 2 ;;
        --threads) threads="${2:?--threads needs a list}"; shift 2 ;;
        --out) out="${2:?--out needs a directory}"; shift 2 ;;
        --quick) extra+=(--quick); shift ;;
        --only) extra+=(--only "${2:?--only needs a list}"); shift 2 ;;
        *) usage >&2; exit 2 ;;
    esac
done
[[ -x "$rtt" ]] || die "no rtt binary at $rtt (build first, or pass --rtt PATH)"
command -v gnuplot >/dev/null 2>&1 || die "gnuplot is not installed (ci/install-deps.sh installs gnuplot-nox)"
data="$(bash "$src/bench/fetch-scenes.sh")" || die "fetching the scenes failed"
mkdir -p "$out/runs"
work="$(mktemp -d "${TMPDIR:-/tmp}/rtt-bench.XXXXXX")"
trap 'rm -rf "$work"' EXIT

date_utc="$(date -u +%Y-%m-%d)"
stamp="$(date -u +%Y-%m-%dT%H:%M:%SZ)"
cpu="$(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1)"
cores="$(nproc)"
embree="$(dpkg-query -W -f='${Version}' libembree3-3 2>/dev/null || echo unknown)"
compiler="$(cc --version | head -n 1)"
isa="$(grep -o -w -E 'avx512f|avx2|avx|sse4_2' /proc/cpuinfo | sort -u | tr '\n' ' ')"

scene_file() {
    if [[ -s "$data/maps/$1.bsp" ]]; then echo "$data/maps/$1.bsp"
    elif [[ -s "$data/meshes/$1.off" ]]; then echo "$data/meshes/$1.off"
    else return 1; fi
}

runs=()
failed=()
for scene in $scenes; do
    file="$(scene_file "$scene")" || { failed+=("$scene: no file in $data"); continue; }
    for size in $sizes; do
        base="$out/runs/$scene-$size"
        echo "run-all: $scene at ${size}x$size" >&2
        start=$SECONDS
        if "$rtt" bench "$file" --views "$src/bench/views.json" --size "$size" --frames "$frames" \
            --threads "$threads" "${extra[@]}" --json --markdown "$base.md" --tsv "$base.tsv" \
            >"$work/run.json" 2>"$work/run.err"; then
            mv "$work/run.json" "$base.json"
            echo "$stamp \`$command_line\`" >"$base.cmd"
            echo "run-all: $scene at ${size}x$size took $((SECONDS - start)) s" >&2
        else
            failed+=("$scene ${size}x$size: $(tail -n 1 "$work/run.err")")
        fi
    done
done
for scene in oa_dm4 ctf_inyard czest3ctf bunny00 armadillo refined_elephant $scenes; do
    for size in 512 1024 $sizes; do
        base="$out/runs/$scene-$size"
        [[ -s "$base.json" && -s "$base.md" && -s "$base.tsv" ]] || continue
        [[ " ${runs[*]+${runs[*]}} " == *" $base "* ]] || runs+=("$base")
    done
done
[[ ${#runs[@]} -gt 0 ]] || die "no benchmark run succeeded: ${failed[*]}"

# ---- JSON: every report plus the machine and the command ----
{
    printf '{\n  "date": "%s",\n  "command": "%s",\n' "$stamp" "$command_line"
    printf '  "machine": {"cpu": "%s", "cores": %s, "isa": "%s", "compiler": "%s", "embree": "%s"},\n' \
        "$cpu" "$cores" "${isa% }" "$compiler" "$embree"
    printf '  "failed": ['
    sep=""
    for f in "${failed[@]+"${failed[@]}"}"; do printf '%s"%s"' "$sep" "${f//\"/\'}"; sep=", "; done
    printf '],\n  "runs": [\n'
    sep=""
    for r in "${runs[@]}"; do printf '%s' "$sep"; cat "$r.json"; sep=","; done
    printf '\n  ]\n}\n'
} >"$work/all.json"
mv "$work/all.json" "$out/$date_utc.json"

cat "${runs[@]/%/.tsv}" >"$work/all.tsv"

# ---- plots ----
# rays/s per method and tile size (primary kernels, 1 thread), one panel per scene
for size in $sizes; do
    awk -F'\t' -v size="${size}x$size" -v dir="$work" '
        $1 == "row" && $3 == size && $4 == "primary" && $9 == 1 {
            if ($5 == "embree") { if ($7 ~ /native/ && $10 > best[$2]) { best[$2] = $10; bestr[$2] = $11 } next }
            m = $6; tile = $8
            if (tile == 0) { flat[$2 "\t" m] = $11; next }
            sub(/_[0-9]+x[0-9]+/, "", m)
            print tile, $11 > (dir "/p-" size "-" $2 "-" m ".dat")
        }
        END {
            for (s in bestr) print bestr[s] > (dir "/p-" size "-" s "-embree.val")
            for (k in flat) { split(k, a, "\t"); print flat[k] > (dir "/p-" size "-" a[1] "-" a[2] ".val") }
        }' "$work/all.tsv"
    panels=""
    for scene in $scenes; do ls "$work"/p-"${size}x$size"-"$scene"-*.dat >/dev/null 2>&1 && panels="$panels $scene"; done
    [[ -n "$panels" ]] || continue
    {
        echo "set terminal pngcairo size 1500,900 font ',10' noenhanced"
        echo "set output '$out/rays-$size.png'"
        echo "set multiplot layout 2,3 title 'Primary rays, traversal kernels alone, 1 thread, ${size}x$size (Mrays/s; flat lines: 2x2 packets and Embree best native variant)'"
        echo "set logscale x 2; set xtics (4, 8, 16, 32); set xlabel 'tile side'; set ylabel 'Mrays/s'; set key left top"
        for scene in $panels; do
            plots=()
            for family in frustum frustum_nocull mft cone mft-cone; do
                f="$work/p-${size}x$size-$scene-$family.dat"
                [[ -s "$f" ]] && plots+=("'$f' using 1:(\$2/1e6) with linespoints title '$family'")
            done
            for flat in packet_2x2 embree; do
                f="$work/p-${size}x$size-$scene-$flat.val"
                [[ -s "$f" ]] && plots+=("$(awk '{printf "%g", $1/1e6}' "$f") with lines dashtype 2 title '$flat'")
            done
            echo "set title '$scene'"
            (IFS=,; echo "plot [3:40] ${plots[*]}")
        done
        echo "unset multiplot"
    } >"$work/rays-$size.gp"
    gnuplot "$work/rays-$size.gp" || echo "run-all: gnuplot failed on rays-$size.png" >&2
done

# speed-up of MFT (best tile) against Embree's best coherent variant, per scene and size
awk -F'\t' '$1 == "headline" && $4 ~ /^mft_vs_embree_t/ { t = $4; sub(/mft_vs_embree_t/, "", t); v[$2 " " $3, t] = $5; k[$2 " " $3] = 1; th[t] = 1 }
    END { printf "run"; n = 0; for (t in th) ts[++n] = t; asort_n = n
          for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (ts[j] + 0 < ts[i] + 0) { x = ts[i]; ts[i] = ts[j]; ts[j] = x }
          for (i = 1; i <= n; i++) printf "\t%s_thread%s", ts[i], ts[i] == 1 ? "" : "s"; printf "\n"
          for (r in k) { lbl = r; gsub(/ /, "_", lbl); printf "%s", lbl; for (i = 1; i <= n; i++) printf "\t%s", ((r, ts[i]) in v) ? v[r, ts[i]] : 0; printf "\n" } }' \
    "$work/all.tsv" | { read -r header; echo "$header"; sort; } >"$work/vs-embree.dat"
if [[ $(wc -l <"$work/vs-embree.dat") -gt 1 ]]; then
    columns=$(head -n 1 "$work/vs-embree.dat" | awk -F'\t' '{print NF}')
    cat >"$work/vs-embree.gp" <<EOF
set terminal pngcairo size 1300,600 font ',10' noenhanced
set output '$out/vs-embree.png'
set title 'Primary visibility: MFT at its best tile over Embree best coherent variant (same rays, same threads); 1 = parity'
set style data histograms; set style histogram clustered gap 1; set style fill solid 0.8 border -1
set datafile separator '\t'; set key top left; set ylabel 'speed-up'; set xtics rotate by -30
set yrange [0:*]; set arrow from graph 0, first 1 to graph 1, first 1 nohead dashtype 2
plot for [c=2:$columns] '$work/vs-embree.dat' using c:xtic(1) title columnheader(c)
EOF
    gnuplot "$work/vs-embree.gp" || echo "run-all: gnuplot failed on vs-embree.png" >&2
fi

# ---- report.md ----
{
    echo "# rtt benchmark report"
    echo
    echo "- date: $stamp"
    echo "- commands of the kept runs (runs of several invocations add up; each scene: \`rtt bench SCENE --views bench/views.json --size N --frames N --threads LIST --json --markdown --tsv\`):"
    for r in "${runs[@]}"; do [[ -s "$r.cmd" ]] && cat "$r.cmd"; done | sort -u | sed 's/^/  - /'
    echo "- machine: $cpu, $cores cores visible, ISA flags: ${isa% }; $compiler; Embree $embree (Debian)"
    echo "- data: bench/results/$date_utc.json; plots: $(cd "$out" && ls rays-*.png vs-embree.png 2>/dev/null | tr '\n' ' ')"
    echo
    echo "Every ratio is between rows measured in the same process and run: medians of the timed frames after a warm-up"
    echo "(each run's section gives its frame count)."
    echo "Primary rows time the traversal kernels alone on the camera's primary rays, pre-formed into tile blocks as"
    echo "the renderer forms them; Embree traces exactly the same rays through the same tile scheduler and threads."
    echo "Embree variants: native ISA (Embree's own choice on this CPU) or pinned to SSE4.2 (our kernels' ISA), scene flag"
    echo "RTC_SCENE_FLAG_ROBUST or none, RTC_BUILD_QUALITY_HIGH; 4/8/16-wide calls use RTC_INTERSECT_CONTEXT_FLAG_COHERENT."
    echo "\"Embree best coherent\" is the fastest of the 4/8/16-wide calls over all variants."
    echo
    echo "Measured apart, by hand, with their commands: [tree-depth.md](tree-depth.md) (the kd-tree depth bound, the"
    echo "builder at one million triangles, the cost of checking a baked tree), [kernel-tuning.md](kernel-tuning.md)"
    echo "(the frustum and MFT kernels' tuning), [shadows.md](shadows.md) (the soft-shadow trade, bench/shadows.sh)."
    echo
    echo "## Headline ratios (targets: MFT at least Embree's best coherent packets, frustum faster than 2x2 packets)"
    echo
    echo "| scene | size | ratio | measured | target | rows |"
    echo "|---|---|---|---:|---:|---|"
    awk -F'\t' '$1 == "headline" { printf "| %s | %s | %s | %.2f× | %.2f× %s | %s |\n", $2, $3, $4, $5, $6, ($5 >= $6 ? "met" : "missed"), $7 }' \
        "$work/all.tsv"
    if [[ ${#failed[@]} -gt 0 ]]; then
        echo
        echo "## Runs that failed"
        echo
        for f in "${failed[@]}"; do echo "- $f"; done
    fi
    echo
    for plot in "$out"/rays-*.png "$out"/vs-embree.png; do
        [[ -e "$plot" ]] && echo "![$(basename "$plot" .png)]($(basename "$plot"))"
    done
    echo
    for r in "${runs[@]}"; do cat "$r.md"; done
} >"$work/report.md"
mv "$work/report.md" "$out/report.md"
echo "run-all: wrote $out/$date_utc.json, $out/report.md and the plots" >&2
