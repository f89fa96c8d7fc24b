#!/bin/sh
# kernel_isa.sh — what PoCL made of each kernel: per kernel that a render
# ran, the float arithmetic in its compiled .so counted by register width,
# packed on zmm (AVX-512), ymm (AVX) or xmm (4 lanes, or a float3's
# arithmetic) registers, and scalar; and its stack traffic, vector
# registers spilled to the stack and read back apart. A stage in lanes
# carries its work in the packed wide columns; one item per work-item that
# PoCL could not widen shows in the scalar one; lanes that do not fit the
# registers show as spills (compare --lanes 8 and --lanes 16). Not a test:
# it prints figures.
#
#   sh tools/kernel_isa.sh [STRATA_BENCH_ARGS...]
#
# runs `strata bench` with the arguments given (default: the built-in
# Cornell box, direct lighting, at 128x128) into a fresh PoCL cache, then
# disassembles every kernel's .so there with objdump. Counts are of
# instructions in the code, not of instructions run (callgrind counts those).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
strata=${STRATA:-$root/build/release/strata}
cache=$(mktemp -d)
trap 'rm -rf "$cache"' EXIT
[ $# -gt 0 ] || set -- --width 128 --height 128 --spp 4 --sampler random --filter box \
    --integrator direct
POCL_CACHE_DIR=$cache "$strata" bench "$@" > "$cache/bench.txt"
grep '^kernels *lanes' "$cache/bench.txt"

# Float arithmetic: adds, multiplies, fused multiply-adds, divides, roots,
# min/max and compares, in their packed (ps) and scalar (ss) forms, by the
# register they work on: zmm (AVX-512, 16 lanes), ymm (AVX, 8), xmm (4 lanes
# or a float3). Then the stack traffic: vector registers stored to and
# loaded from the stack (spills: a stage whose lanes do not fit the
# registers), other stack accesses, and gathers.
ops='(add|sub|mul|div|sqrt|rsqrt|rcp|min|max|cmp[a-z]*|f[n]?m(add|sub)[0-9]+)'
printf '%-26s %7s %7s %7s %7s %9s %9s %7s\n' kernel zmm ymm xmm scalar 'spill-vec' 'stack' gather
find "$cache" -name '*.so' | sort | while read -r so; do
    k=$(basename "$so" .so)
    # one launch shape per kernel is enough (PoCL builds one per grid shape)
    [ -e "$cache/seen.$k" ] && continue
    : > "$cache/seen.$k"
    objdump -d --no-show-raw-insn "$so" | awk -v ops="$ops" -v k="$k" '
        $2 ~ "^v?" ops "ps$" { if ($0 ~ /zmm/) z++; else if ($0 ~ /ymm/) y++; else x++ }
        $2 ~ "^v?" ops "ss$" || $2 ~ /^v?u?comiss$/ { scalar++ }
        /\((%rsp|%rbp)[,)]/ { if ($0 ~ /[xyz]mm/) sv++; else so++ }
        /gather/ { g++ }
        END { printf "%-26s %7d %7d %7d %7d %9d %9d %7d\n", k, z, y, x, scalar, sv, so, g }'
done
