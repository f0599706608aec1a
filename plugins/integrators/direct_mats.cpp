/*
 * direct_mats — direct lighting by sampling the BSDF and finding emitters with the rays (Veach
 * 1997, ch. 9; PBR 4th ed. §13.4).
 *
 * No parameters (one bounce: emission seen directly plus light scattered once).
 *
 *   <integrator type="direct_mats"/>
 */
#include <nori/pathtracer.h>

namespace nori {

class DirectMATS : public PathTracer {
public:
    explicit DirectMATS(const PropertyList &props)
        : PathTracer(props, Strategy::BSDF, 1, "DirectMATS") {}
};

NORI_REGISTER_CLASS(DirectMATS, "direct_mats");

} // namespace nori
