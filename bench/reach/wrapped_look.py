#!/usr/bin/env python3
"""The remesh of wrapped assets against their ORIGINAL (issue 29, items 4 and 5).

For each file: `spheremap remesh FILE -o OUT.glb --resolution N --metrics M.json`
(prepare auto, the default; one thread) and, from M.json's remesh metrics, the distance
to the original relative to the whole input's bounding-box diagonal (asset_hausdorff and
asset_rms for parts+wrap, hausdorff and rms for a whole wrap), the envelope's own distance,
and the time the colour bake and the distance took. Prints one line per file and a summary.
Usage: bench/reach/wrapped_look.py SPHEREMAP SETDIR [N] < list of paths under SETDIR
"""
import json, statistics, subprocess, sys, tempfile, time

spheremap, setdir = sys.argv[1:3]
resolution = sys.argv[3] if len(sys.argv) > 3 else "128"
rows = []
for path in [line.strip() for line in sys.stdin if line.strip()]:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = ["timeout", "300", spheremap, "remesh", f"{setdir}/{path}", "-o", f"{tmp}/out.glb",
               "--resolution", resolution, "--metrics", f"{tmp}/m.json", "--threads", "1",
               "--quiet"]
        start = time.monotonic()
        p = subprocess.run(cmd, capture_output=True, text=True, errors="replace")
        wall = time.monotonic() - start
        if p.returncode != 0:
            print(f"FAIL {p.returncode} {path}: {' '.join(p.stderr.split())[:200]}")
            continue
        m = json.load(open(f"{tmp}/m.json"))
    r = m["remesh"]
    prep = m["map"].get("preparation", {})
    decided = prep.get("decided", "")
    d = r.get("distance_to_original")
    if d is None:
        print(f"NOT WRAPPED ({decided}) {path}")
        continue
    # Also: the remesh -> original direction alone (what one sees: the original's faces
    # inside the envelope's solid only count the other way), and the envelope's own
    # two-sided Hausdorff to the original (metrics.map), all over the asset's diagonal.
    if "asset_hausdorff" in d:  # parts+wrap
        h, rms, diag = d["asset_hausdorff"], d["asset_rms"], d["asset_diagonal"]
        seen = max(q["distance_to_original"]["output_to_original"]["max"] *
                   q["distance_to_original"]["diagonal"] / diag
                   for q in r["parts"] if "distance_to_original" in q)
        envelope = max(q["wrapped"]["envelope_hausdorff"] for q in m["map"]["parts"]
                       if "wrapped" in q)
    else:
        h, rms = d["hausdorff"], d["rms"]
        seen = d["output_to_original"]["max"]
        envelope = prep.get("envelope_hausdorff", float("nan"))
    s = r.get("seconds", {})
    decoded = sum(q.get("texture", {}).get("images_decoded", 0) for q in r.get("parts", [r]))
    look = r.get("original_look")
    if look is None:  # parts: per wrapped part
        looks = {q.get("original_look", "") for q in r.get("parts", []) if "original_look" in q}
        look = "baked" if any(x.startswith("baked") for x in looks) else "none"
    rows.append((path, decided, h, rms, s.get("bake", 0.0), s.get("distance_to_original", 0.0),
                 s.get("total", 0.0), wall, seen, envelope))
    print(f"{decided:10s} hausdorff {h:.4f} rms {rms:.4f} remesh->original {seen:.4f} "
          f"envelope's own hausdorff {envelope:.4f} bake {s.get('bake', 0):.2f} s "
          f"distance {s.get('distance_to_original', 0):.2f} s remesh {s.get('total', 0):.2f} s "
          f"wall {wall:.1f} s look {look[:5]} images {decoded} {path}", flush=True)
if rows:
    hs = [r[2] for r in rows]
    rs = [r[3] for r in rows]
    print(f"\n{len(rows)} wrapped files at N = {resolution}: hausdorff to the original median "
          f"{statistics.median(hs):.4f} max {max(hs):.4f}; rms median {statistics.median(rs):.4f} "
          f"max {max(rs):.4f}; within 0.02 of the diagonal: {sum(h <= 0.02 for h in hs)}/{len(hs)}")
    ss = [r[8] for r in rows]
    es = [r[9] for r in rows]
    print(f"remesh -> original alone: median {statistics.median(ss):.4f} max {max(ss):.4f}, "
          f"within 0.02: {sum(x <= 0.02 for x in ss)}/{len(ss)}; the envelope's own Hausdorff: "
          f"median {statistics.median(es):.4f} max {max(es):.4f}; remesh Hausdorff at most the "
          f"envelope's + 0.01: {sum(r[2] <= r[9] + 0.01 for r in rows)}/{len(rows)}")
    print(f"bake: median {statistics.median([r[4] for r in rows]):.2f} s, max "
          f"{max(r[4] for r in rows):.2f} s; distance to original: median "
          f"{statistics.median([r[5] for r in rows]):.2f} s; remesh total median "
          f"{statistics.median([r[6] for r in rows]):.2f} s")
