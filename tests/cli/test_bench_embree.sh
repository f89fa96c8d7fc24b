#!/bin/sh
# test_bench_embree.sh — the native Embree peer of the trace benchmark
# (tools/bench_embree.c) traces the same scene and rays as `strata bench
# --rays`: its check against strata's own kernel agrees on every sampled ray
# (closest t, or both miss), its hit fractions equal strata's, a short
# final packet is masked right, and the check fails when the side rule
# differs (its two-sided runs hit the back faces strata culls), so it can
# tell.
# Needs Debian's libembree-dev (`make bench-deps`); without it the test is
# skipped, saying so. TAP output.
. tests/tap.sh

BUILD=${BUILD:-build/release}
E=$BUILD/bench_embree
if [ ! -x "$E" ] && [ ! -f /usr/include/embree3/rtcore.h ]; then
    echo "1..0 # SKIP libembree-dev is not installed (make bench-deps): bench_embree not tested"
    exit 0
fi
make --no-print-directory -s "$E" > "$T/make.log" 2>&1 || { cat "$T/make.log" >&2; exit 1; }

"$BUILD/make_icosphere" "$T/ico5" 5 > /dev/null # 20,480 triangles, double-sided
# key K of bench_embree's JSON line in FILE ("rays.hit_fraction", "check.agree1", ...)
field() {
    python3 -c 'import json, sys
v = json.loads(open(sys.argv[1]).read())
for k in sys.argv[2].split("."):
    v = v[k]
print(v)' "$1" "$2"
}
# the rays agree on every sampled ray, with both calls, and hit as often as strata's
same_as_strata() {
    scene=$1 kind=$2 count=$3 name=$4
    "$E" "$scene" "$kind" --count "$count" --check "$count" --json > "$T/e.json" 2> "$T/e.err"
    status=$?
    case $scene in *ico5*) cp "$T/e.json" "$T/e.json.ico" ;; esac
    $S bench "$scene" --rays "$kind" --count "$count" --json > "$T/s.json" 2> /dev/null
    check "$name: exits 0" '[ $status -eq 0 ]' "(status $status: $(cat "$T/e.err"))"
    check "$name: rtcIntersect1 agrees with strata on all $count rays" \
        '[ "$(field "$T/e.json" check.agree1)" = "$count" ]'
    check "$name: rtcIntersect8 agrees with strata on all $count rays" \
        '[ "$(field "$T/e.json" check.agree8)" = "$count" ]'
    check "$name: rtcIntersect16 agrees with strata on all $count rays" \
        '[ "$(field "$T/e.json" check.agree16)" = "$count" ]'
    check "$name: hit fractions equal strata bench's" \
        '[ "$(field "$T/e.json" rays.hit_fraction)" = "$(field "$T/s.json" rays.hit_fraction)" ] &&
         [ "$(field "$T/e.json" rays8.hit_fraction)" = "$(field "$T/s.json" rays.hit_fraction)" ] &&
         [ "$(field "$T/e.json" rays16.hit_fraction)" = "$(field "$T/s.json" rays.hit_fraction)" ]'
}
same_as_strata "$T/ico5.gltf" camera 3000 "icosphere, camera rays"
same_as_strata "$T/ico5.gltf" random 3000 "icosphere, random rays"
same_as_strata cornell-box random 3000 "one-sided Cornell box, random rays"
same_as_strata cornell-box camera 13 "13 camera rays (a last packet of 5, 3 lanes masked; of 16, 13 lanes, 3 masked)"

# without strata's side rule (the two-sided runs) Embree hits the back faces
# strata culls: the check sees it
"$E" cornell-box random --count 3000 --check 3000 --json > "$T/c.json" 2> /dev/null
$S bench cornell-box --rays random --count 3000 --json > "$T/culled.json" 2> /dev/null
check "two-sided: the check finds rays that disagree" \
    '[ "$(field "$T/c.json" two_sided.check.agree1)" -lt 3000 ] &&
     [ "$(field "$T/c.json" two_sided.check.agree8)" -lt 3000 ]'
check "two-sided hits more than strata's culled rule" \
    'python3 -c "import sys; sys.exit(not float(sys.argv[1]) > float(sys.argv[2]))" \
        "$(field "$T/c.json" two_sided.rays.hit_fraction)" "$(field "$T/culled.json" rays.hit_fraction)"'
check "a scene of two-sided triangles alone is measured once" \
    '! grep -q two_sided "$T/e.json.ico"'

expect "an unknown ray set is a usage error" 2 "^bench_embree: error: ray set sideways" \
    "$E" cornell-box sideways
expect "a bad count is a usage error" 2 "^bench_embree: error: --count 0" \
    "$E" cornell-box camera --count 0
expect "a missing scene names the file" 1 "^bench_embree: error: .*$T/none.gltf" \
    "$E" "$T/none.gltf" camera
echo "1..$n"
