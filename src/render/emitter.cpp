#include <nori/emitter.h>
#include <nori/proplist.h>

namespace nori {

Color3f Emitter::readIntensity(const PropertyList &props, const std::string &plugin,
                               float solidAngle) {
    const bool hasPower = props.has("power"), hasIntensity = props.has("intensity");
    if (hasPower == hasIntensity)
        throw NoriException("{}: give exactly one of 'power' and 'intensity'", plugin);
    const Color3f intensity =
        hasPower ? Color3f(props.getColor("power") / solidAngle) : props.getColor("intensity");
    if ((intensity < 0.0f).any() || !intensity.allFinite())
        throw NoriException("{}: power and intensity must be finite and not negative", plugin);
    return intensity;
}

} // namespace nori
