/*
 * path_mis — path tracing with emitter and BSDF sampling combined by multiple importance sampling
 * (Veach 1997, ch. 9; PBR 4th ed. §13.4).
 *
 * Parameters:
 *   maxDepth  integer  -1  bounces after the camera ray (-1: unbounded)
 *   rrDepth   integer  3   Russian roulette from this bounce on
 *
 *   <integrator type="path_mis"><integer name="maxDepth" value="8"/></integrator>
 */
#include <nori/pathtracer.h>

namespace nori {

class PathMIS : public PathTracer {
public:
    explicit PathMIS(const PropertyList &props) : PathTracer(props, Strategy::MIS, 0, "PathMIS") {}
};

NORI_REGISTER_CLASS(PathMIS, "path_mis");

} // namespace nori
