#!/bin/sh
# discrepancy_table.sh — prints the README's table of star discrepancies (exact, 2-D):
# N = 256 and 1024, the mean over seeds 1-8 for a randomised sampler, one run for a
# deterministic one. `make pictures` prints it; paste it into README.md when it changes.
set -e
S=${S:-./strata}
star() { # sampler count scramble(on, none, - for a sampler without, pixels: --pixels) seed
    case "$3" in
    -) set -- "$1" "$2" "" "$4" ;;
    pixels) set -- "$1" "$2" "--pixels" "$4" ;;
    *) set -- "$1" "$2" "--scramble=$3" "$4" ;;
    esac
    "$S" pattern --sampler "$1" --count "$2" $3 --seed "$4" --discrepancy |
        sed -n 's/^star discrepancy (exact, 2-D): //p'
}
mean() { # sampler count scramble seeds
    for seed in $(seq 1 "$4"); do star "$1" "$2" "$3" "$seed"; done |
        awk -v d="$5" '{ s += $1 } END { printf "%.*f", d, s / NR }'
}
row() { # label sampler scramble seeds digits
    echo "| $1 | $(mean "$2" 256 "$3" "$4" "$5") | $(mean "$2" 1024 "$3" "$4" "$5") |"
}
echo "| sampler | N = 256 | N = 1024 |"
echo "|---|---|---|"
row random random - 8 5
row "uniform (16×16, 32×32 grid)" uniform - 1 5
row stratified stratified on 8 5
row joint-stratified joint-stratified - 8 5
row "poisson (Bridson)" poisson - 8 5
row "best-candidate (Mitchell)" best-candidate - 8 5
row "poisson \`--pixels\` (N points a pixel of a 16×16, 32×32 tile)" poisson pixels 8 5
row "best-candidate \`--pixels\` (same)" best-candidate pixels 8 5
row "halton (scrambled)" halton on 8 5
row "halton (\`--scramble none\`)" halton none 1 5
row "hammersley (scrambled)" hammersley on 8 5
row "hammersley (\`--scramble none\`)" hammersley none 1 6
row "paddedsobol (scrambled)" paddedsobol on 8 5
row "paddedsobol (\`--scramble none\`)" paddedsobol none 1 5
row "sobol (scrambled)" sobol on 8 5
row "sobol (\`--scramble none\`)" sobol none 1 5
row "zsobol (scrambled)" zsobol on 8 5
row pmj02 pmj02 - 8 5
