#!/bin/sh
# bench_peers.sh — the trace benchmark of strata beside Embree, same rays,
# same scenes: the 327,680-triangle icosphere (`make bench` writes it) and the
# bench Cornell box, camera and random rays; prints one line per run with
# rays/s, the hit fraction (which should agree) and the BVH build rate.
# Needs `make strata build/release/bench/icosphere.gltf` and, for Embree,
# `pip install embreex numpy`. Run it on an idle machine; figures are medians
# of RUNS runs (default 3). Not a test: speed is measured, never asserted.
# Usage: sh tools/bench_peers.sh [COUNT] [RUNS]
COUNT=${1:-2097152}
RUNS=${2:-3}
STRATA=${STRATA:-./strata}
ICO=build/release/bench/icosphere.gltf
CORNELL=../shared/scenes/bench/cornell.gltf
[ -f "$ICO" ] || make "$ICO" > /dev/null || exit 1
python3 -c "import embreex" 2> /dev/null || echo "bench_peers: embreex missing (pip install embreex numpy); strata only"

# Median of RUNS runs of a command printing strata's JSON; one summary line.
median_of() {
    name=$1
    shift
    i=0
    while [ $i -lt "$RUNS" ]; do "$@" || return 1; i=$((i + 1)); done | python3 -c '
import json, statistics, sys
runs = [json.loads(l) for l in sys.stdin if l.startswith("{")]
rps = statistics.median(r["rays"]["rays_per_second"] for r in runs)
tps = statistics.median(r["bvh"]["triangles_per_second"] for r in runs)
r = runs[0]
print("%-8s %-40s %-6s %8.3f M rays/s  hit %.6f  bvh %7.3f M tris/s  (%d tris, %d runs)" % (
    sys.argv[1], r["scene"][-40:], r["rays"]["kind"], rps * 1e-6, r["rays"]["hit_fraction"],
    tps * 1e-6, r["bvh"]["triangles"], len(runs)))' "$name"
}

for scene in "$ICO" "$CORNELL"; do
    [ -f "$scene" ] || { echo "bench_peers: $scene not found, skipped"; continue; }
    for kind in camera random; do
        median_of strata "$STRATA" bench "$scene" --rays "$kind" --count "$COUNT" --json
        if python3 -c "import embreex" 2> /dev/null; then
            median_of embree python3 tools/bench_embree.py "$scene" "$kind" "$COUNT"
        fi
    done
done
