/* gltf_cameras.cpp — camera nodes (§3.10). */
#include "gltf_int.h"

#include <cmath>

namespace st_gltf {

/* A camera looks down its node's local -Z with +Y up (§3.10.1); the node's
 * scale is ignored (the axes are normalised) and up is made orthogonal to
 * forward (Gram-Schmidt). A node whose transform collapses either axis (zero
 * scale) is passed over with a warning. */
void take_camera(const Model &m, int node, int cam, const mat4 &world,
                 std::vector<st_gltf_camera> &out, notes &warn)
{
    const tinygltf::Camera &c = m.cameras[size_t(cam)];
    st_gltf_camera pick = {};
    if (c.type == "perspective") {
        const double yfov = c.perspective.yfov;
        if (!(yfov > 0.0 && yfov < M_PI))
            fail("camera %d: yfov %g is not in (0, pi)", cam, yfov);
        pick.yfov = float(yfov);
    } else if (c.type == "orthographic") {
        const double ymag = std::fabs(c.orthographic.ymag);
        if (!(ymag > 0.0 && ymag < 1e30))
            fail("camera %d: ymag %g must be non-zero and finite", cam, c.orthographic.ymag);
        pick.orthographic = 1;
        pick.ymag = float(ymag);
    } else {
        fail("camera %d: type \"%s\" is neither perspective nor orthographic", cam,
             c.type.c_str());
    }
    double f[3] = {0.0 - world.m[8], 0.0 - world.m[9], 0.0 - world.m[10]}; /* no -0 */
    double u[3] = {world.m[4], world.m[5], world.m[6]};
    bool ok = normalize3(f);
    const double d = u[0] * f[0] + u[1] * f[1] + u[2] * f[2];
    for (int i = 0; i < 3; i++)
        u[i] -= d * f[i];
    if (!ok || !normalize3(u)) {
        note(warn, "node %d: camera %d passed over (its transform collapses an axis)", node, cam);
        return;
    }
    for (int i = 0; i < 3; i++) {
        pick.origin[i] = float(world.m[12 + i]);
        pick.forward[i] = float(f[i]);
        pick.up[i] = float(u[i]);
    }
    out.push_back(pick);
}

} /* namespace st_gltf */
