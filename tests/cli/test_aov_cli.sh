#!/bin/sh
# test_aov_cli.sh — --aov through the command line: strict parsing, the
# refusals (adaptive, PNG only, bench), the note on filters with negative
# lobes (once, and not for box or gaussian); the channels in exrheader's
# listing (Debian's openexr); read back by OpenEXR's Python
# binding (build/pyexr, from make deps): the channels Albedo.R/G/B, N.X/Y/Z,
# P.X/Y/Z and Z are FLOAT beside R, G, B, equal to what the render wrote, and
# a split render's parts merge into every channel of the whole render bit for
# bit; with Open Image Denoise's Python package (oidn, in the same venv
# where pip could install it) a 16-spp render denoised with its albedo and
# normal is nearer a 1024-spp reference than the noisy one. TAP output.
. tests/tap.sh
PY=${PYEXR:-build/pyexr/bin/python}
M=tests/scenes/aov_sphere.gltf
R="--width 24 --height 16 --spp 4 --quiet"

expect "--aov with an unknown name exits 2 naming the known ones" 2 \
    "^strata: error: --aov colour: .*albedo" "$S" render $M $R --aov albedo,colour -o "$T/o.exr"
expect "--aov with a name twice exits 2" 2 "^strata: error: --aov depth,depth: depth given twice" \
    "$S" render $M $R --aov depth,depth -o "$T/o.exr"
expect "--aov with --adaptive exits 2" 2 "^strata: error: --aov: not with --adaptive" \
    "$S" render $M $R --aov depth --adaptive --sampler random -o "$T/o.exr"
expect "--aov into a PNG alone exits 2" 2 "^strata: error: --aov: the AOVs go into an EXR" \
    "$S" render $M $R --aov depth -o "$T/o.png"
expect "bench --aov exits 2" 2 "^strata: error: --aov: only .strata render." "$S" bench $M $R --aov depth
check "the refused renders wrote nothing" '[ ! -e "$T/o.exr" ] && [ ! -e "$T/o.png" ]'

"$S" render $M --width 24 --height 16 --spp 4 --aov depth,normal -o "$T/m.exr" > /dev/null 2> "$T/err"
check "mitchell (negative lobes) with --aov: one note saying denoisers expect box or gaussian" \
    '[ "$(grep -c "denoisers expect a box or gaussian" "$T/err")" = 1 ]' "($(cat "$T/err"))"
for f in box gaussian; do
    "$S" render $M $R --filter $f --aov depth -o "$T/$f.exr" 2> "$T/err"
    check "no such note with $f" '! grep -q "denoisers" "$T/err"'
done
check "the EXR header names the AOVs" 'grep -aq "normal,depth" "$T/m.exr"'
"$S" render $M --width 24 --height 16 --spp 4 --aov depth --filter box -o "$T/s.exr" > "$T/out" 2> /dev/null
check "the summary gives the AOVs' time apart" 'grep -q "^strata: AOVs rendered in [0-9.]* s more$" "$T/out"' "($(cat "$T/out"))"
if command -v exrheader > /dev/null; then # Debian's openexr (make deps)
    exrheader "$T/m.exr" > "$T/h" 2>&1
    check "exrheader lists N.X/Y/Z and Z as 32-bit floats beside R, G, B" \
        '(for c in B G N.X N.Y N.Z R Z; do grep -q "^    $c, 32-bit floating-point" "$T/h" || exit 1; done)' "($(head -c 400 "$T/h"))"
else
    skip "exrheader (Debian's openexr, make deps) is not installed"
fi
if command -v bash > /dev/null; then
    got=$(bash -c '. tools/strata.bash-completion; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _strata; echo "${COMPREPLY[*]}"' _ "$S" render --aov albedo,no)
    check "the completion completes the last AOV of a list" '[ "$got" = "albedo,normal" ]' "(got '$got')"
fi

if ! "$PY" -c "import OpenEXR, numpy" 2> /dev/null; then
    skip "OpenEXR's Python binding is not installed (make deps; it needs pip's network)"
    echo "1..$n"
    exit 0
fi
A="--width 32 --height 24 --spp 8 --filter lanczos --quiet --aov albedo,normal,depth,position"
"$S" render $M $A -o "$T/whole.exr"
"$S" render $M $A --sample-range 0:3 -o "$T/p1.exr"
"$S" render $M $A --sample-range 3:8 -o "$T/p2.exr"
"$S" merge "$T/p1.exr" "$T/p2.exr" -o "$T/merged.exr"
"$PY" - "$T/whole.exr" "$T/merged.exr" > "$T/py" 2>&1 << 'PYEOF'
import sys, OpenEXR, numpy as np
whole = OpenEXR.File(sys.argv[1], separate_channels=True)
merged = OpenEXR.File(sys.argv[2], separate_channels=True)
want = ["Albedo.B", "Albedo.G", "Albedo.R", "B", "G", "N.X", "N.Y", "N.Z", "P.X", "P.Y", "P.Z", "R", "Z"]
ch = whole.channels()
print("names", sorted(ch) == want, sorted(ch))
print("float32", all(ch[c].pixels.dtype == np.float32 for c in ch))
print("merged", sorted(merged.channels()) == want and
      all(np.array_equal(ch[c].pixels.view(np.uint32), merged.channels()[c].pixels.view(np.uint32)) for c in want))
centre = [float(ch["N." + a].pixels[12, 16]) for a in "XYZ"]  # the sphere's middle, facing us
print("centre", abs(centre[0]) < 0.05 and abs(centre[1]) < 0.05 and centre[2] > 0.99, centre)
PYEOF
check "OpenEXR's binding reads the AOV channels by their names" 'grep -q "^names True" "$T/py"' "($(cat "$T/py"))"
check "every channel is FLOAT (32-bit)" 'grep -q "^float32 True" "$T/py"'
check "merged parts hold every channel of one render bit for bit" 'grep -q "^merged True" "$T/py"'
check "the normal read back at the sphere's middle faces the camera" 'grep -q "^centre True" "$T/py"'

if ! "$PY" -c "import oidn" 2> /dev/null; then
    skip "Open Image Denoise's Python package (oidn) is not installed (make deps; pip)"
    echo "1..$n"
    exit 0
fi
# a Cornell box at 16 spp (box filter: what denoisers expect) with its
# albedo and normal, and the same at 1024 spp (another seed) as the reference
D="--width 64 --height 64 --filter box --quiet"
"$S" render $D --spp 16 --seed 3 --aov albedo,normal -o "$T/noisy.exr"
"$S" render $D --spp 1024 --seed 4 -o "$T/ref.exr"
"$PY" - "$T/noisy.exr" "$T/ref.exr" > "$T/py" 2>&1 << 'PYEOF'
import sys, ctypes, OpenEXR, numpy as np, oidn
def rgb(f, names):
    ch = OpenEXR.File(f, separate_channels=True).channels()
    return np.ascontiguousarray(np.stack([ch[c].pixels for c in names], -1).astype(np.float32))
color = rgb(sys.argv[1], "RGB")
albedo = rgb(sys.argv[1], ["Albedo.R", "Albedo.G", "Albedo.B"])
normal = rgb(sys.argv[1], ["N.X", "N.Y", "N.Z"])
ref = rgb(sys.argv[2], "RGB")
h, w, _ = color.shape
out = np.zeros_like(color)
dev = oidn.NewDevice()
oidn.CommitDevice(dev)
flt = oidn.NewFilter(dev, "RT")
for name, img in (("color", color), ("albedo", albedo), ("normal", normal), ("output", out)):
    oidn.SetSharedFilterImage(flt, name, img, oidn.FORMAT_FLOAT3, w, h)
lib = getattr(oidn, "__lib_oidn")  # the wrapper has no setter for bool parameters
lib.oidnSetFilter1b.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_bool]
lib.oidnSetFilter1b(flt, b"hdr", True)  # radiance, the light above 1
oidn.CommitFilter(flt)
oidn.ExecuteFilter(flt)
err = oidn.GetDeviceError(dev)
# compared as displayed (clamped to [0, 1]): in radiance the light's few
# pixels (17 times white) and their edges, which any denoiser softens, outweigh the room
shown = lambda a: np.clip(a, 0.0, 1.0)
rmse = lambda a: float(np.sqrt(np.mean((shown(a) - shown(ref)) ** 2)))
print("noisy %.5f denoised %.5f error %s" % (rmse(color), rmse(out), err))
PYEOF
read -r _ noisy _ denoised _ < "$T/py"
check "Open Image Denoise with the albedo and normal AOVs brings 16 spp nearer 1024 spp" \
    'awk -v a="$denoised" -v b="$noisy" "BEGIN { exit !(a + 0 > 0 && a < b) }"' "($(cat "$T/py"))"
echo "# RMSE against 1024 spp: $(cat "$T/py")"
echo "1..$n"
