#!/usr/bin/env bash
# Speed at scale (issue 30): per mesh, meshopt_simplify's time on the same mesh in the same
# run (speed_bench: min of 5, one thread, spatially sorted, down to 4 triangles), our
# hierarchy's, and the whole CLI process (`spheremap map MESH -o OUT.glb`, read to output
# written, default threads) at --quality fast and standard, each the min of ROUNDS runs
# (default 3) taken interleaved, with the stage seconds of the fastest run. Prints one
# table row per mesh with every time also as a multiple of meshopt_simplify's, then the
# spread (max/min over the rounds).
#
# With HUGE=MESH (igea), also the 17.2M-triangle run: MESH subdivided 1-to-4 three times
# (speed_bench --subdivide), mapped once at standard: wall seconds, peak RSS and bytes per
# triangle, certified or not. Needs about 5 GB of memory and several minutes.
#
# Usage: bench/speed/run.sh BUILD_DIR MESH...     (BUILD_DIR holds cli/spheremap and
#        bench/speed_bench; e.g. build, configured with the default SPHEREMAP_BUILD_BENCH)
#   ROUNDS=5 HUGE=../shared/meshes/igea.obj bench/speed/run.sh build ../shared/meshes/{horse,armadillo,scorpion,igea}.obj
# Measure on an idle machine: the ratios move a lot under load.
set -euo pipefail
build=$(realpath "$1")
shift
python3 - "$build" "${ROUNDS:-3}" "${HUGE:-}" "$@" << 'EOF'
import json, os, subprocess, sys, tempfile, time
build, rounds, huge, meshes = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4:]
spheremap = f"{build}/cli/spheremap"
speed_bench = f"{build}/bench/speed_bench"

def run_map(mesh, quality, tmp, must_succeed=True):
    """One whole CLI run: (wall seconds, peak RSS bytes, metrics)."""
    cmd = [spheremap, "map", mesh, "-o", f"{tmp}/out.glb", "--metrics", f"{tmp}/m.json",
           "--quality", quality, "--quiet"]
    start = time.monotonic()
    child = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.monotonic() - start
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0 and must_succeed:
        sys.exit(f"{' '.join(cmd)}: exit {child.returncode}: {child.stderr.read().decode()[:400]}")
    try:
        metrics = json.load(open(f"{tmp}/m.json"))
    except (OSError, ValueError):
        metrics = {"exit": child.returncode}
    return wall, usage.ru_maxrss * 1024, metrics

print(f"# bench/speed/run.sh, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
      f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}, rounds {rounds}")
print("| mesh | triangles | meshopt_simplify | hierarchy | fast total | standard total "
      "| standard: prepare / hierarchy / optimize / verify / metrics (s) | spread |")
print("|---|---|---|---|---|---|---|---|")
with tempfile.TemporaryDirectory() as tmp:
    for mesh in meshes:
        row = json.loads(subprocess.run([speed_bench, mesh], check=True, capture_output=True,
                                        text=True).stdout.splitlines()[-1])
        base = row["meshopt_seconds"]
        walls = {"fast": [], "standard": []}
        stages = {}
        for _ in range(rounds):  # interleaved, so a load spike hits both alike
            for quality in walls:
                wall, _, metrics = run_map(mesh, quality, tmp)
                if not metrics.get("bijective"):
                    sys.exit(f"{mesh} at {quality}: not certified")
                if quality == "standard" and (not walls[quality] or wall < min(walls[quality])):
                    stages = metrics.get("seconds", {})
                walls[quality].append(wall)
        ratio = lambda s: f"{s:.2f} s ({s / base:.1f}x)"
        spread = " / ".join(f"{max(w) / min(w):.2f}" for w in walls.values())
        stage_text = " / ".join(f"{stages.get(k, 0):.2f}" for k in
                                ("prepare", "hierarchy", "optimize", "verify", "metrics"))
        print(f"| {row['mesh']} | {row['triangles']:,} | {base * 1000:.0f} ms "
              f"| {ratio(row['hierarchy_seconds'])} | {ratio(min(walls['fast']))} "
              f"| {ratio(min(walls['standard']))} | {stage_text} | {spread} |", flush=True)

    if huge:
        big = f"{tmp}/huge.ply"
        print(subprocess.run([speed_bench, "--subdivide", "3", huge, big], check=True,
                             capture_output=True, text=True).stdout.strip())
        triangles = int(open(big, "rb").read(300).split(b"element face ")[1].split(b"\n")[0])
        wall, rss, metrics = run_map(big, "standard", tmp, must_succeed=False)
        print(f"huge: {triangles:,} triangles, standard: {wall:.0f} s, peak RSS "
              f"{rss / 2**30:.2f} GiB ({rss / triangles:.0f} B/triangle), "
              f"bijective {metrics.get('bijective')}, stages {json.dumps(metrics.get('seconds'))}")
EOF
