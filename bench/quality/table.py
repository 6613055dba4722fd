"""Prints the BENCHMARKS.md quality table from quality_bench's JSON lines.
Usage: table.py RESULTS.jsonl PH_DIR (PH_DIR holds Praun & Hoppe's timings, NAME.eE.json)."""
import json
import os
import sys

rows = [json.loads(line) for line in open(sys.argv[1]) if line.startswith("{")]
ph_dir = sys.argv[2]


def ph_seconds(mesh, label):
    path = os.path.join(ph_dir, f"{mesh}.e{label[-1]}.json")
    try:
        return json.load(open(path)).get("seconds")
    except (OSError, ValueError):
        return None


def fmt(value, spec):
    return "-" if value is None else format(value, spec)


print("| mesh | F | map | time s | sweeps | sweeps, coherent order | stretch L2 | mean abs log area | K | float32 bijective | remesh Hausdorff |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    label = r["label"]
    seconds = r.get("seconds")
    if label.startswith("praun-hoppe"):
        seconds = ph_seconds(r["mesh"], label)
        label = "Praun-Hoppe " + ("fastest" if label.endswith("0") else "default")
    sweeps, coherent = r.get("sweeps"), r.get("sweeps_coherent")
    if sweeps is None and seconds is not None:
        sweeps = seconds / r["csr_sweep_seconds"]
        coherent = seconds / r["csr_coherent_sweep_seconds"]
    print(f"| {r['mesh']} | {r['faces']} | {label} | {fmt(seconds, '.2f')} | {fmt(sweeps, '.0f')} | "
          f"{fmt(coherent, '.0f')} | "
          f"{fmt(r['stretch_l2'], '.3f')} | {fmt(r['area_mean_abs_log'], '.3f')} | "
          f"{fmt(r['dilatation_mean'], '.2f')} | {'yes' if r['float32_bijective'] else 'NO'} | "
          f"{fmt(r.get('remesh_hausdorff'), '.4f')} |")
