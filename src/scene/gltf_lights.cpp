/* gltf_lights.cpp — KHR_lights_punctual lights on nodes. */
#include "gltf_int.h"

#include <cmath>

namespace st_gltf {

/* The KHR_lights_punctual light a node names (its extension's "light"),
 * or -1. */
int node_light(const tinygltf::Node &node, int index, size_t light_count)
{
    auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end())
        return -1;
    const tinygltf::Value &v = ext->second.Get("light");
    if (!v.IsInt() && !v.IsNumber())
        fail("node %d: KHR_lights_punctual has no light index", index);
    /* compared as a double: a number such as 1e20 has no int to convert to */
    const double i = v.IsInt() ? double(v.Get<int>()) : v.GetNumberAsDouble();
    if (!(i >= 0.0 && i < double(light_count)) || i != std::floor(i))
        fail("node %d: light %g out of range (have %zu)", index, i, light_count);
    return int(i);
}

/* A punctual light (KHR_lights_punctual) at its node's world translation,
 * shining down the node's world -Z; the colour and intensity as the file
 * gives them (range, a culling hint, is not read). A spot's cone angles must
 * satisfy 0 <= inner < outer <= pi/2; a negative intensity or colour is an
 * error; a node whose transform collapses -Z drops a spot or directional
 * light with a warning. */
void take_light(const Model &m, int node, int li, const mat4 &world,
                std::vector<st_gltf_light> &out, notes &warn)
{
    const tinygltf::Light &l = m.lights[size_t(li)];
    st_gltf_light pick = {};
    if (l.type == "point")
        pick.type = 0;
    else if (l.type == "spot")
        pick.type = 1;
    else if (l.type == "directional")
        pick.type = 2;
    else
        fail("light %d: type \"%s\" is not point, spot or directional", li, l.type.c_str());
    if (!(l.intensity >= 0.0 && l.intensity < 1e30))
        fail("light %d: intensity %g must be finite and not negative", li, l.intensity);
    for (int i = 0; i < 3; i++) {
        const double c = l.color.size() == 3 ? l.color[size_t(i)] : 1.0;
        if (!(c >= 0.0 && c < 1e30))
            fail("light %d: color must be three finite values, not negative", li);
        pick.color[i] = float(c);
    }
    pick.intensity = float(l.intensity);
    pick.inner_cone = float(l.spot.innerConeAngle);
    pick.outer_cone = float(l.spot.outerConeAngle);
    if (pick.type == 1 && !(l.spot.innerConeAngle >= 0.0 &&
                            l.spot.innerConeAngle < l.spot.outerConeAngle &&
                            l.spot.outerConeAngle <= M_PI / 2.0))
        fail("light %d: spot cone angles %g, %g not 0 <= inner < outer <= pi/2", li,
             l.spot.innerConeAngle, l.spot.outerConeAngle);
    double f[3] = {0.0 - world.m[8], 0.0 - world.m[9], 0.0 - world.m[10]};
    if (!normalize3(f)) {
        if (pick.type != 0) {
            note(warn, "node %d: light %d passed over (its transform collapses -Z)", node, li);
            return;
        }
        f[2] = -1.0;
    }
    for (int i = 0; i < 3; i++) {
        pick.pos[i] = float(world.m[12 + i]);
        pick.dir[i] = float(f[i]);
    }
    out.push_back(pick);
}

} /* namespace st_gltf */
