# tap.sh — sourced by the command-line test scripts: a scratch folder $T
# (removed on exit), the binary $S, and TAP output helpers.
#   check NAME CONDITION          ok when the shell condition holds
#   skip REASON                   a check that cannot run here, and why (TAP's
#                                 "# SKIP": make test counts and lists it); a
#                                 script skipped whole prints "1..0 # SKIP REASON"
#   expect NAME STATUS PATTERN CMD...   ok when CMD exits with STATUS and a
#                                 line of its stderr matches PATTERN
S=${STRATA:-./strata}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
n=0
ok() { n=$((n + 1)); echo "ok $n - $1"; }
not_ok() { n=$((n + 1)); echo "not ok $n - $1"; }
skip() { n=$((n + 1)); echo "ok $n - # SKIP $1"; }
check() { if eval "$2"; then ok "$1"; else not_ok "$1 $3"; fi; }
expect() {
    name=$1 want=$2 pat=$3
    shift 3
    "$@" > "$T/out" 2> "$T/err"
    got=$?
    if [ "$got" -eq "$want" ] && grep -q -- "$pat" "$T/err"; then
        ok "$name"
    else
        not_ok "$name (status $got, stderr: $(head -c 300 "$T/err"))"
    fi
}
