#!/usr/bin/env bash
# Reach benchmark: maps every file of MANIFEST.tsv in SETDIR (see assemble.sh) with the
# default preparation (--prepare parts) and again with --prepare repair (the old default:
# one part only), each as `timeout 120 SPHEREMAP map FILE -o OUT.glb --metrics OUT.json
# --time-limit 30 --quiet --threads 1`, JOBS (default 2) files at a time. Classifies each run:
#   all-parts-mapped  exit 0, no part left out      some-parts-mapped  exit 0, parts left out
#   refused           exit 2 (the failed check)     not-certified      exit 3 (map/time limit)
#   unreadable        exit 2 with a read check      crash/timeout      anything else (a bug)
# Writes SETDIR/results.tsv (one line per file; its last column the --prepare run's peak
# memory in MB, by /usr/bin/time) and prints the summary per kind, then the crashes/timeouts
# and not-certified files, the slowest and largest runs, then the per-file lines.
# PREPARE (default parts) and COMPARE (default repair) name the two --prepare methods;
# COMPARE=none runs each file once (a sweep of a new set: half the machine time).
# Usage: [PREPARE=auto COMPARE=parts|none] bench/reach/run.sh SPHEREMAP SETDIR
set -euo pipefail
spheremap=$(realpath "$1")
setdir=$(realpath "$2")
python3 - "$spheremap" "$setdir" << 'EOF'
import collections, concurrent.futures, csv, json, os, re, subprocess, sys, tempfile, time
spheremap, setdir = sys.argv[1:3]
prepare, compare = os.environ.get("PREPARE", "parts"), os.environ.get("COMPARE", "repair")
read_checks = {"io", "parse", "gltf", "missing_resources"}  # the reader could not read it

def run(path, prepare):
    """One map run: a dict of exit, seconds, class, check, parts, message."""
    if prepare == "none":
        return {"exit": "", "class": "", "check": ""}
    with tempfile.TemporaryDirectory() as tmp:
        # /usr/bin/time: the run's peak resident memory (through timeout: its waited child).
        cmd = ["/usr/bin/time", "-f", "%M", "-o", f"{tmp}/rss",
               "timeout", "120", spheremap, "map", path, "-o", f"{tmp}/out.glb",
               "--metrics", f"{tmp}/out.json", "--time-limit", "30", "--quiet",
               "--threads", "1", "--prepare", prepare]
        start = time.monotonic()
        p = subprocess.run(cmd, capture_output=True, text=True, errors="replace")
        r = {"exit": p.returncode, "seconds": round(time.monotonic() - start, 2),
             "check": "", "bijective": "", "mapped": "", "left_out": "", "left_checks": "",
             "decided": "", "wrapped": "", "method": "",
             "message": " ".join(p.stderr.split())[:300], "peak_mb": ""}
        try:  # the last line: "Command exited with non-zero status N" may come first
            r["peak_mb"] = round(int(open(f"{tmp}/rss").read().split()[-1]) / 1024, 1)
        except (OSError, ValueError, IndexError):
            pass
        try:
            m = json.load(open(f"{tmp}/out.json"))
            r["bijective"] = m.get("bijective", "")
            r["mapped"] = m.get("parts_mapped", "")
            r["left_out"] = m.get("parts_left_out", "")
            # prepare=auto: what it took, and how many parts it wrapped.
            r["decided"] = m.get("preparation", {}).get("decided", "")
            r["method"] = m.get("preparation", {}).get("method", "")
            r["wrapped"] = sum(1 for q in m.get("parts") or [] if q.get("wrapped")) or ""
            checks = collections.Counter(q.get("check", "?") for q in m.get("parts") or []
                                         if not q.get("mapped", True))
            r["left_checks"] = ",".join(f"{c}x{n}" for c, n in sorted(checks.items()))
            if p.returncode == 3:  # why it is not certified: the stop reason, or the problem
                stop = m.get("stop_reason", "")
                r["check"] = stop if stop != "bijective" else m.get("problem", {}).get("type", "")
        except (OSError, ValueError):
            pass
    refusal = re.search(r"invalid input \[([^\]]+)\]", p.stderr)
    if p.returncode == 0:
        r["class"] = "some-parts-mapped" if r["left_out"] else "all-parts-mapped"
    elif p.returncode == 2 and refusal:
        r["check"] = refusal.group(1)
        r["class"] = "unreadable" if r["check"] in read_checks else "refused"
    elif p.returncode == 3:
        r["class"] = "not-certified"
    else:  # 124 = timeout, negative = signal, 1/4/2 without a check: all bugs here
        r["class"] = "crash/timeout"
    return r

rows = list(csv.DictReader(open(f"{setdir}/MANIFEST.tsv"), delimiter="\t"))
def both(row):
    path = f"{setdir}/{row['kind']}/{row['source']}/{row['path']}"
    return row, run(path, prepare), run(path, compare)
results = []
with concurrent.futures.ThreadPoolExecutor(int(os.environ.get("JOBS", "2"))) as pool:  # 1 thread each
    for i, res in enumerate(pool.map(both, rows), 1):
        results.append(res)
        print(f"[{i}/{len(rows)}] {res[1]['class']:18} {res[0]['path']}", file=sys.stderr, flush=True)

fields = ["exit", "seconds", "class", "check", "bijective", "mapped", "left_out", "left_checks",
          "method", "decided", "wrapped"]
lines = ["\t".join(["kind", "source", "path", "bytes", *fields, "repair_exit", "repair_class",
                    "repair_check", "message", "peak_mb"])]
for row, p, r in results:
    lines.append("\t".join(str(x) for x in [row["kind"], row["source"], row["path"], row["bytes"],
                 *(p[f] for f in fields), r["exit"], r["class"], r["check"],
                 p["message"] if p["class"] not in ("all-parts-mapped", "some-parts-mapped") else "",
                 p["peak_mb"]]))
open(f"{setdir}/results.tsv", "w").write("\n".join(lines) + "\n")

def pct(n, d): return f"{n} ({100 * n / d:.0f}%)" if d else "0"
groups = collections.defaultdict(list)
for res in results:
    groups[res[0]["kind"]].append(res)
    groups["ALL"].append(res)
version = subprocess.run([spheremap, "--version"], capture_output=True, text=True).stdout.strip()
digest = subprocess.run(["sha256sum", spheremap], capture_output=True, text=True).stdout.split()[0]
print(f"binary: {spheremap} ({version}; sha256 {digest[:16]}); {len(rows)} files of {setdir}\n")
print(f"== Summary (--prepare {prepare}; last column: the same share under --prepare {compare})")
print(f"{'kind':32} {'files':>5} {'all parts':>10} {'some':>5} {'refused':>7} {'not cert':>8} "
      f"{'unread':>6} {'crash/to':>8} {compare + ': all':>11}")
for kind in sorted(groups, key=lambda k: (k == "ALL", k)):
    g = groups[kind]
    n = collections.Counter(p["class"] for _, p, _ in g)
    rep = sum(r["class"] == "all-parts-mapped" for _, _, r in g)
    print(f"{kind:32} {len(g):>5} {pct(n['all-parts-mapped'], len(g)):>10} "
          f"{n['some-parts-mapped']:>5} {n['refused']:>7} {n['not-certified']:>8} "
          f"{n['unreadable']:>6} {n['crash/timeout']:>8} {pct(rep, len(g)):>11}")
for kind in sorted(groups, key=lambda k: (k == "ALL", k)):
    ref = collections.Counter(p["check"] for _, p, _ in groups[kind] if p["class"] == "refused")
    left = collections.Counter()
    for _, p, _ in groups[kind]:
        for c in filter(None, p["left_checks"].split(",")):
            name, k = c.rsplit("x", 1)
            left[name] += int(k)
    decided = collections.Counter(p["decided"] for _, p, _ in groups[kind] if p["decided"])
    print(f"-- {kind}: refusals {dict(ref.most_common()) or '-'}; parts left out by check {dict(left.most_common()) or '-'}"
          + (f"; decided {dict(decided.most_common())}" if decided else ""))
gain = collections.Counter(p["class"] for _, p, r in results
                           if r["class"] != "all-parts-mapped" and p["class"].endswith("mapped"))
print(f"-- gain over --prepare {compare}: {dict(gain)} (files not mapped under {compare}, now mapped)")
print("\n== Crashes / timeouts (bugs)")
for row, p, r in results:
    for mode, x in ((prepare, p), (compare, r)):
        if x["class"] == "crash/timeout":
            print(f"{mode:6} exit {x['exit']} {x['seconds']}s {row['source']}/{row['path']}: {x['message']}")
print("\n== Not certified (exit 3), unreadable")
for row, p, r in results:
    if p["class"] in ("not-certified", "unreadable"):
        print(f"{p['class']} {p['check']} {p['seconds']}s {row['source']}/{row['path']}: {p['message']}")
print("\n== Slowest and largest (--prepare %s): over 10 s or 500 MB, else the top 5" % prepare)
def top(key, bar):
    ranked = sorted((res for res in results if res[1].get(key) not in ("", None)),
                    key=lambda res: -float(res[1][key]))
    return [res for res in ranked if float(res[1][key]) > bar] or ranked[:5]
for key, bar, unit in (("seconds", 10, "s"), ("peak_mb", 500, "MB")):
    print(f"{key}: " + "; ".join(f"{res[1][key]} {unit} {res[0]['source']}/{res[0]['path']}"
                                for res in top(key, bar)))
print("\n== Per file (also in SETDIR/results.tsv)")
print("\n".join(lines))
EOF
