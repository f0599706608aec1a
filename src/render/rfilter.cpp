#include <nori/rfilter.h>

namespace nori {

float ReconstructionFilter::checkedRadius(float radius, const char *filterName) {
    if (!(radius > 0.0f && radius <= kMaxRadius))
        throw NoriException("{} filter: 'radius' must lie in (0, {}] pixels, got {}", filterName,
                            kMaxRadius, radius);
    return radius;
}

} // namespace nori
