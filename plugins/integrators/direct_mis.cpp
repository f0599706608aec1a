/*
 * direct_mis — direct lighting by both strategies, combined by multiple importance sampling
 * (balance heuristic) (Veach 1997, ch. 9; PBR 4th ed. §13.4).
 *
 * No parameters (one bounce: emission seen directly plus light scattered once).
 *
 *   <integrator type="direct_mis"/>
 */
#include <nori/pathtracer.h>

namespace nori {

class DirectMIS : public PathTracer {
public:
    explicit DirectMIS(const PropertyList &props)
        : PathTracer(props, Strategy::MIS, 1, "DirectMIS") {}
};

NORI_REGISTER_CLASS(DirectMIS, "direct_mis");

} // namespace nori
