#!/bin/sh
# test_layers.sh — the modules' layering (tools/check_layers.py): the tree as it
# is passes, and the check fails, naming the file, on each kind of fault put
# into a scratch copy: an include of a module above, one of a module in the
# same layer, a kernel file that includes a host header or one of a higher
# kernel folder, a kernel folder with no place in the layers, a private header
# used by another module, a folder of src/ with no place in the layers, a
# source, kernel or test outside the folders the build reads, and,
# from objects, a call up to a higher module and two files calling each
# other. TAP output.
. tests/tap.sh
BUILD=${BUILD:-build/release}
C="python3 tools/check_layers.py"

if [ -d "$BUILD/obj" ]; then
    check "the tree's includes and its objects' calls point down, with no circle" \
        '$C --objects "$BUILD/obj" > "$T/out" 2>&1 || { cat "$T/out"; false; }'
else
    check "the tree's includes point down (no objects built: calls not checked)" \
        '$C > "$T/out" 2>&1 || { cat "$T/out"; false; }'
fi

# copy: a scratch copy of what the check reads; fails: the check fails on it and
# a line names $1 and the words $2
copy() { rm -rf "$T/r" && mkdir "$T/r" && cp -R Makefile src include kernels "$T/r/"; }
fails() { ! $C "$T/r" > "$T/out" 2>&1 && grep -q "^check_layers: $1.*$2" "$T/out"; }

copy
printf '#include "st_render.h"\n' >> "$T/r/src/image/image.c"
check "an include of a module above is named" 'fails "src/image/image.c:[0-9]*" "of module render, above image"'

copy
printf '#include "st_bvh.h"\n' >> "$T/r/src/filter/filter.c"
check "an include of a module of the same layer is named" 'fails "src/filter/filter.c:[0-9]*" "in the same layer as filter"'

copy
printf '#include "st_error.h"\n' >> "$T/r/kernels/shared/rng.h"
check "a kernel file that includes a host header is named" 'fails "kernels/shared/rng.h:[0-9]*" "only kernel files"'

copy
printf '#include "integrator.h"\n' >> "$T/r/kernels/geom/trace.h"
check "a kernel file that includes one of a higher kernel folder is named" 'fails "kernels/geom/trace.h:[0-9]*" "of kernels/integrator/, above kernels/geom/"'

copy
mkdir "$T/r/kernels/extra"
check "a kernel folder outside the kernel layers is named" 'fails "kernels" "folders"'

copy
printf '#include "render_int.h"\n' >> "$T/r/src/cli/cli.c"
check "a private header used by another module is named" 'fails "src/cli/cli.c:[0-9]*" "a private header of another module"'

copy
printf '#include "no_such_header.h"\n' >> "$T/r/src/scene/scene.c"
check "an include found nowhere is named" 'fails "src/scene/scene.c:[0-9]*" "none of the include folders"'

copy
mkdir "$T/r/src/extra"
check "a folder of src/ outside the layers is named" 'fails "src" "folders"'

copy
printf '/* x */\n' > "$T/r/src/extra.c"
check "a source file outside the module folders is named" 'fails "src/extra.c" "outside src/<module>/"'

copy
printf '/* x */\n' > "$T/r/kernels/extra.cl"
check "a kernel outside the kernel folders is named" 'fails "kernels/extra.cl" "outside kernels/<folder>/"'

copy
mkdir "$T/r/tests" && printf '#!/bin/sh\n' > "$T/r/tests/test_extra.sh"
check "a test outside the layer folders is named" 'fails "tests/test_extra.sh" "outside tests/<layer>/"'

copy
printf '/* x */\n' > "$T/r/include/st_extra.h"
check "a public header of no module is named" 'fails "include/st_extra.h" "of no module"'

# objects: render/a.o and render/b.o call each other; image/c.o calls up into render
mkdir -p "$T/o/render" "$T/o/image"
printf 'int st_b(void);\nint st_a(void) { return st_b(); }\n' > "$T/a.c"
printf 'int st_a(void);\nint st_b(void) { return st_a() + 1; }\n' > "$T/b.c"
printf 'int st_a(void);\nint st_c(void) { return st_a(); }\n' > "$T/c.c"
cc -c -o "$T/o/render/a.o" "$T/a.c" && cc -c -o "$T/o/render/b.o" "$T/b.c" && cc -c -o "$T/o/image/c.o" "$T/c.c"
copy
check "two files calling each other are a circle" '! $C --objects "$T/o" "$T/r" > "$T/out" 2>&1 && grep -q "^check_layers: src/render/a: a circle of files calling each other: render/a -> render/b -> render/a" "$T/out"'
check "a call up into a higher module is named" '! $C --objects "$T/o" "$T/r" > "$T/out" 2>&1 && grep -q "^check_layers: src/image/c: calls render/a (st_a) of module render, above image" "$T/out"'

echo "1..$n"
