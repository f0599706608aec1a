#include <nori/rfilter.h>

namespace nori {

float ReconstructionFilter::checkedRadius(float radius, const char *filterName) {
    if (!(radius > 0.0f) || !std::isfinite(radius))
        throw NoriException("{} filter: 'radius' must be positive and finite, got {}", filterName,
                            radius);
    return radius;
}

} // namespace nori
