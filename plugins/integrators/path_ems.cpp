/*
 * path_ems — path tracing with emitter sampling at every vertex with a non-delta BSDF (Veach 1997,
 * ch. 9; PBR 4th ed. §13.4).
 *
 * Parameters:
 *   maxDepth  integer  -1  bounces after the camera ray (-1: unbounded)
 *   rrDepth   integer  3   Russian roulette from this bounce on
 *
 *   <integrator type="path_ems"><integer name="maxDepth" value="8"/></integrator>
 */
#include <nori/pathtracer.h>

namespace nori {

class PathEMS : public PathTracer {
public:
    explicit PathEMS(const PropertyList &props)
        : PathTracer(props, Strategy::Light, 0, "PathEMS") {}
};

NORI_REGISTER_CLASS(PathEMS, "path_ems");

} // namespace nori
