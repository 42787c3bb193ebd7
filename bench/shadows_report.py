#!/usr/bin/env python3
"""Report of bench/shadows.sh: rows (JSON lines) -> shadows.json, shadows.md,
shadows.gp (+ shadows.dat) for gnuplot.  Usage: shadows_report.py ROWS OUTDIR THREADS RUNS"""
import json
import os
import sys
from collections import OrderedDict


def main():
    rows_path, out, threads, runs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
    rows = [json.loads(line) for line in open(rows_path) if line.strip()]
    scenes = OrderedDict()
    for r in rows:
        scenes.setdefault(r["scene"], []).append(r)
    main_scenes = [s for s in scenes if "@r" not in s]
    table46 = [s for s in scenes if "@r" in s]

    def by_label(scene):
        return {r["label"]: r for r in scenes[scene]}

    summary = []
    for s in main_scenes:
        rs = by_label(s)
        hard = rs.get("hard")
        if not hard:
            continue
        for r in scenes[s]:
            r["time_vs_hard"] = r["seconds"] / hard["seconds"] if hard["seconds"] > 0 else None
            r["rmse_vs_hard"] = r["rmse"] / hard["rmse"] if hard["rmse"] > 0 else None
        summary.append(s)
    with open(os.path.join(out, "shadows.json"), "w") as f:
        json.dump({"threads": int(threads), "runs": int(runs), "truth": "reference multi:256", "rows": rows}, f,
                  indent=1)

    md = ["# Soft shadows: time against error (bench/shadows.sh)", "",
          f"Optimized renderer (rows labelled `ref`: the reference renderer), {threads} thread(s), median of "
          f"{runs} runs of `rtt render --stats` (render time, no loading or tree build).  Error against the reference renderer's multi:256 (`rtt compare`): RMSE, "
          "largest channel error, share of pixels off by more than 1/255.  edgewidth:R, R a fraction of the "
          "light-to-point distance; +fix = `--edge-leak-fix`." +
          (f"  {os.environ['RTT_SHADOW_NOTE']}" if os.environ.get("RTT_SHADOW_NOTE") else ""), ""]
    for s in main_scenes:
        md += [f"## {s}", "", "| method | time (s) | × hard | rays/s | RMSE | × hard RMSE | max | > 1/255 |",
               "|---|---:|---:|---:|---:|---:|---:|---:|"]
        for r in scenes[s]:
            tv = r.get("time_vs_hard")
            ev = r.get("rmse_vs_hard")
            md.append(f"| {r['label']} | {r['seconds']:.4f} | {tv:.2f} | {r['rays_per_second']:.3g} | "
                      f"{r['rmse']:.5f} | {ev:.2f} | {r['max_error']:.3f} | {100 * r['share_over_1_255']:.1f}% |"
                      if tv is not None and ev is not None else
                      f"| {r['label']} | {r['seconds']:.4f} | | {r['rays_per_second']:.3g} | {r['rmse']:.5f} | | "
                      f"{r['max_error']:.3f} | {100 * r['share_over_1_255']:.1f}% |")
        md.append("")

    # Table 5.1 as ratios: frame rate relative to hard shadows (thesis: 1, 0.80, 0.28, 0.095).
    labels = ["hard"] + sorted({r["label"] for s in main_scenes for r in scenes[s] if r["label"].startswith("edgewidth")},
                               key=lambda l: (float(l.split(":")[1].split("+")[0]), l.endswith("fix"))) + ["multi:4",
                                                                                                          "multi:32"]
    md += ["## Table 5.1 as ratios to hard shadows", "",
           "Frame rate relative to hard shadows (1 / time ratio); the thesis on Sponza: single sample 1.00, edge "
           "width 0.80, 4 samples 0.28, 32 samples 0.095 (15, 12, 4.26, 1.42 fps).", "",
           "| scene | " + " | ".join(labels) + " |", "|---|" + "---:|" * len(labels)]
    for s in summary:
        rs = by_label(s)
        cells = []
        for l in labels:
            r = rs.get(l)
            cells.append(f"{1.0 / r['time_vs_hard']:.2f}" if r and r.get("time_vs_hard") else "")
        md.append(f"| {s} | " + " | ".join(cells) + " |")
    md.append("")

    md += ["## Edge width: cost and error against hard shadows", "",
           "Target: at most 1.3× the time of hard shadows, and lower RMSE than hard on every scene.", "",
           "| scene | method | time × hard | RMSE × hard | lower error than hard |", "|---|---|---:|---:|---|"]
    for s in summary:
        for r in scenes[s]:
            if r["label"].startswith("edgewidth"):
                md.append(f"| {s} | {r['label']} | {r['time_vs_hard']:.2f} | {r['rmse_vs_hard']:.2f} | "
                          f"{'yes' if r['rmse_vs_hard'] < 1 else 'no'} |")
    md.append("")

    md += ["## Table 4.6: cone:16 against pyramid:16", "",
           "The test scenes with the sphere light's radius set to 1 and 2 (thesis, Sponza: cone 1.36× and 1.45× "
           "faster; target ≥ 1.3×).  Same samples, so the same image: the RMSE columns agree.", "",
           "| scene | light radius | cone:16 (s) | pyramid:16 (s) | pyramid / cone | RMSE cone | RMSE pyramid |",
           "|---|---:|---:|---:|---:|---:|---:|"]
    for s in table46:
        rs = by_label(s)
        c, p = rs.get("cone:16"), rs.get("pyramid:16")
        if not c or not p:
            continue
        base, radius = s.split("@r")
        md.append(f"| {base} | {radius} | {c['seconds']:.4f} | {p['seconds']:.4f} | {p['seconds'] / c['seconds']:.2f} | "
                  f"{c['rmse']:.5f} | {p['rmse']:.5f} |")
    for s in main_scenes:
        rs = by_label(s)
        c, p = rs.get("cone:16"), rs.get("pyramid:16")
        if c and p:
            md.append(f"| {s} | scene's | {c['seconds']:.4f} | {p['seconds']:.4f} | {p['seconds'] / c['seconds']:.2f} | "
                      f"{c['rmse']:.5f} | {p['rmse']:.5f} |")
    md.append("")
    with open(os.path.join(out, "shadows.md"), "w") as f:
        f.write("\n".join(md))

    # gnuplot: time against RMSE, one point set per method family
    families = OrderedDict([("hard", lambda l: l == "hard"),
                            ("edgewidth", lambda l: l.startswith("edgewidth") and not l.endswith("fix")),
                            ("edgewidth + leak fix", lambda l: l.startswith("edgewidth") and l.endswith("fix")),
                            ("multi:N", lambda l: l.startswith("multi")),
                            ("cone:16", lambda l: l == "cone:16"),
                            ("pyramid:16", lambda l: l == "pyramid:16"),
                            ("interleaved:N (reference)", lambda l: l.startswith("interleaved") and "nofilter" not in l),
                            ("interleaved:N:nofilter (reference)", lambda l: l.startswith("interleaved") and "nofilter" in l),
                            ("frusta:N", lambda l: l.startswith("frusta") and ":nofilter" not in l and ":refine" not in l),
                            ("frusta:N:nofilter", lambda l: l.startswith("frusta") and ":nofilter" in l),
                            ("frusta:N:refine", lambda l: l.startswith("frusta") and ":refine" in l)])
    dat = os.path.join(out, "shadows.dat")
    with open(dat, "w") as f:
        for fam, test in families.items():
            f.write(f"# {fam}\n")
            for s in summary:
                for r in scenes[s]:
                    if test(r["label"]):
                        f.write(f"{r['time_vs_hard']:.6g} {r['rmse']:.6g} \"{s}:{r['label']}\"\n")
            f.write("\n\n")
    # the plot names its files relative to the results directory (shadows.sh runs gnuplot there), so the
    # committed script holds no machine's paths
    plots = ", ".join(f"'shadows.dat' index {i} using 1:2 with points pt {i + 5} ps 1.3 title '{fam}'"
                      for i, fam in enumerate(families))
    with open(os.path.join(out, "shadows.gp"), "w") as f:
        f.write(f"""set terminal pngcairo size 900,600
set output 'shadows.png'
set title 'Soft shadows: render time (x hard shadows) against RMSE to multi:256, per scene and method'
set xlabel 'render time / hard-shadow render time (log)'
set ylabel 'RMSE against multi:256 (log)'
set logscale xy
set key outside right
set grid
plot {plots}
""")


if __name__ == "__main__":
    main()
