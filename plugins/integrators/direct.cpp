/*
 * direct — the ETH course's name for direct_ems: direct lighting by emitter sampling (Veach 1997,
 * ch. 9; PBR 4th ed. §13.4).
 *
 * No parameters (one bounce: emission seen directly plus light scattered once).
 *
 *   <integrator type="direct"/>
 */
#include <nori/pathtracer.h>

namespace nori {

class Direct : public PathTracer {
public:
    explicit Direct(const PropertyList &props) : PathTracer(props, Strategy::Light, 1, "Direct") {}
};

NORI_REGISTER_CLASS(Direct, "direct");

} // namespace nori
