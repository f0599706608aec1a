#include <nori/bsdfparams.h>
#include <nori/proplist.h>

namespace nori {

TexturedMicrofacet::TexturedMicrofacet(MicrofacetDistribution::Type type, const PropertyList &props,
                                       TextureParameters &textures, const std::string &plugin)
    : m_type(type), m_alpha(textures.scalar(props, "alpha", 0.1f)) {
    if (m_alpha->isConstant() && !(m_alpha->average().x() > 0.0f))
        throw NoriException("{}: 'alpha' must be positive, got {}", plugin, m_alpha->average().x());
}

ConductorIOR readConductorIOR(const PropertyList &props, const std::string &plugin,
                              TextureParameters &textures) {
    Color3f eta, k;
    ConductorIOR ior;
    if (props.has("material")) {
        if (props.has("eta") || props.has("k"))
            throw NoriException("{}: give either 'material' or 'eta' and 'k', not both", plugin);
        lookupConductor(props.getString("material"), eta, k);
        ior.eta = textures.constant(eta);
        ior.k = textures.constant(k);
    } else {
        lookupConductor("Cu", eta, k);
        ior.eta = textures.color(props, "eta", eta);
        ior.k = textures.color(props, "k", k);
    }
    ior.extIOR = props.getFloat("extIOR", 1.000277f);
    if (!(ior.extIOR > 0.0f))
        throw NoriException("{}: need extIOR > 0", plugin);
    if (ior.eta->isConstant() && ior.k->isConstant() &&
        ((ior.eta->average() <= 0.0f).any() || (ior.k->average() < 0.0f).any()))
        throw NoriException("{}: need eta > 0 and k >= 0", plugin);
    return ior;
}

float readIOR(const PropertyList &props, const std::string &name, float defaultValue,
              const std::string &plugin) {
    float ior = defaultValue;
    if (props.holdsScalar(name)) {
        ior = props.getFloat(name);
    } else if (props.has(name)) {
        try {
            ior = lookupIOR(props.getString(name));
        } catch (const NoriException &error) {
            throw NoriException("{}: '{}' at {}: {}", plugin, name, props.location(name),
                                error.what());
        }
    }
    if (!(ior > 0.0f) || !std::isfinite(ior))
        throw NoriException("{}: '{}' must be a positive index of refraction, got {}", plugin, name,
                            ior);
    return ior;
}

Color3f ConductorIOR::fresnel(const TextureQuery &q, float cosThetaI) const {
    // Textures may hold any value: keep η positive and k non-negative.
    const Color3f etaHere = eta->eval(q).max(1e-4f) / extIOR;
    const Color3f kHere = k->eval(q).max(0.0f) / extIOR;
    return fresnelConductor(cosThetaI, etaHere, kHere);
}

} // namespace nori
