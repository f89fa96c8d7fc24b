#!/bin/sh
# test_sobol_scipy.sh — the global Sobol' sampler against an independent
# implementation: `strata pattern --sampler sobol --scramble none` (one pixel:
# the sequence itself) must equal scipy.stats.qmc.Sobol(d, scramble=False,
# bits=32) in every dimension strata has (256), scipy's Gray-code order
# undone, each value being the largest float <= scipy's k 2^-32 (the 24
# leading significant bits of k). Needs python3-scipy (in the Makefile's
# DEB_PACKAGES); without it the test says so and is skipped. TAP output.
. tests/tap.sh
PY=""
for p in /usr/bin/python3 python3; do
    if "$p" -c "import scipy.stats, numpy" 2>/dev/null; then PY=$p; break; fi
done
if [ -z "$PY" ]; then
    echo "1..0 # SKIP python3 with scipy not found (apt-get install python3-scipy)"
    exit 0
fi
$S pattern --sampler sobol --scramble none --count 1024 --dims 256 --csv "$T/s.csv"
check "pattern writes a header and 1024 points of 256 dimensions" '[ "$(wc -l < "$T/s.csv")" -eq 1025 ] && [ "$(head -c 9 "$T/s.csv")" = "x0,x1,x2," ]'
"$PY" - "$T/s.csv" > "$T/out" 2>&1 <<'PYEOF'
import sys
import numpy as np
from scipy.stats import qmc
ours = np.loadtxt(sys.argv[1], delimiter=",", skiprows=1, dtype=np.float64).astype(np.float32)
# scipy draws in Gray-code order: its point n is the sequence at index
# n xor (n >> 1) (the same set in every prefix of 2^m points)
n = np.arange(1024)
ref = np.empty((1024, 256))
ref[n ^ (n >> 1)] = qmc.Sobol(d=256, scramble=False, bits=32).random(1024)
k = np.round(ref * 2.0**32).astype(np.uint64)    # exact: scipy's values are k 2^-32
shift = np.array([max(int(v).bit_length() - 24, 0) for v in k.flat], dtype=np.uint64)
want = (((k.flatten() >> shift) << shift) * 2.0**-32).astype(np.float32).reshape(k.shape)
bad = np.argwhere(ours != want)
if len(bad):
    i, d = bad[0]
    print("point %d dim %d: strata %r, scipy %r" % (i, d, float(ours[i, d]), float(ref[i, d])))
    sys.exit(1)
print("equal in all %d x %d values" % ours.shape)
PYEOF
st=$?
check "sobol --scramble none equals scipy's Sobol' in every dimension" '[ "$st" -eq 0 ]' "$(cat "$T/out")"
echo "1..$n"
