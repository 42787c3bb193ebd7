#!/usr/bin/env python3
"""The accuracy sweep of bench/accuracy.sh (see there for what it measures).

For each closed mesh and each placement (scale s at offset 0, or scale 1 at
offset o: every coordinate x -> x * s + o, in double), writes the scene as a
JSON file with the vertices in full double precision (rtt reads them in
double), the exact triangles for the double brute force (oracle.c), and four
ray sets: random directions from a point inside the mesh, rays from that
point aimed at every vertex and edge midpoint (`rtt rays --kind inside`),
random rays in and around the bounds (`--kind random`) and rays aimed from
outside exactly at vertices and edge midpoints, the shared edges (`--kind
vertex`).  Traces them with every kd and BVH kernel under both triangle
tests, Embree and the reference (`rtt trace`), and compares each hit with the
brute force.  Writes one JSON row per (mesh, placement, engine, ray set).
"""
import argparse
import json
import math
import os
import random
import struct
import subprocess
import sys

KD_KERNELS = ["mono", "packet", "omni", "frustum", "mft", "cone", "mft-cone"]
BVH_KERNELS = ["bvh-mono", "bvh-packet", "bvh-mft"]
SCALES = [1e-20, 1e-10, 1.0, 1e10, 1e20]
OFFSETS = [1.0, 1e3, 1e5, 1e7]


def sphere(segments=48, rings=24):
    """A closed UV sphere of radius 1, shared vertices, poles single."""
    verts = [(0.0, 1.0, 0.0)]
    for r in range(1, rings):
        th = math.pi * r / rings
        for s in range(segments):
            ph = 2 * math.pi * s / segments
            verts.append((math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)))
    verts.append((0.0, -1.0, 0.0))
    south = len(verts) - 1
    ring = lambda r, s: 1 + (r - 1) * segments + s % segments
    tris = []
    for s in range(segments):
        tris.append((0, ring(1, s + 1), ring(1, s)))
        tris.append((south, ring(rings - 1, s), ring(rings - 1, s + 1)))
    for r in range(1, rings - 1):
        for s in range(segments):
            a, b, c, d = ring(r, s), ring(r, s + 1), ring(r + 1, s), ring(r + 1, s + 1)
            tris += [(a, b, d), (a, d, c)]
    return verts, tris


def read_off(path):
    words = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].split()
            words += line
    if words[0] != "OFF":
        raise SystemExit(f"{path}: not an OFF file")
    nv, nf = int(words[1]), int(words[2])
    at = 4
    verts = []
    for _ in range(nv):
        verts.append(tuple(float(w) for w in words[at:at + 3]))
        at += 3
    tris = []
    for _ in range(nf):
        n = int(words[at])
        idx = [int(w) for w in words[at + 1:at + 1 + n]]
        at += 1 + n
        for k in range(1, n - 1):  # fan, as the scene loader does
            tris.append((idx[0], idx[k], idx[k + 1]))
    # centred on its bounds and brought to a radius of about 1: the sweep's
    # scales are then the scene's size
    lo = [min(v[a] for v in verts) for a in range(3)]
    hi = [max(v[a] for v in verts) for a in range(3)]
    c = [(lo[a] + hi[a]) / 2 for a in range(3)]
    r = max(hi[a] - lo[a] for a in range(3)) / 2
    return [tuple((v[a] - c[a]) / r for a in range(3)) for v in verts], tris


def run(cmd, **kw):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def read_rays(path):
    data = open(path, "rb").read()
    return [struct.unpack_from("<8f", data, 32 * i) for i in range(len(data) // 32)]


def write_rays(path, rays):
    with open(path, "wb") as f:
        for r in rays:
            f.write(struct.pack("<8f", *r))


def read_hits(path, n):
    data = open(path, "rb").read()
    if len(data) != 16 * n:
        return None
    return [struct.unpack_from("<3fI", data, 16 * i) for i in range(n)]


def read_oracle(path, n):
    data = open(path, "rb").read()
    return [struct.unpack_from("<dI", data, 12 * i) for i in range(n)]


def engines():
    out = [("optimized", "kd", k, isect) for isect in ("watertight", "projected") for k in KD_KERNELS]
    out += [("optimized", "bvh", k, isect) for isect in ("watertight", "projected") for k in BVH_KERNELS]
    out += [("embree", "", "embree", "robust"), ("reference", "", "reference", "watertight")]
    return out


def trace_cmd(rtt, scene, rays, hits, engine):
    name, accel, kernel, isect = engine
    cmd = [rtt, "trace", scene, "--rays", rays, "-o", hits, "--engine", name]
    if name == "optimized":
        cmd += ["--accel", accel, "--traversal", kernel, "--isect", isect]
    return cmd


def measure(kind, rays, oracle, hits):
    """The row's numbers for one ray set."""
    n = len(rays)
    oracle_hits = sum(1 for t, p in oracle if p != 0xFFFFFFFF)
    escapes = hitmiss = 0
    errors = []
    for ray, (to, po), (te, ue, ve, pe) in zip(rays, oracle, hits):
        o_hit, e_hit = po != 0xFFFFFFFF, pe != 0xFFFFFFFF
        if o_hit and not e_hit:
            escapes += 1
        if o_hit != e_hit:
            hitmiss += 1
        if o_hit and e_hit and to > 0 and math.isfinite(te):
            errors.append(abs(te - to) / to)
    row = {"rays": n, "oracle_hits": oracle_hits, "hit_miss": hitmiss, "engine_missed": escapes}
    if kind.startswith("inside"):
        row["escapes"] = escapes
        row["escape_rate"] = escapes / oracle_hits if oracle_hits else None
    row["t_rel_error_max"] = max(errors) if errors else None
    row["t_rel_error_mean"] = sum(errors) / len(errors) if errors else None
    row["hit_miss_rate"] = hitmiss / n if n else None
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtt", required=True)
    ap.add_argument("--oracle", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--rays", type=int, default=4096)
    ap.add_argument("--meshes", default="")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    meshes = [("sphere", sphere(), [(s, 0.0) for s in SCALES] + [(1.0, o) for o in OFFSETS])]
    bunny = os.path.join(a.meshes, "bunny00.off")
    if a.meshes and os.path.exists(bunny):  # the bench mesh: fewer placements (its brute force is 19x the sphere's)
        meshes.append(("bunny00", read_off(bunny), [(1e-20, 0.0), (1.0, 0.0), (1e20, 0.0), (1.0, 1e5), (1.0, 1e7)]))
    rows = []
    rng = random.Random(13)
    for mesh, (verts, tris), placements in meshes:
        for scale, offset in placements:
            tag = f"{mesh}_{scale:g}_{offset:g}"
            place = lambda v: [x * scale + offset for x in v]
            pv = [place(v) for v in verts]
            scene = os.path.join(a.work, tag + ".json")
            with open(scene, "w") as f:
                json.dump({"meshes": [{"vertices": pv, "triangles": [list(t) for t in tris]}]}, f)
            with open(os.path.join(a.work, tag + ".f64"), "wb") as f:
                for t in tris:
                    f.write(struct.pack("<9d", *(pv[t[0]] + pv[t[1]] + pv[t[2]])))
            sets = {}
            for kind, rtt_kind in (("inside_vertex", "inside"), ("random", "random"), ("edges", "vertex")):
                path = os.path.join(a.work, f"{tag}_{kind}.bin")
                r = run([a.rtt, "rays", scene, "--kind", rtt_kind, "-n", str(a.rays), "-o", path, "--seed", "7"])
                if r.returncode != 0:
                    sys.exit(f"rtt rays {rtt_kind} on {tag}: {r.stderr.strip()}")
                sets[kind] = read_rays(path)
            # random directions from the same inside point as the vertex-aimed rays
            o = sets["inside_vertex"][0][:3]
            inside = []
            while len(inside) < a.rays:
                d = [rng.gauss(0, 1) for _ in range(3)]
                n = math.sqrt(sum(x * x for x in d))
                if n > 1e-6:
                    inside.append(tuple(o) + tuple(x / n for x in d) + (0.0, float("inf")))
            sets["inside_random"] = inside
            order = ["inside_random", "inside_vertex", "random", "edges"]
            everything = [r for k in order for r in sets[k]]
            rays_path = os.path.join(a.work, tag + "_all.bin")
            write_rays(rays_path, everything)
            oracle_path = os.path.join(a.work, tag + "_oracle.bin")
            r = run([a.oracle, os.path.join(a.work, tag + ".f64"), rays_path, oracle_path])
            if r.returncode != 0:
                sys.exit(f"oracle on {tag}: {r.stderr.strip()}")
            oracle = read_oracle(oracle_path, len(everything))
            for engine in engines():
                hits_path = os.path.join(a.work, tag + "_hits.bin")
                r = run(trace_cmd(a.rtt, scene, rays_path, hits_path, engine))
                hits = read_hits(hits_path, len(everything)) if r.returncode == 0 else None
                at = 0
                for kind in order:
                    n = len(sets[kind])
                    row = {"mesh": mesh, "triangles": len(tris), "scale": scale, "offset": offset, "rays_kind": kind,
                           "engine": engine[0], "accel": engine[1], "kernel": engine[2], "isect": engine[3]}
                    if hits is None:
                        row["failed"] = f"rtt trace exited {r.returncode}: {r.stderr.strip()[:200]}"
                    else:
                        row.update(measure(kind, sets[kind], oracle[at:at + n], hits[at:at + n]))
                    rows.append(row)
                    at += n
                if os.path.exists(hits_path):
                    os.remove(hits_path)
            print(f"accuracy: {tag} done", file=sys.stderr)
    with open(a.out, "w") as f:
        json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
