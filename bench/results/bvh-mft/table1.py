"""bench/results/bvh-mft.md's Table 1 rows: python3 bench/results/bvh-mft/table1.py RUN.json...

Per scene: primary rays (bvh-packet = P-Packet, bvh-mft = P-Frusta) and soft
shadows (bvh-packet on one pixel's 16 rays = S-Packet, frusta:16 = S-Frusta),
Embree's best coherent variant (4/8/16 lanes, any ISA and scene flag) at the
same thread count, all rows of one run."""
import json, sys


def rate(rows, kind, method, threads):
    for r in rows:
        if r['engine'] == 'rtt' and r['kind'] == kind and r['method'] == method and r['threads'] == threads:
            return r
    return None


def embree_best(rows, kind, threads):
    best = None
    for r in rows:
        if r['engine'] == 'embree' and r['kind'] == kind and r['threads'] == threads and r['lanes'] >= 4:
            if best is None or r['rays_per_second'] > best['rays_per_second']:
                best = r
    return best


print("| scene | tris | kind | Packet N | Frusta N | Packet I | Frusta I | bvh-packet Mrays/s t1 / t2 | frusta Mrays/s t1 / t2 | Embree best Mrays/s t1 / t2 (variant t1) | frusta / Embree t1 / t2 | frusta / packet t1 / t2 |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for path in sys.argv[1:]:
    d = json.load(open(path))
    name = d['scene'].split('/')[-1].split('.')[0]
    rows = d['rows']
    for kind, frusta in (('primary', 'bvh-mft'), ('soft', 'frusta:16')):
        p1, p2 = rate(rows, kind, 'bvh-packet', 1), rate(rows, kind, 'bvh-packet', 2)
        f1, f2 = rate(rows, kind, frusta, 1), rate(rows, kind, frusta, 2)
        e1, e2 = embree_best(rows, kind, 1), embree_best(rows, kind, 2)
        if not (p1 and f1 and e1):
            continue
        m = lambda r: r['rays_per_second'] / 1e6 if r else float('nan')
        n = lambda r, k: f"{r[k]:.2f}" if r and r.get(k) is not None and r[k] >= 0 else ""
        print(f"| {name} | {d['triangles']} | {kind} | {n(p1, 'N')} | {n(f1, 'N')} | {n(p1, 'I')} | {n(f1, 'I')} "
              f"| {m(p1):.2f} / {m(p2):.2f} | {m(f1):.2f} / {m(f2):.2f} "
              f"| {m(e1):.2f} / {m(e2):.2f} ({e1['method']} {e1['variant']}) "
              f"| {m(f1) / m(e1):.2f} / {m(f2) / m(e2):.2f} | {m(f1) / m(p1):.2f} / {m(f2) / m(p2):.2f} |")
print()
print("| scene | BVH build s / MB | Embree HQ build s / MB | BVH / Embree |")
print("|---|---|---|---|")
for path in sys.argv[1:]:
    d = json.load(open(path))
    name = d['scene'].split('/')[-1].split('.')[0]
    b = [r for r in d['rows'] if r['kind'] == 'build']
    ours = [r for r in b if r['engine'] == 'rtt' and 'bvh' in (r['method'] + r['variant']).lower()]
    emb = [r for r in b if r['engine'] == 'embree']
    if ours and emb:
        o, e = ours[0], min(emb, key=lambda r: r['seconds'])
        mb = lambda r: r.get('memory_bytes', 0) / 1e6 if r.get('memory_bytes') else float('nan')
        print(f"| {name} | {o['seconds']:.3f} / {mb(o):.1f} | {e['seconds']:.3f} / {mb(e):.1f} | {o['seconds'] / e['seconds']:.2f}x |")
