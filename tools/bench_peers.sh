#!/bin/sh
# bench_peers.sh — the trace benchmark of strata beside Embree, same rays,
# same scenes: the 327,680-triangle icosphere (`make bench` writes it) and the
# bench Cornell box, camera and random rays, strata and Embree alternating;
# prints one line per renderer with rays/s, the hit fraction (which should
# agree) and the BVH build rate.
# Then the whole pass beside Mitsuba 3 (tools/bench_mitsuba.py): the bench
# Cornell box, 512x512, 64 spp, independent samples, box filter, paths of max
# depth 4 and direct lighting; runs interleaved (strata, Mitsuba, strata, ...),
# medians of samples/s, and whether the two images agree (their means).
# Needs `make strata build/release/bench/icosphere.gltf`, for Embree
# `pip install embreex numpy`, for Mitsuba `make bench-deps`. Run it on an
# idle machine; figures are medians of RUNS runs (default 3). Not a test:
# speed is measured, never asserted.
# Usage: sh tools/bench_peers.sh [COUNT] [RUNS]
COUNT=${1:-2097152}
RUNS=${2:-3}
STRATA=${STRATA:-./strata}
# the peers' Python: make bench-deps's venv where there is one
PY=${PY:-python3}
[ -x build/bench-py/bin/python ] && PY=build/bench-py/bin/python
ICO=build/release/bench/icosphere.gltf
CORNELL=../shared/scenes/bench/cornell.gltf
[ -f "$ICO" ] || make "$ICO" > /dev/null || exit 1
"$PY" -c "import embreex" 2> /dev/null || echo "bench_peers: embreex missing (pip install embreex numpy); strata only"

# One summary line per renderer (strata, or Embree by its "device") from the
# JSON lines on stdin: medians of rays/s and of the BVH build rate.
summarise() {
    python3 -c '
import json, statistics, sys
runs = {}
for line in sys.stdin:
    if line.startswith("{"):
        r = json.loads(line)
        runs.setdefault("embree" if r["device"].startswith("embree") else "strata", []).append(r)
for name, rs in runs.items():
    rps = statistics.median(r["rays"]["rays_per_second"] for r in rs)
    tps = statistics.median(r["bvh"]["triangles_per_second"] for r in rs)
    r = rs[0]
    print("%-8s %-40s %-6s %8.3f M rays/s  hit %.6f  bvh %7.3f M tris/s  (%d tris, %d runs)" % (
        name, r["scene"][-40:], r["rays"]["kind"], rps * 1e-6, r["rays"]["hit_fraction"],
        tps * 1e-6, r["bvh"]["triangles"], len(rs)))'
}

# RUNS runs of strata's trace benchmark and Embree's, alternating.
trace_pair() {
    scene=$1 kind=$2 i=0
    while [ $i -lt "$RUNS" ]; do
        "$STRATA" bench "$scene" --rays "$kind" --count "$COUNT" --json 2> /dev/null || return 1
        if "$PY" -c "import embreex" 2> /dev/null; then
            "$PY" tools/bench_embree.py "$scene" "$kind" "$COUNT" || return 1
        fi
        i=$((i + 1))
    done | summarise
}

for scene in "$ICO" "$CORNELL"; do
    [ -f "$scene" ] || { echo "bench_peers: $scene not found, skipped"; continue; }
    for kind in camera random; do
        trace_pair "$scene" "$kind"
    done
done

# The whole pass: strata bench's total against bench_mitsuba.py, interleaved.
has_mitsuba() { "$PY" -c "import mitsuba" 2> /dev/null; }
whole_pass() {
    integrator=$1
    shift
    out=$(mktemp -d) || return 1
    i=0
    while [ $i -lt "$RUNS" ]; do
        "$STRATA" bench "$CORNELL" --width 512 --height 512 --spp 64 --sampler random \
            --filter box --integrator "$integrator" "$@" --json >> "$out/strata" || return 1
        RUNS=1 "$PY" tools/bench_mitsuba.py render "$CORNELL" "$integrator" "$out/mitsuba.exr" \
            >> "$out/mitsuba" || return 1
        i=$((i + 1))
    done
    "$STRATA" render "$CORNELL" --width 512 --height 512 --spp 64 --sampler random --filter box \
        --integrator "$integrator" "$@" -o "$out/strata.exr" 2> /dev/null || return 1
    python3 -c '
import json, statistics, sys
s = [json.loads(l)["total"]["samples_per_second"] for l in open(sys.argv[1]) if l.startswith("{")]
m = [json.loads(l) for l in open(sys.argv[2])]
ms = statistics.median(r["samples_per_second"] for r in m)
ss = statistics.median(s)
print("whole pass %-6s strata %6.3f M samples/s  %s (%s) %6.3f M samples/s  strata/mitsuba %.2fx  (%d runs)" % (
    sys.argv[3], ss * 1e-6, m[0]["renderer"], m[0]["variant"], ms * 1e-6, ss / ms, len(s)))' \
        "$out/strata" "$out/mitsuba" "$integrator"
    "$PY" tools/bench_mitsuba.py compare "$out/strata.exr" "$out/mitsuba.exr"
    status=$?
    rm -rf "$out"
    return $status
}

if [ ! -f "$CORNELL" ]; then
    echo "bench_peers: $CORNELL not found, whole pass skipped"
elif ! has_mitsuba; then
    echo "bench_peers: mitsuba missing (make bench-deps); whole pass skipped"
else
    whole_pass path --max-depth 4
    whole_pass direct
fi
