"""bench/results/frusta.md's tables: python3 bench/results/frusta/table1.py RUN.json..."""
import json, sys
for path in sys.argv[1:]:
    d = json.load(open(path))
    name = d['scene'].split('/')[-1]  # the rows of bench/results/frusta/*.json as Benthin & Wald's Table 1 (soft, shadow)
    print(f"\n### {name} ({d['triangles']} triangles, {d['width']}x{d['height']}, median of {d['frames']} frames)\n")
    print("| kind | engine | method | variant | threads | frame s | Mrays/s | xEmbree | agree | #tris (+culling) | #AABB tests | #isec tests |")
    print("|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in d['rows']:
        if r['kind'] not in ('soft', 'shadow'): continue
        if r['engine'] == 'embree' and (r['lanes'] != 16 or r['variant'].startswith('sse4.2')): continue  # native ISA only
        if r['engine'] == 'rtt' and not (r['method'].startswith('bvh-') or r['method'].startswith('frusta')): continue
        if r['method'] == 'bvh-mono': continue
        # BVH rows: N, I per 2x2 slots of the rays' image (soft: 4x wider and higher);
        # frusta:16 at c892a43 (these runs): per 2x2 active rays
        quads = r['rays'] / 4 if r['method'].startswith('frusta') else d['width'] * d['height'] * (16 if r['kind'] == 'soft' else 1) / 4
        aabb = f"{r['N']*quads/1e3:.0f}K" if r.get('N') is not None and r['N'] >= 0 else ""
        isec = f"{r['I']*quads/1e3:.0f}K" if r.get('I') is not None and r['I'] >= 0 else ""
        tris = r['variant'].split('tris ')[1] if 'tris ' in r['variant'] else ""
        variant = r['variant'].split(' tris')[0]
        agree = f"{100*r['agree']:.4f}%" if r.get('agree') is not None and r['agree'] >= 0 else ""
        print(f"| {r['kind']} | {r['engine']} | {r['method']} | {variant} | {r['threads']} | {r['seconds']:.4f} | {r['rays_per_second']/1e6:.2f} | {r['vs_embree']:.2f} | {agree} | {tris} | {aabb} | {isec} |")
