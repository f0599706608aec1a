#include <nori/bsdf.h>
#include <nori/instance.h>

namespace nori {

bool BSDF::attachTo(NoriObject &parent, const std::string &name) {
    (void)name;
    auto self = std::static_pointer_cast<BSDF>(shared_from_this());
    if (auto *shape = dynamic_cast<Shape *>(&parent)) {
        shape->setBSDF(std::move(self));
        return true;
    }
    if (auto *tmesh = dynamic_cast<TMesh *>(&parent)) {
        tmesh->setBSDF(std::move(self));
        return true;
    }
    return false;
}

Color3f BSDF::albedo(const BSDFQueryRecord &bRec) const {
    // The mean of sample()'s weights eval·|cos θo|/pdf is an unbiased estimate of the
    // integral; cell centres of a grid keep it deterministic and smooth over the image.
    constexpr int kGrid = 8;
    Color3f sum(0.0f);
    for (int i = 0; i < kGrid; ++i)
        for (int j = 0; j < kGrid; ++j) {
            BSDFQueryRecord query = bRec;
            sum += sample(query, Point2f((i + 0.5f) / kGrid, (j + 0.5f) / kGrid));
        }
    return sum / float(kGrid * kGrid);
}

} // namespace nori
