#include <nori/integrator.h>

#include <map>

namespace nori {

IntegratorQuantity courseIntegratorQuantity(const std::string &name) {
    // The integrators of the Nori 2 courses' assignments (EPFL CS-440, ETH Computer
    // Graphics), by the names their handouts give them.
    static const std::map<std::string, IntegratorQuantity> course = {
        {"ao", IntegratorQuantity::AmbientOcclusion},
        {"av", IntegratorQuantity::AverageVisibility},
        {"simple", IntegratorQuantity::PointLight},
        {"direct", IntegratorQuantity::DirectIllumination},
        {"direct_ems", IntegratorQuantity::DirectIllumination},
        {"direct_mats", IntegratorQuantity::DirectIllumination},
        {"direct_mis", IntegratorQuantity::DirectIllumination},
        {"whitted", IntegratorQuantity::Whitted},
        {"normals", IntegratorQuantity::Normals},
        {"material", IntegratorQuantity::Material}};
    const auto it = course.find(name);
    return it == course.end() ? IntegratorQuantity::Radiance : it->second;
}

const char *referenceIntegrator(IntegratorQuantity quantity) {
    switch (quantity) {
    case IntegratorQuantity::AmbientOcclusion:
        return "ao";
    case IntegratorQuantity::AverageVisibility:
        return "av";
    case IntegratorQuantity::DirectIllumination:
        return "direct";
    case IntegratorQuantity::Whitted:
        return "whitted";
    case IntegratorQuantity::PointLight:
        return "simple";
    case IntegratorQuantity::Normals:
        return "normals";
    case IntegratorQuantity::Material:
        return "material";
    case IntegratorQuantity::Radiance:
        break;
    }
    return "path_mis";
}

} // namespace nori
