/* fuzz_gltf.c — libFuzzer harness for the glTF importer (src/scene/gltf_*.cpp
 * behind src/scene/gltf_shim.h): any bytes, as a .gltf or .glb, parsed, validated,
 * flattened and their images decoded, with no file access (as a built-in
 * scene: URIs other than data: are refused). ASan and UBSan find what a
 * malformed file does wrong; the status must be ST_OK or an error with a
 * message. Built by `make fuzz`, run by `make test-fuzz`. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "gltf_shim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    st_gltf_data g;
    st_error err = {ST_OK, ""};
    st_status s = st_gltf_shim_load("fuzz.gltf", data, size, NULL, &g, &err);
    if (s != ST_OK && err.msg[0] == '\0')
        abort(); /* every error names what and where */
    if (s == ST_OK)
        st_gltf_shim_release(&g);
    return 0;
}
