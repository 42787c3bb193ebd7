"""bench/results/pgrid.md's tables from `rtt bench --json` runs:

    python3 bench/results/pgrid/tables.py primary RUN.json...   # --accel pgrid --only primary,build
    python3 bench/results/pgrid/tables.py shadow RUN.json...    # --only shadow,build

primary: per thread count, the pgrid eye-ray row (build included), the
share of its frame the grid's build takes, Embree's best coherent variant
and llvmpipe in the same run.  shadow: the pgrid hard-shadow row, its light
grid's build, Embree's best rtcOccluded16 variant and bvh-packet on the same
rays in the same run."""
import json, sys


def pick(rows, **want):
    return [r for r in rows if all(r.get(k) == v for k, v in want.items())]


def pct(x):
    return f"{x * 100:.2f}%" if x is not None else "-"


def primary(d, name):
    rows, out = d['rows'], []
    for t in (1, 2):
        p = pick(rows, kind='primary', method='pgrid', threads=t)[0]
        emb = max((r for r in rows if r['kind'] == 'primary' and r['engine'] == 'embree' and r['threads'] == t
                   and r['lanes'] >= 4), key=lambda r: r['fps'])
        ll = pick(rows, engine='llvmpipe', threads=t)
        build = [r for r in pick(rows, kind='build', threads=t) if r['method'].startswith('pgrid')]
        share = f"{build[0]['seconds'] * p['fps'] * 100:.0f}%" if build else "-"
        lf = ll[0]['fps'] if ll else float('nan')
        out.append(f"| {name} | {d['width']}x{d['height']} | {d['triangles']} | {t} | {p['fps']:.1f} | {share} | "
                   f"{p['rays_per_second'] / 1e6:.1f} | {emb['fps']:.1f} ({emb['method']} {emb['variant']}) | "
                   f"{p['fps'] / emb['fps']:.2f} | {lf:.1f} | {p['fps'] / lf:.2f} | "
                   f"{pct(p.get('agree')) if t == 1 else '-'} | {pct(ll[0].get('agree')) if ll and t == 1 else '-'} |")
    return out


def shadow(d, name):
    rows, out = d['rows'], []
    for t in (1, 2):
        p = pick(rows, kind='shadow', method='pgrid', threads=t)[0]
        emb = max((r for r in rows if r['kind'] == 'shadow' and r['engine'] == 'embree' and r['threads'] == t
                   and 'Occluded16' in r['method']), key=lambda r: r['fps'])
        packet = pick(rows, kind='shadow', method='bvh-packet', threads=t)[0]
        build = pick(rows, kind='build', method='pgrid light', threads=t)[0]
        out.append(f"| {name} | {d['width']}x{d['height']} | {t} | {p['rays']} | {p['fps']:.1f} | "
                   f"{build['variant'].split()[-1]} | {build['seconds'] * 1e3:.1f} ms "
                   f"({build['seconds'] * p['fps'] * 100:.0f}%) | {p['rays_per_second'] / 1e6:.2f} | "
                   f"{emb['fps']:.1f} ({emb['variant']}) | {p['fps'] / emb['fps']:.2f} | {packet['fps']:.1f} | "
                   f"{pct(p.get('agree')) if t == 1 else '-'} |")
    return out


kind = sys.argv[1]
if kind == 'primary':
    print("| scene | size | triangles | threads | pgrid fps | build | Mrays/s | Embree best fps | x Embree | "
          "llvmpipe fps | x llvmpipe | agree E | llvmpipe agree |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
else:
    print("| scene | size | threads | rays | pgrid fps | light res | build | Mrays/s | rtcOccluded16 best fps | "
          "x Embree | bvh-packet fps | agree |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for path in sys.argv[2:]:
    d = json.load(open(path))
    name = d['scene'].split('/')[-1].split('.')[0]
    print("\n".join(primary(d, name) if kind == 'primary' else shadow(d, name)))
