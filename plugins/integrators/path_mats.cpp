/*
 * path_mats — path tracing by BSDF sampling alone (emitters are found by the paths) (Veach 1997,
 * ch. 9; PBR 4th ed. §13.4).
 *
 * Parameters:
 *   maxDepth  integer  -1  bounces after the camera ray (-1: unbounded)
 *   rrDepth   integer  3   Russian roulette from this bounce on
 *
 *   <integrator type="path_mats"><integer name="maxDepth" value="8"/></integrator>
 */
#include <nori/pathtracer.h>

namespace nori {

class PathMATS : public PathTracer {
public:
    explicit PathMATS(const PropertyList &props)
        : PathTracer(props, Strategy::BSDF, 0, "PathMATS") {}
};

NORI_REGISTER_CLASS(PathMATS, "path_mats");

} // namespace nori
