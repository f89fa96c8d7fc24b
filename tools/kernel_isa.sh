#!/bin/sh
# kernel_isa.sh — what PoCL made of each kernel: per kernel that a render
# ran, the float arithmetic in its compiled .so counted by register width,
# packed on ymm (AVX) or zmm (AVX-512) registers, packed on xmm (4 lanes, or
# a float3's arithmetic), and scalar. A stage in lanes carries its work in
# the packed wide column; one item per work-item that PoCL could not widen
# shows in the scalar one. Not a test: it prints figures.
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
# min/max and compares, in their packed (ps) and scalar (ss) forms.
ops='(add|sub|mul|div|sqrt|rsqrt|rcp|min|max|cmp[a-z]*|f[n]?m(add|sub)[0-9]+)'
printf '%-26s %8s %8s %8s\n' kernel 'wide' 'xmm' 'scalar'
find "$cache" -name '*.so' | sort | while read -r so; do
    k=$(basename "$so" .so)
    # one launch shape per kernel is enough (PoCL builds one per grid shape)
    [ -e "$cache/seen.$k" ] && continue
    : > "$cache/seen.$k"
    objdump -d --no-show-raw-insn "$so" | awk -v ops="$ops" -v k="$k" '
        $2 ~ "^v?" ops "ps$" { if ($0 ~ /[yz]mm/) wide++; else xmm++ }
        $2 ~ "^v?" ops "ss$" || $2 ~ /^v?u?comiss$/ { scalar++ }
        END { printf "%-26s %8d %8d %8d\n", k, wide, xmm, scalar }'
done
