#!/usr/bin/env python3
"""bench/accuracy.sh's report: merges the timing and the sweep into
accuracy.json (keeping the part not rerun), writes the generated tables
into accuracy.md between its markers and the plot's data for accuracy.gp."""
import argparse
import json
import os

BEGIN, END = "<!-- accuracy.sh: generated from here -->", "<!-- accuracy.sh: generated up to here -->"
KD = ["mono", "packet", "omni", "frustum", "mft", "cone", "mft-cone"]
BVH = ["bvh-mono", "bvh-packet", "bvh-mft"]


def pct(x):
    return "—" if x is None else ("0" if x == 0 else f"{100 * x:.3g} %")


def sci(x):
    return "—" if x is None else f"{x:.2g}"


def placement(r):
    return f"scale {r['scale']:g}" if r["offset"] == 0 else f"offset {r['offset']:g}"


def timing_tables(t):
    # a 1-minute load average above one runnable task besides the bench's own is a shared machine
    shared = float(t["load_before"].split()[0]) > 1.5
    load = (": **the machine was shared** with other builds and tests, so single rows swing both ways; rerun on a "
            "quiet machine with `bench/accuracy.sh --timing-only`" if shared else
            ": the machine was otherwise idle")
    lines = [f"Mesh {t['mesh']}, view {t['view']}, {t['threads']} thread, median of {t['frames']} frames per row; "
             f"load average (1, 5, 15 min) {t['load_before']} before and {t['load_after']} after{load}.", "",
             "| kernel | watertight ms/frame | projected ms/frame | watertight / projected |", "|---|---|---|---|"]
    pairs = {}
    for r in t["rows"]:
        if r.get("engine") != "rtt" or not r.get("fps") or r["method"].startswith("pgrid"):
            continue  # the perspective grid is neither a kd nor a BVH kernel
        variant = r.get("variant", "").replace(" watertight", "").replace(" projected", "")
        key = (r["method"], variant)
        pairs.setdefault(key, {})[r.get("isect") or "projected"] = 1000.0 / r["fps"]  # rows without isect: projected
    ratios = []
    for (method, variant), v in pairs.items():
        w, p = v.get("watertight"), v.get("projected")
        ratio = w / p if w and p else None
        if ratio:
            ratios.append(ratio)
        name = f"{method} ({variant})" if variant else method
        lines.append(f"| {name} | {w and f'{w:.1f}' or '—'} | {p and f'{p:.1f}' or '—'} | "
                     f"{ratio and f'{ratio:.2f}' or '—'} |")
    for r in t["rows"]:
        if r.get("engine") == "embree" and r.get("fps"):
            lines.append(f"| Embree {r['method']} {r.get('variant', '')} (peer) | — | — | {1000.0 / r['fps']:.1f} ms |")
    if ratios:
        g = 1.0
        for x in ratios:
            g *= x
        g **= 1.0 / len(ratios)
        lines += ["", f"Over the {len(ratios)} kd rows timed with both tests: geometric mean of watertight / projected "
                  f"**{g:.2f}**, best {min(ratios):.2f}, worst {max(ratios):.2f}."]
    return lines, pairs


def label(r):
    return r["kernel"] if r["engine"] != "optimized" else f"{r['accel']} {r['kernel']}"


def sweep_tables(rows, rays):
    out = [f"{rays} rays per set and placement.  Escape: the brute force hits (every ray from inside a closed "
           "mesh must), the engine misses.  t error: |t − t_bf| / t_bf over the random rays both hit (a hit on "
           "another triangle counts).  Shared edges: rays from outside aimed exactly at vertices and edge "
           "midpoints whose hit/miss differs from the brute force, and of those the ones the engine missed; on a closed "
           "mesh a ray through an interior shared edge hits one of its two triangles however it is rounded, so what "
           "differs there are silhouette edges the ray grazes (its float direction passes a hair inside or "
           "outside).  A placement where `rtt trace` failed is listed, not counted.", ""]
    engines = []
    for r in rows:
        key = (r["engine"], r["accel"], r["kernel"], r["isect"])
        if key not in engines:
            engines.append(key)
    out += ["### Every kernel, all placements and meshes pooled", "",
            "| engine / kernel | test | escapes, random inside | escapes, vertex-aimed inside | t error max | t error mean | shared edges: hit/miss differs (engine missed) | failed placements |",
            "|---|---|---|---|---|---|---|---|"]
    summary = {}
    for key in engines:
        mine = [r for r in rows if (r["engine"], r["accel"], r["kernel"], r["isect"]) == key]
        ok = [r for r in mine if "failed" not in r]
        def total(kind, field):
            sel = [r for r in ok if r["rays_kind"] == kind]
            return sum(r.get(field) or 0 for r in sel), sum(r.get("oracle_hits") or 0 for r in sel), sum(r["rays"] for r in sel)
        er, hr, _ = total("inside_random", "escapes")
        ev, hv, _ = total("inside_vertex", "escapes")
        em, _, ne = total("edges", "hit_miss")
        emiss, _, _ = total("edges", "engine_missed")
        rnd = [r for r in ok if r["rays_kind"] == "random" and r.get("t_rel_error_max") is not None]
        tmax = max((r["t_rel_error_max"] for r in rnd), default=None)
        tmean = sum(r["t_rel_error_mean"] for r in rnd) / len(rnd) if rnd else None
        failed = sorted({placement(r) + " " + r["mesh"] for r in mine if "failed" in r})
        summary[key] = {"escape_random": er / hr if hr else None, "escape_vertex": ev / hv if hv else None,
                        "t_max": tmax, "t_mean": tmean, "edges": em / ne if ne else None}
        out.append(f"| {label(mine[0])} | {key[3]} | {er} of {hr} ({pct(er / hr if hr else None)}) | "
                   f"{ev} of {hv} ({pct(ev / hv if hv else None)}) | {sci(tmax)} | {sci(tmean)} | "
                   f"{em} of {ne} ({pct(em / ne if ne else None)}; {emiss} missed) | {', '.join(failed) or '—'} |")
    # per placement, the default kernel under both tests, the BVH's, Embree
    shown = [("optimized", "kd", "mft", "watertight"), ("optimized", "kd", "mft", "projected"),
             ("optimized", "bvh", "bvh-mft", "watertight"), ("optimized", "bvh", "bvh-mft", "projected"),
             ("embree", "", "embree", "robust")]
    for mesh in dict.fromkeys(r["mesh"] for r in rows):
        places = list(dict.fromkeys((r["scale"], r["offset"]) for r in rows if r["mesh"] == mesh))
        out += ["", f"### {mesh}: per placement (kd mft watertight / kd mft projected / bvh-mft watertight / bvh-mft projected / Embree)", "",
                "| placement | escapes, vertex-aimed | escapes, random | t error max | shared edges hit/miss |",
                "|---|---|---|---|---|"]
        for scale, offset in places:
            cells = {"inside_vertex": [], "inside_random": [], "random": [], "edges": []}
            for key in shown:
                for kind in cells:
                    r = next((r for r in rows if r["mesh"] == mesh and (r["scale"], r["offset"]) == (scale, offset)
                              and r["rays_kind"] == kind and (r["engine"], r["accel"], r["kernel"], r["isect"]) == key), None)
                    if r is None or "failed" in r:
                        cells[kind].append("fail" if r else "—")
                    elif kind.startswith("inside"):
                        cells[kind].append(pct(r["escape_rate"]))
                    elif kind == "random":
                        cells[kind].append(sci(r["t_rel_error_max"]))
                    else:
                        cells[kind].append(str(r["hit_miss"]))
            name = f"scale {scale:g}" if offset == 0 else f"offset {offset:g}"
            out.append(f"| {name} | {' / '.join(cells['inside_vertex'])} | {' / '.join(cells['inside_random'])} | "
                       f"{' / '.join(cells['random'])} | {' / '.join(cells['edges'])} |")
    return out, summary


def plot_data(pairs, summary, rows, path):
    with open(path, "w") as f:
        # index 0, 1: the front, ms per frame against escape rate (vertex-aimed), per kd kernel at tile 8
        for isect in ("watertight", "projected"):
            f.write(f"# {isect}: ms/frame, escape rate % (vertex-aimed inside rays), kernel\n")
            for (method, variant), v in pairs.items():
                kernel = method.split()[0]
                tile = method.split()[1] if len(method.split()) > 1 else ""
                if variant != "cull on" or (tile not in ("", "2x2", "8x8")) or isect not in v:
                    continue
                s = summary.get(("optimized", "kd", kernel, isect))
                if s and s["escape_vertex"] is not None:
                    f.write(f"{v[isect]:.3f} {100 * s['escape_vertex']:.4f} {kernel}\n")
            f.write("\n\n")
        # index 2..5: escape rate (vertex-aimed) per sphere placement
        shown = [("optimized", "kd", "mft", "watertight"), ("optimized", "kd", "mft", "projected"),
                 ("optimized", "bvh", "bvh-mft", "projected"), ("embree", "", "embree", "robust")]
        places = list(dict.fromkeys((r["scale"], r["offset"]) for r in rows if r["mesh"] == "sphere"))
        for key in shown:
            f.write(f"# {key}: placement index, escape rate %, label\n")
            for i, (scale, offset) in enumerate(places):
                r = next((r for r in rows if r["mesh"] == "sphere" and (r["scale"], r["offset"]) == (scale, offset)
                          and r["rays_kind"] == "inside_vertex"
                          and (r["engine"], r["accel"], r["kernel"], r["isect"]) == key), None)
                name = f"s{scale:g}" if offset == 0 else f"o{offset:g}"
                if r is not None and "failed" not in r and r["escape_rate"] is not None:
                    f.write(f"{i} {100 * r['escape_rate']:.4f} {name}\n")
                else:
                    f.write(f"{i} NaN {name}\n")
            f.write("\n\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", required=True)
    ap.add_argument("--md", required=True)
    ap.add_argument("--dat", required=True)
    ap.add_argument("--timing")
    ap.add_argument("--sweep")
    ap.add_argument("--rays", type=int)
    a = ap.parse_args()
    data = json.load(open(a.json)) if os.path.exists(a.json) else {}
    if not isinstance(data, dict) or "sweep" not in data and "timing" not in data:
        data = {}
    if a.timing:
        data["timing"] = json.load(open(a.timing))
    if a.sweep:
        data["sweep"] = json.load(open(a.sweep))
        data["rays_per_set"] = a.rays
    if "timing" not in data or "sweep" not in data:
        raise SystemExit("accuracy report: both the timing and the sweep are needed (run bench/accuracy.sh whole once)")
    with open(a.json, "w") as f:
        json.dump(data, f, indent=1)
    lines, pairs = timing_tables(data["timing"])
    sweep, summary = sweep_tables(data["sweep"], data["rays_per_set"])
    generated = ["## Time per primary frame", ""] + lines + ["", "## Accuracy against the double brute force", ""] + sweep
    text = open(a.md).read() if os.path.exists(a.md) else f"# Accuracy\n\n{BEGIN}\n{END}\n"
    head, rest = text.split(BEGIN, 1) if BEGIN in text else (text + "\n", END)
    tail = rest.split(END, 1)[1] if END in rest else ""
    with open(a.md, "w") as f:
        f.write(head + BEGIN + "\n\n" + "\n".join(generated) + "\n\n" + END + tail)
    plot_data(pairs, summary, data["sweep"], a.dat)


if __name__ == "__main__":
    main()
