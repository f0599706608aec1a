// Layered BSDFs by stochastic evaluation (Guo, Hašan and Zhao 2018, "Position-Free Monte
// Carlo Simulation for Arbitrary Layered BSDFs"; PBR 4th ed. §14.3, pbrt-v4's
// LayeredBxDF): a dielectric coating over a base (diffuse or conductor), with an
// optional homogeneous medium of thickness `thickness` between them. f and the density
// have no closed form: eval() and pdf() are Monte Carlo estimates from random walks
// between the two interfaces, and sample() follows one walk and returns the ratio of its
// throughput to its density. The estimates are deterministic functions of the directions
// (their random numbers are seeded by a hash of them), so that the density an integrator
// asks for a direction is the same each time it asks: MIS weights of one path, computed
// by two strategies, still sum to one.
//
// Directions follow pbrt-v4 in this file: wo points to the viewer, wi to the light; the
// plugins (coateddiffuse, coatedconductor) map our BSDFQueryRecord's wi and wo onto them.
#pragma once

#include <nori/color.h>
#include <nori/microfacet.h>

namespace nori::layered {

/// Which way light flows (pbrt-v4's TransportMode): refraction scales radiance by 1/η²
/// but not importance.
enum class Transport { Radiance, Importance };

/// What a sample or a density may take: reflection, transmission, or both.
enum Lobes { kReflection = 1, kTransmission = 2, kAllLobes = 3 };

/// A sampled direction: f, the direction, its density (the discrete probability for a
/// specular lobe) and what kind of event it was.
struct Sample {
    Color3f f{0.0f};
    Vector3f wi = Vector3f::Zero();
    float pdf = 0.0f;
    bool reflection = true;
    bool specular = false;
    bool valid() const { return pdf > 0.0f && !(f == 0.0f).all() && wi.z() != 0.0f; }
};

/// A microfacet distribution with the height-correlated Smith shadowing pbrt-v4 uses,
/// G = 1/(1 + Λ(wo) + Λ(wi)) (Heitz 2014, eq. 99), and the density of visible normals seen
/// from either side; smooth below α = 10⁻³ (pbrt-v4's EffectivelySmooth).
class Microfacets {
public:
    Microfacets(float alphaX, float alphaY)
        : m_distribution(MicrofacetDistribution::Type::GGX, std::max(alphaX, 1e-4f),
                         std::max(alphaY, 1e-4f)),
          m_smooth(std::max(alphaX, alphaY) < 1e-3f) {}
    bool smooth() const { return m_smooth; }
    float D(const Vector3f &m) const { return m_distribution.D(m); }
    float G(const Vector3f &wo, const Vector3f &wi) const {
        return 1.0f / (1.0f + m_distribution.lambda(wo) + m_distribution.lambda(wi));
    }
    /// D_w(m) = G1(w) max(0, ... ) |w·m| D(m)/|cos θw|, for w on either side.
    float visibleDensity(const Vector3f &w, const Vector3f &m) const;
    /// A visible normal (z > 0) seen from w, w on either side.
    Vector3f sampleVisible(const Vector3f &w, const Point2f &u) const;

private:
    MicrofacetDistribution m_distribution;
    bool m_smooth;
};

/// A dielectric interface of relative index eta (inside over outside), smooth or rough
/// (pbrt-v4's DielectricBxDF).
class Dielectric {
public:
    Dielectric(float eta, const Microfacets &microfacets)
        : m_eta(eta), m_microfacets(microfacets) {}
    Color3f f(const Vector3f &wo, const Vector3f &wi, Transport mode) const;
    float pdf(const Vector3f &wo, const Vector3f &wi, Transport mode, int lobes = kAllLobes) const;
    Sample sample(const Vector3f &wo, float uc, const Point2f &u, Transport mode,
                  int lobes = kAllLobes) const;
    bool specular() const { return m_eta == 1.0f || m_microfacets.smooth(); }

private:
    float m_eta;
    Microfacets m_microfacets;
};

/// A Lambertian base of reflectance R.
class Diffuse {
public:
    explicit Diffuse(const Color3f &reflectance) : m_reflectance(reflectance) {}
    Color3f f(const Vector3f &wo, const Vector3f &wi, Transport mode) const;
    float pdf(const Vector3f &wo, const Vector3f &wi, Transport mode, int lobes = kAllLobes) const;
    Sample sample(const Vector3f &wo, float uc, const Point2f &u, Transport mode,
                  int lobes = kAllLobes) const;
    bool specular() const { return false; }

private:
    Color3f m_reflectance;
};

/// A conductor base of complex index η + ik relative to the medium above it, smooth or
/// rough (pbrt-v4's ConductorBxDF).
class Conductor {
public:
    Conductor(const Color3f &eta, const Color3f &k, const Microfacets &microfacets)
        : m_eta(eta), m_k(k), m_microfacets(microfacets) {}
    Color3f f(const Vector3f &wo, const Vector3f &wi, Transport mode) const;
    float pdf(const Vector3f &wo, const Vector3f &wi, Transport mode, int lobes = kAllLobes) const;
    Sample sample(const Vector3f &wo, float uc, const Point2f &u, Transport mode,
                  int lobes = kAllLobes) const;
    bool specular() const { return m_microfacets.smooth(); }

private:
    Color3f m_eta, m_k;
    Microfacets m_microfacets;
};

/// The parameters of the walk between the layers.
struct WalkParameters {
    float thickness = 0.01f; ///< of the medium between the interfaces (σ_t = 1)
    Color3f albedo{0.0f};    ///< its single-scattering albedo (0: no medium, only absorption)
    float g = 0.0f;          ///< its Henyey–Greenstein asymmetry
    int maxDepth = 10;       ///< the most scattering events a walk follows
    int samples = 1;         ///< walks averaged by one f() or pdf() estimate
};

/// A dielectric coating over `Base`, two-sided (seen from below it is the same).
template <typename Base> class CoatedBSDF {
public:
    CoatedBSDF(const Dielectric &top, const Base &bottom, const WalkParameters &walk)
        : m_top(top), m_bottom(bottom), m_walk(walk) {}
    /// An unbiased estimate of f(wo, wi), from walks seeded by the directions.
    Color3f f(Vector3f wo, Vector3f wi, Transport mode) const;
    /// A walk's direction, with f/pdf of the walk as its weight; uc and u drive the first
    /// interface, the rest comes from a generator seeded by them.
    Sample sample(Vector3f wo, float uc, const Point2f &u, Transport mode) const;
    /// An estimate of the density of sample(), mixed with the uniform one (pbrt-v4's
    /// 0.9 and 0.1) so that it is never zero where f is not.
    float pdf(Vector3f wo, Vector3f wi, Transport mode) const;

private:
    Dielectric m_top;
    Base m_bottom;
    WalkParameters m_walk;
};

extern template class CoatedBSDF<Diffuse>;
extern template class CoatedBSDF<Conductor>;

} // namespace nori::layered
