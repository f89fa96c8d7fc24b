#!/bin/sh
# bench_peers.sh — strata beside its peers, like for like. Not a test: speed
# is measured, never asserted.
#
# The trace: `strata bench SCENE --rays camera|random` beside native Embree 3
# (build/release/bench_embree, tools/bench_embree.c: the same triangles, read
# by strata's importer, the same rays, from strata's own generator, strata's
# one-sided culling as an intersection filter, rtcIntersect1 and
# rtcIntersect8 and rtcIntersect16 on two threads; where the scene has one-sided triangles, also
# Embree without the filter, faster but not strata's hits), on the
# 327,680-triangle icosphere (`make bench` writes it) and the bench Cornell
# box, runs alternating (strata, Embree, strata, ...). Per scene and ray set:
# medians of rays/s of strata, of rtcIntersect1, 8 and 16, the
# hit fractions (equal when the rays and the scene are the same), how many
# of bench_embree's sampled rays agree with strata's own kernel, and strata
# against the best Embree median among the runs that agree on every sampled
# ray (the filterless runs count where the rays never meet a back face, as
# camera rays in the Cornell box); and the BVH build rates.
#
# The whole pass: strata bench's total beside Mitsuba 3
# (tools/bench_mitsuba.py, its like-for-like settings: 512x512, 64 spp,
# independent samples, box filter; paths of max depth 4, Mitsuba's 5, and
# direct lighting), runs interleaved, medians of samples/s, and whether the
# two images agree (their means and block means). On the bench Cornell box,
# then on a large scene where traversal dominates: the icosphere standing
# inside the Cornell box (tools/make_cornell_sphere.py writes it into build/).
#
# Needs `make strata`; `make bench-deps` for the peers (Debian's
# libembree-dev and libllvm19, Mitsuba in build/bench-py); a peer that is
# missing is skipped with a note. Run it on an idle machine; figures are
# medians of RUNS runs (default 3).
# Usage: sh tools/bench_peers.sh [COUNT] [RUNS] [trace|whole]   (default: both parts)
COUNT=${1:-2097152}
RUNS=${2:-3}
PARTS=${3:-trace whole}
STRATA=${STRATA:-./strata}
BUILD=${BUILD:-build/release}
EMBREE=${EMBREE:-$BUILD/bench_embree}
# the peers' Python: make bench-deps's venv where there is one
PY=${PY:-python3}
[ -x build/bench-py/bin/python ] && PY=build/bench-py/bin/python
ICO=$BUILD/bench/icosphere.gltf
CORNELL=build/scenes/cornell-bench.gltf
LARGE=$BUILD/bench/cornell_sphere.gltf
[ -f "$ICO" ] || make "$ICO" > /dev/null || exit 1
[ -f "$CORNELL" ] || make "$CORNELL" > /dev/null || exit 1

has_embree() { [ -f /usr/include/embree3/rtcore.h ]; }
if has_embree; then
    make --no-print-directory -s "$EMBREE" > /dev/null || exit 1
else
    echo "bench_peers: libembree-dev missing (make bench-deps); strata's trace alone"
fi

# One summary per scene and ray set from the JSON lines on stdin (strata's
# and bench_embree's, told apart by bench_embree's "rays8").
summarise() {
    python3 -c '
import json, statistics, sys
s, e = [], []
for line in sys.stdin:
    if line.startswith("{"):
        r = json.loads(line)
        (e if "rays8" in r else s).append(r)
med = lambda rs, f: statistics.median(f(r) for r in rs)
rps = lambda key: lambda r: r[key]["rays_per_second"]
tps = lambda r: r["bvh"]["triangles_per_second"]
r = s[0]
print("%s, %s rays (%d tris, %d runs of %d rays)" % (
    r["scene"], r["rays"]["kind"], r["bvh"]["triangles"], len(s), r["rays"]["count"]))
st, sb = med(s, rps("rays")), med(s, tps)
print("  strata                %8.3f M rays/s  hit %.6f  bvh %7.3f M tris/s%s" % (
    st * 1e-6, r["rays"]["hit_fraction"], sb * 1e-6,
    "  (sorted by ray first, sort counted)" if r["rays"].get("sorted") else ""))
if e:
    calls = (("1", "rays", "agree1"), ("8", "rays8", "agree8"), ("16", "rays16", "agree16"))
    eb, x, n = med(e, tps), e[0], e[0]["check"]["rays"]
    agree = lambda rs, k: min(y["check"][k] for y in rs)
    # the best Embree call whose hits agree with strata on every checked ray
    rate = {w: med(e, rps(key)) for w, key, _ in calls}
    best = max([rate[w] for w, _, k in calls if agree(e, k) == n] or [0])
    for w, key, _ in calls:
        print("  embree rtcIntersect%-2s %8.3f M rays/s  hit %.6f%s" % (
            w, rate[w] * 1e-6, x[key]["hit_fraction"],
            "  bvh %7.3f M tris/s  (%s)" % (eb * 1e-6, x["device"]) if w == "1" else
            "  (emulated: no native 16-wide build)" if w == "16" and not x.get("native16") else ""))
    print("  check: %s of the sampled rays agree with strata" % ", ".join(
        "%d/%d (%s)" % (agree(e, k), n, w) for w, _, k in calls))
    if "two_sided" in x:
        two = [y["two_sided"] for y in e]
        rate2 = {w: med(two, rps(key)) for w, key, _ in calls}
        same = min(agree(two, k) for _, _, k in calls) == n
        print("  embree without the culling filter: %s M rays/s  hit %.6f  check %s%s" % (
            "  ".join("%s: %.3f" % (w, rate2[w] * 1e-6) for w, _, _ in calls),
            two[0]["rays"]["hit_fraction"],
            " ".join("%d/%d (%s)" % (agree(two, k), n, w) for w, _, k in calls),
            "" if same else ": other hits, not compared"))
        best = max([best] + [rate2[w] for w, _, k in calls if agree(two, k) == n])
    if best:
        print("  strata / best embree with the same hits %.2fx  (bvh %.2fx)" % (st / best, sb / eb))
    else:
        print("  no Embree run agreed with strata on every checked ray: not compared")'
}

# RUNS runs of strata's trace benchmark and Embree's, alternating.
trace_pair() {
    scene=$1 kind=$2 i=0
    while [ $i -lt "$RUNS" ]; do
        "$STRATA" bench "$scene" --rays "$kind" --count "$COUNT" --json 2> /dev/null || return 1
        if has_embree; then
            "$EMBREE" "$scene" "$kind" --count "$COUNT" --json || return 1
        fi
        i=$((i + 1))
    done | summarise
}

trace_part() {
    for scene in "$ICO" "$CORNELL"; do
        [ -f "$scene" ] || { echo "bench_peers: $scene not found, skipped"; continue; }
        for kind in camera random; do
            trace_pair "$scene" "$kind" || return 1
        done
    done
}

# The whole pass of one scene: strata bench's total against bench_mitsuba.py,
# interleaved, then whether one image of each agrees.
whole_pass() {
    scene=$1 integrator=$2
    shift 2
    out=$(mktemp -d) || return 1
    i=0
    while [ $i -lt "$RUNS" ]; do
        "$STRATA" bench "$scene" --width 512 --height 512 --spp 64 --sampler random \
            --filter box --integrator "$integrator" "$@" --json 2> /dev/null >> "$out/strata" ||
            { rm -rf "$out"; return 1; }
        RUNS=1 "$PY" tools/bench_mitsuba.py render "$scene" "$integrator" "$out/mitsuba.exr" \
            >> "$out/mitsuba" || { rm -rf "$out"; return 1; }
        i=$((i + 1))
    done
    "$STRATA" render "$scene" --width 512 --height 512 --spp 64 --sampler random --filter box \
        --integrator "$integrator" "$@" -o "$out/strata.exr" > /dev/null 2>&1 || { rm -rf "$out"; return 1; }
    python3 -c '
import json, statistics, sys
s = [json.loads(l)["total"]["samples_per_second"] for l in open(sys.argv[1]) if l.startswith("{")]
m = [json.loads(l) for l in open(sys.argv[2])]
ms = statistics.median(r["samples_per_second"] for r in m)
ss = statistics.median(s)
print("whole pass %s %-6s strata %6.3f M samples/s  %s (%s) %6.3f M samples/s  strata/mitsuba %.2fx  (%d runs)" % (
    sys.argv[4], sys.argv[3], ss * 1e-6, m[0]["renderer"], m[0]["variant"], ms * 1e-6, ss / ms, len(s)))' \
        "$out/strata" "$out/mitsuba" "$integrator" "$(basename "$scene")"
    "$PY" tools/bench_mitsuba.py compare "$out/strata.exr" "$out/mitsuba.exr"
    status=$?
    rm -rf "$out"
    return $status
}

whole_part() {
    if ! "$PY" -c "import mitsuba" 2> /dev/null; then
        echo "bench_peers: mitsuba missing (make bench-deps); whole pass skipped"
        return 0
    fi
    [ -f "$LARGE" ] || python3 tools/make_cornell_sphere.py "$CORNELL" "$ICO" "$LARGE" || return 1
    status=0
    for scene in "$CORNELL" "$LARGE"; do
        whole_pass "$scene" path --max-depth 4 || status=1
        whole_pass "$scene" direct || status=1
    done
    return $status
}

status=0
for part in $PARTS; do
    case $part in
    trace) trace_part || status=1 ;;
    whole) whole_part || status=1 ;;
    *) echo "bench_peers: part $part: expected trace or whole" >&2; exit 2 ;;
    esac
done
exit $status
