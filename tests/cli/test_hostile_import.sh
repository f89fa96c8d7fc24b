#!/bin/sh
# test_hostile_import.sh — hostile input, round three (issue 55), the scene import: values that
# overflow a float after conversion, numbers past 2^32 that would wrap, and the import's memory
# and work budget, reckoned from the file's declarations before anything is expanded. TAP.
. tests/tap.sh

R="--width 16 --height 12 --spp 1 --quiet"

# Writes scene $1 (a path, or a name in tests/scenes) with the Python statements $3 applied to
# its JSON (as g) to $T/$2.
edit() {
    src=$1
    [ -f "$src" ] || src=tests/scenes/$1
    python3 -c 'import json, sys
g = json.load(open(sys.argv[1]))
exec(sys.argv[3])
json.dump(g, open(sys.argv[2], "w"))' "$src" "$T/$2" "$3"
}
# refused NAME PATTERN FILE: the render of $T/FILE exits 1 with PATTERN after its name.
refused() {
    expect "$1" 1 "^strata: error: $T/$3: $2" timeout 120 $S render "$T/$3" $R -o "$T/o.exr"
}

# ---- float overflow after conversion --------------------------------------------------------
edit punctual.gltf hot.gltf 'g["extensions"]["KHR_lights_punctual"]["lights"][0].update(intensity=1e20, color=[1e20] * 3)'
refused "a light of colour 1e20 x intensity 1e20 is refused naming the product" \
    "light 0 (in node order): colour 1e+20 x intensity 1e+20 = 1e+40, past the most a light may have" hot.gltf
edit punctual.gltf farcam.gltf 'g["nodes"][1]["translation"] = [0, 0, 1e39]'
refused "a camera at z = 1e39 (infinite as a float) is refused" \
    "camera 0 at (0, 0, inf): a coordinate past the float range" farcam.gltf
edit punctual.gltf farlight.gltf 'g["nodes"][2]["translation"] = [0, 0, 1e39]'
refused "a light at z = 1e39 is refused" "light 0 (in node order) at (0, 0, inf): a coordinate past the float range" farlight.gltf
check "no image from a refused scene" '[ ! -e "$T/o.exr" ]'

# ---- numbers past what tinygltf's int holds ------------------------------------------------------
edit quad_sparse_zeros.gltf mesh32.gltf 'g["nodes"][0]["mesh"] = 4294967296'
refused "\"mesh\": 4294967296 is refused, not read as mesh 0" "nodes\[0\].mesh: 4294967296 is not an index" mesh32.gltf
edit quad_sparse_zeros.gltf scene32.gltf 'g["scene"] = 4294967296'
refused "\"scene\": 4294967296 is refused, not read as scene 0" "scene: 4294967296 is not an index" scene32.gltf
edit quad_sparse_zeros.gltf mode32.gltf 'g["meshes"][0]["primitives"][0]["mode"] = 4294967300'
refused "\"mode\": 4294967300 is refused, not read as TRIANGLES" \
    "meshes\[0\].primitives\[0\].mode: 4294967300 is not an index" mode32.gltf
edit punctual.gltf light20.gltf 'g["nodes"][2]["extensions"]["KHR_lights_punctual"]["light"] = 1e20'
refused "\"light\": 1e20 is refused (no int to convert to)" \
    "nodes\[2\].extensions.KHR_lights_punctual.light: 1e+20 is not an index" light20.gltf
edit quad_sparse_zeros.gltf extras.gltf 'g["nodes"][0]["extras"] = {"mesh": 4294967296, "index": 0.5}'
$S render "$T/extras.gltf" $R -o "$T/x.exr" 2> "$T/err"
check "numbers in extras are the file's own business: the scene renders" '[ -s "$T/x.exr" ]' "($(cat "$T/err"))"

# ---- one warning per mesh, however many draw it -------------------------------------------------
edit camera_pick.gltf many.gltf 'g["nodes"] += [{"mesh": 0, "translation": [i, 0, 0]} for i in range(300)]
g["scenes"][0]["nodes"] += list(range(7, 307))'
$S render "$T/many.gltf" $R -o "$T/many.exr" 2> "$T/err"
check "a skipped primitive drawn by 301 nodes is warned about once (a char counter wrapped at 256)" \
    '[ -s "$T/many.exr" ] && [ "$(grep -c "POINTS" "$T/err")" = 1 ]' "($(grep -c POINTS "$T/err") warnings)"

# ---- messages ------------------------------------------------------------------------------------
edit skin.gltf floatjoints.gltf 'g["accessors"][2].update(componentType=5126, bufferView=3)'
refused "float JOINTS_0 names the types it may have" \
    "accessor 2: JOINTS_0 must be unsigned byte or unsigned short VEC4" floatjoints.gltf

# ---- the import's budget, reckoned before anything is expanded -----------------------------------
# (a sparse accessor of N elements without a bufferView: zeros but for `count` values)
SPARSE='def sparse(count, type, n=3, values=5): return {"componentType": 5126, "count": count, "type": type,
    "sparse": {"count": n, "indices": {"bufferView": 4, "componentType": 5121}, "values": {"bufferView": values}}}'
edit quad_sparse_zeros.gltf unused.gltf "$SPARSE
g[\"accessors\"] += [sparse(1 << 26, \"VEC4\") for _ in range(8)]"
sh -c "ulimit -v 3000000; exec $S render $T/unused.gltf $R -o $T/unused.exr" 2> "$T/err"
check "8 unused sparse accessors of 1 GiB each stay sparse: the scene renders in 3 GB" '[ -s "$T/unused.exr" ]' \
    "($(cat "$T/err"))"
edit quad_sparse_zeros.gltf used.gltf "$SPARSE
g[\"accessors\"][0][\"count\"] = 1 << 26
g[\"accessors\"][1] = sparse(1 << 26, \"VEC3\")"
expect "used sparse accessors of 1.5 GiB in all are refused before any is expanded" 1 \
    "used.gltf: accessor 1: sparse accessors made dense for the scene .*: more than 1024 MiB in all, the limit" \
    sh -c "ulimit -v 3000000; exec $S render $T/used.gltf $R -o $T/o.exr"
edit instancing.gltf empty_inst.gltf 'g["meshes"].append({"primitives": [{"attributes": {"POSITION": 0}, "mode": 0}]})
g["accessors"].append({"componentType": 5126, "count": 4000000, "type": "VEC3",
    "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5121}, "values": {"bufferView": 2}}})
g["nodes"].append({"mesh": 1, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": 5}}}})
g["scenes"][0]["nodes"].append(1)'
refused "4 million instances of a mesh without triangles are refused before they are made" \
    "node 1: [0-9]* drawings of meshes (nodes and EXT_mesh_gpu_instancing instances): more than 1048576, the limit" empty_inst.gltf
# (a mesh drawing one quad from a million vertices, sparse, and a small mesh beside it)
edit quad_sparse_zeros.gltf alternate.gltf 'g["accessors"][0]["count"] = 1000000
g["meshes"] = [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 3}]},
               {"primitives": [{"attributes": {"POSITION": 1}, "indices": 3}]}]
g["nodes"] = [{"mesh": i % 2, "translation": [i, 0, 0]} for i in range(200)]
g["scenes"][0]["nodes"] = list(range(200))'
refused "100 nodes drawing a million vertices between nodes of another mesh are refused by the vertices they read" \
    "the scene reads more than 67108864 vertices, every node and instance that draws a mesh counted" alternate.gltf
edit "$T/alternate.gltf" siblings.gltf 'g["nodes"] = [{"mesh": 0, "translation": [i, 0, 0]} for i in range(200)]'
$S render "$T/siblings.gltf" $R -o "$T/siblings.exr" 2> "$T/err"
check "200 sibling nodes of that mesh read it once: the scene renders" '[ -s "$T/siblings.exr" ]' "($(cat "$T/err"))"

# PNGs of W x H 1-bit texels, a few kB each ($1: the file, $2 $3: W H)
png() {
    python3 -c 'import struct, sys, zlib
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
W, H = int(sys.argv[2]), int(sys.argv[3])
raw = (b"\0" * (1 + (W + 7) // 8)) * H
open(sys.argv[1], "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 1, 0, 0, 0, 0))
    + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))' "$@"
}
png "$T/big.png" 4096 4096
IMAGES='g["images"] = [{"uri": u} for u in URIS]
g["textures"] = [{"source": i} for i in range(len(URIS))]
g["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": i}}} for i in range(len(URIS))]'
edit textured_quad.gltf same8.gltf "URIS = ['big.png'] * 8
$IMAGES"
sh -c "ulimit -v 1500000; exec $S render $T/same8.gltf $R -o $T/same8.exr" 2> "$T/err"
check "8 images of one 4096 x 4096 PNG are decoded once: the scene renders in 1.5 GB" \
    '[ -s "$T/same8.exr" ] && ! grep -q "white texture\|memory" "$T/err"' "($(cat "$T/err"))"
for k in 0 1 2 3 4; do png "$T/d$k.png" 8192 $((8192 - k)); done
edit textured_quad.gltf distinct5.gltf "URIS = ['d%d.png' % k for k in range(5)]
$IMAGES"
refused "5 distinct 8192 x 8192 images (2^28.3 texels) are refused by their headers, before decoding" \
    "the textures' images hold [0-9]* texels in all (images of the same bytes once): more than 2^28, the limit" distinct5.gltf
python3 -c 'import json, sys
g = json.load(open(sys.argv[1]))
g["materials"] = [{}] * 1000000
json.dump(g, open(sys.argv[2], "w"), separators=(",", ":"))' tests/scenes/quad_sparse_zeros.gltf "$T/mats.gltf"
expect "a million empty materials (3 MB) are refused before tinygltf makes them" 1 \
    "mats.gltf: 1000000 materials: more than 65536, the limit" \
    sh -c "ulimit -v 1500000; exec $S render $T/mats.gltf $R -o $T/o.exr"

echo "1..$n"
