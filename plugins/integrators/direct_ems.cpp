/*
 * direct_ems — direct lighting by sampling the emitters (next-event estimation) (Veach 1997, ch. 9;
 * PBR 4th ed. §13.4).
 *
 * No parameters (one bounce: emission seen directly plus light scattered once).
 *
 *   <integrator type="direct_ems"/>
 */
#include <nori/pathtracer.h>

namespace nori {

class DirectEMS : public PathTracer {
public:
    explicit DirectEMS(const PropertyList &props)
        : PathTracer(props, Strategy::Light, 1, "DirectEMS") {}
};

NORI_REGISTER_CLASS(DirectEMS, "direct_ems");

} // namespace nori
