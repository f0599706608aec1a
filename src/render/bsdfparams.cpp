#include <nori/bsdfparams.h>
#include <nori/proplist.h>

namespace nori {

TexturedMicrofacet::TexturedMicrofacet(MicrofacetDistribution::Type type, const PropertyList &props,
                                       TextureParameters &textures, const std::string &plugin)
    : m_type(type), m_remap(props.getBoolean("remapRoughness", false)) {
    if (props.has("alphaU") || props.has("alphaV")) {
        if (props.has("alpha"))
            throw NoriException("{}: give 'alpha', or 'alphaU' and 'alphaV', not both", plugin);
        m_alphaU = textures.scalar(props, "alphaU", 0.1f);
        m_alphaV = textures.scalar(props, "alphaV", 0.1f);
    } else {
        m_alphaU = m_alphaV = textures.scalar(props, "alpha", 0.1f);
    }
    for (const auto &[name, value] :
         {std::make_pair("alphaU", m_alphaU.get()), std::make_pair("alphaV", m_alphaV.get())})
        if (value->isConstant() && !(value->average().x() > 0.0f))
            throw NoriException("{}: '{}' must be positive, got {}", plugin,
                                m_alphaU == m_alphaV ? "alpha" : name, value->average().x());
}

std::string TexturedMicrofacet::toString() const {
    const std::string remap = m_remap ? ", remapRoughness=true" : "";
    if (m_alphaU == m_alphaV)
        return fmt::format("alpha={}{}", m_alphaU->toString(), remap);
    return fmt::format("alphaU={}, alphaV={}{}", m_alphaU->toString(), m_alphaV->toString(), remap);
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
    if (props.holdsScalar(name) || props.holdsObject(name)) {
        ior = props.getFloat(name); // a nested object: getFloat names the mismatch
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

PlasticLayers::PlasticLayers(const PropertyList &props, TextureParameters &textures,
                             const std::string &plugin) {
    intIOR = readIOR(props, "intIOR", 1.49f, plugin);
    extIOR = readIOR(props, "extIOR", 1.000277f, plugin);
    if (intIOR == extIOR)
        throw NoriException("{}: 'intIOR' and 'extIOR' must differ, both are {}", plugin, intIOR);
    invEta2 = (extIOR / intIOR) * (extIOR / intIOR);
    diffuse = textures.color(props, "diffuseReflectance", Color3f(0.5f));
    specular = textures.color(props, "specularReflectance", Color3f(1.0f));
    nonlinear = props.getBoolean("nonlinear", false);
    const float diffuseMean = diffuse->average().getLuminance();
    const float specularMean = specular->average().getLuminance();
    specularSamplingWeight =
        diffuseMean + specularMean > 0.0f ? specularMean / (diffuseMean + specularMean) : 0.5f;
}

float PlasticLayers::specularProbability(float share) const {
    const float toSpecular = share * specularSamplingWeight;
    const float toDiffuse = (1.0f - share) * (1.0f - specularSamplingWeight);
    return toSpecular + toDiffuse > 0.0f ? toSpecular / (toSpecular + toDiffuse) : 0.0f;
}

Color3f PlasticLayers::baseReflectance(const TextureQuery &q, float fdrInternal) const {
    const Color3f rho = diffuse->eval(q).max(0.0f).min(1.0f);
    if (nonlinear)
        return rho / (Color3f(1.0f) - rho * fdrInternal);
    return rho / (1.0f - fdrInternal);
}

std::string PlasticLayers::toString() const {
    return fmt::format("intIOR={}, extIOR={}, diffuseReflectance={}, specularReflectance={}, "
                       "nonlinear={}",
                       intIOR, extIOR, diffuse->toString(), specular->toString(), nonlinear);
}

Color3f ConductorIOR::fresnel(const TextureQuery &q, float cosThetaI) const {
    // Textures may hold any value: keep η positive and k non-negative.
    const Color3f etaHere = eta->eval(q).max(1e-4f) / extIOR;
    const Color3f kHere = k->eval(q).max(0.0f) / extIOR;
    return fresnelConductor(cosThetaI, etaHere, kHere);
}

LayerRoughness::LayerRoughness(const PropertyList &props, TextureParameters &textures,
                               const std::string &plugin, const std::string &prefix) {
    auto name = [&](const char *plain, const char *prefixed) {
        return prefix.empty() ? std::string(plain) : prefix + prefixed;
    };
    const std::string both = name("roughness", "Roughness");
    const auto roughness = textures.scalar(props, both, 0.0f, 0.0f);
    m_u = props.has(name("uRoughness", "URoughness"))
              ? textures.scalar(props, name("uRoughness", "URoughness"), 0.0f, 0.0f)
              : roughness;
    m_v = props.has(name("vRoughness", "VRoughness"))
              ? textures.scalar(props, name("vRoughness", "VRoughness"), 0.0f, 0.0f)
              : roughness;
    m_remap = props.getBoolean("remapRoughness", true);
    (void)plugin;
}

layered::Microfacets LayerRoughness::at(const TextureQuery &q) const {
    return {alpha(m_u->evalFloat(q)), alpha(m_v->evalFloat(q))};
}

bool LayerRoughness::alwaysSmooth() const {
    return m_u->isConstant() && m_v->isConstant() &&
           layered::Microfacets(alpha(m_u->average().x()), alpha(m_v->average().x())).smooth();
}

std::string LayerRoughness::toString() const {
    return fmt::format("roughness=({}, {}), remapRoughness={}", m_u->toString(), m_v->toString(),
                       m_remap);
}

layered::WalkParameters readWalkParameters(const PropertyList &props, const std::string &plugin) {
    layered::WalkParameters walk;
    walk.thickness = props.getFloat("thickness", 0.01f);
    walk.albedo = props.getColor("albedo", Color3f(0.0f));
    walk.g = props.getFloat("g", 0.0f);
    walk.maxDepth = props.getInteger("maxDepth", 10);
    walk.samples = props.getInteger("nSamples", 1);
    if (!(walk.thickness > 0.0f) || !std::isfinite(walk.thickness))
        throw NoriException("{}: 'thickness' must be positive, got {}", plugin, walk.thickness);
    if ((walk.albedo < 0.0f).any() || (walk.albedo > 1.0f).any())
        throw NoriException("{}: 'albedo' must lie in [0, 1]", plugin);
    if (!(walk.g > -1.0f && walk.g < 1.0f))
        throw NoriException("{}: 'g' must lie in (-1, 1), got {}", plugin, walk.g);
    if (walk.maxDepth < 1 || walk.maxDepth > 1000)
        throw NoriException("{}: 'maxDepth' must lie in [1, 1000], got {}", plugin, walk.maxDepth);
    if (walk.samples < 1 || walk.samples > 1000)
        throw NoriException("{}: 'nSamples' must lie in [1, 1000], got {}", plugin, walk.samples);
    return walk;
}

std::string walkToString(const layered::WalkParameters &walk) {
    return fmt::format("thickness={}, albedo=({}, {}, {}), g={}, maxDepth={}, nSamples={}",
                       walk.thickness, walk.albedo.r(), walk.albedo.g(), walk.albedo.b(), walk.g,
                       walk.maxDepth, walk.samples);
}

} // namespace nori
