#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/hash.h>
#include <nori/layeredbsdf.h>
#include <nori/pcg32.h>
#include <nori/warp.h>

#include <limits>

namespace nori::layered {

namespace {

bool sameHemisphere(const Vector3f &a, const Vector3f &b) {
    return a.z() * b.z() > 0.0f;
}

/// The power heuristic with β = 2 for one sample of each strategy (Veach 1997, §9.2.4).
float powerHeuristic(float f, float g) {
    const float f2 = f * f, g2 = g * g;
    if (std::isinf(f2))
        return 1.0f;
    return f2 + g2 > 0.0f ? f2 / (f2 + g2) : 0.0f;
}

/// Transmittance through a slab of thickness dz along w (σ_t = 1).
float transmittance(float dz, const Vector3f &w) {
    if (std::abs(dz) <= std::numeric_limits<float>::min())
        return 1.0f;
    return std::exp(-std::abs(dz / w.z()));
}

/// pbrt-v4's Refract: η is the relative index across the surface whose normal is n, which
/// may face away from wi (then 1/η applies); etap receives the index used.
bool refractThrough(const Vector3f &wi, Vector3f n, float eta, float &etap, Vector3f &wt) {
    if (n.dot(wi) < 0.0f) {
        eta = 1.0f / eta;
        n = -n;
    }
    etap = eta;
    return refract(wi, n, eta, wt);
}

/// The Henyey–Greenstein density of scattering from travelling along w into wi.
float henyeyGreenstein(const Vector3f &w, const Vector3f &wi, float g) {
    return Warp::squareToHenyeyGreensteinPdf(Frame(w).toLocal(wi), g);
}

/// A 64-bit hash of a vector's bits.
uint64_t hashDirection(const Vector3f &w) {
    return hashFloats(w.x(), w.y(), w.z());
}

/// Uniform numbers in [0, 1) for one estimate, from a generator seeded by two hashes.
class Random {
public:
    Random(uint64_t a, uint64_t b) : m_generator(a, b) {}
    float operator()() { return std::min(m_generator.nextFloat(), 0x1.fffffep-1f); }

private:
    PCG32 m_generator;
};

/// The coating (top) or the base (bottom) seen from inside the layer: the base is asked
/// with both directions negated (pbrt-v4's TopOrBottomBxDF).
template <typename Base> class Side {
public:
    Side(const Dielectric *top, const Base *bottom) : m_top(top), m_bottom(bottom) {}
    Color3f f(const Vector3f &wo, const Vector3f &wi, Transport mode) const {
        return m_top ? m_top->f(wo, wi, mode) : m_bottom->f(-wo, -wi, mode);
    }
    float pdf(const Vector3f &wo, const Vector3f &wi, Transport mode, int lobes = kAllLobes) const {
        return m_top ? m_top->pdf(wo, wi, mode, lobes) : m_bottom->pdf(-wo, -wi, mode, lobes);
    }
    Sample sample(const Vector3f &wo, float uc, const Point2f &u, Transport mode,
                  int lobes = kAllLobes) const {
        if (m_top)
            return m_top->sample(wo, uc, u, mode, lobes);
        Sample s = m_bottom->sample(-wo, uc, u, mode, lobes);
        s.wi = -s.wi;
        return s;
    }
    bool specular() const { return m_top ? m_top->specular() : m_bottom->specular(); }

private:
    const Dielectric *m_top;
    const Base *m_bottom;
};

Transport flip(Transport mode) {
    return mode == Transport::Radiance ? Transport::Importance : Transport::Radiance;
}

} // namespace

// ------------------------------------------------------------------------ Microfacets

float Microfacets::visibleDensity(const Vector3f &w, const Vector3f &m) const {
    const float cosTheta = std::abs(w.z());
    if (cosTheta == 0.0f)
        return 0.0f;
    const float g1 = 1.0f / (1.0f + m_distribution.lambda(w));
    return g1 / cosTheta * m_distribution.D(m) * std::abs(w.dot(m));
}

Vector3f Microfacets::sampleVisible(const Vector3f &w, const Point2f &u) const {
    // Heitz 2018's sampler sees from above: a direction from below sees the same
    // normals as its mirror image through the origin.
    return m_distribution.sampleNormal(w.z() < 0.0f ? Vector3f(-w) : w, u);
}

// ------------------------------------------------------------------------- Dielectric

Color3f Dielectric::f(const Vector3f &wo, const Vector3f &wi, Transport mode) const {
    if (specular())
        return Color3f(0.0f);
    // The generalised half vector (Walter et al. 2007, eq. 16), facing +z.
    const float cosO = wo.z(), cosI = wi.z();
    const bool reflect = cosI * cosO > 0.0f;
    const float etap = reflect ? 1.0f : (cosO > 0.0f ? m_eta : 1.0f / m_eta);
    Vector3f wm = wi * etap + wo;
    if (cosI == 0.0f || cosO == 0.0f || wm.squaredNorm() == 0.0f)
        return Color3f(0.0f);
    wm.normalize();
    if (wm.z() < 0.0f)
        wm = -wm;
    // Back-facing microfacets do not count.
    if (wm.dot(wi) * cosI < 0.0f || wm.dot(wo) * cosO < 0.0f)
        return Color3f(0.0f);
    const float F = fresnelDielectric(wo.dot(wm), 1.0f, m_eta);
    if (reflect)
        return Color3f(m_microfacets.D(wm) * m_microfacets.G(wo, wi) * F /
                       std::abs(4.0f * cosI * cosO));
    const float denominator =
        (wi.dot(wm) + wo.dot(wm) / etap) * (wi.dot(wm) + wo.dot(wm) / etap) * cosI * cosO;
    float ft = m_microfacets.D(wm) * (1.0f - F) * m_microfacets.G(wo, wi) *
               std::abs(wi.dot(wm) * wo.dot(wm) / denominator);
    // Radiance is compressed by η² crossing into the denser medium (PBR 4th ed. §9.5.2).
    if (mode == Transport::Radiance)
        ft /= etap * etap;
    return Color3f(ft);
}

float Dielectric::pdf(const Vector3f &wo, const Vector3f &wi, Transport, int lobes) const {
    if (specular())
        return 0.0f;
    const float cosO = wo.z(), cosI = wi.z();
    const bool reflect = cosI * cosO > 0.0f;
    const float etap = reflect ? 1.0f : (cosO > 0.0f ? m_eta : 1.0f / m_eta);
    Vector3f wm = wi * etap + wo;
    if (cosI == 0.0f || cosO == 0.0f || wm.squaredNorm() == 0.0f)
        return 0.0f;
    wm.normalize();
    if (wm.z() < 0.0f)
        wm = -wm;
    if (wm.dot(wi) * cosI < 0.0f || wm.dot(wo) * cosO < 0.0f)
        return 0.0f;
    const float R = fresnelDielectric(wo.dot(wm), 1.0f, m_eta), T = 1.0f - R;
    const float pr = (lobes & kReflection) ? R : 0.0f, pt = (lobes & kTransmission) ? T : 0.0f;
    if (pr == 0.0f && pt == 0.0f)
        return 0.0f;
    if (reflect)
        return m_microfacets.visibleDensity(wo, wm) / (4.0f * std::abs(wo.dot(wm))) * pr /
               (pr + pt);
    const float denominator = (wi.dot(wm) + wo.dot(wm) / etap) * (wi.dot(wm) + wo.dot(wm) / etap);
    const float jacobian = std::abs(wi.dot(wm)) / denominator;
    return m_microfacets.visibleDensity(wo, wm) * jacobian * pt / (pr + pt);
}

Sample Dielectric::sample(const Vector3f &wo, float uc, const Point2f &u, Transport mode,
                          int lobes) const {
    Sample s;
    if (specular()) {
        // Specular reflection with probability R/(R + T), else refraction.
        const float R = fresnelDielectric(wo.z(), 1.0f, m_eta), T = 1.0f - R;
        const float pr = (lobes & kReflection) ? R : 0.0f, pt = (lobes & kTransmission) ? T : 0.0f;
        if (pr == 0.0f && pt == 0.0f)
            return s;
        s.specular = true;
        if (uc < pr / (pr + pt)) {
            s.wi = Vector3f(-wo.x(), -wo.y(), wo.z());
            s.f = Color3f(R / std::abs(s.wi.z()));
            s.pdf = pr / (pr + pt);
            return s;
        }
        float etap;
        if (!refractThrough(wo, Vector3f(0, 0, 1), m_eta, etap, s.wi))
            return {};
        float ft = T / std::abs(s.wi.z());
        if (mode == Transport::Radiance)
            ft /= etap * etap;
        s.f = Color3f(ft);
        s.pdf = pt / (pr + pt);
        s.reflection = false;
        return s;
    }
    const Vector3f wm = m_microfacets.sampleVisible(wo, u);
    const float R = fresnelDielectric(wo.dot(wm), 1.0f, m_eta), T = 1.0f - R;
    const float pr = (lobes & kReflection) ? R : 0.0f, pt = (lobes & kTransmission) ? T : 0.0f;
    if (pr == 0.0f && pt == 0.0f)
        return s;
    if (uc < pr / (pr + pt)) {
        s.wi = reflect(wo, wm);
        if (!sameHemisphere(wo, s.wi))
            return {};
        s.pdf =
            m_microfacets.visibleDensity(wo, wm) / (4.0f * std::abs(wo.dot(wm))) * pr / (pr + pt);
        s.f = Color3f(m_microfacets.D(wm) * m_microfacets.G(wo, s.wi) * R /
                      (4.0f * s.wi.z() * wo.z()));
        return s;
    }
    float etap;
    if (!refractThrough(wo, wm, m_eta, etap, s.wi) || sameHemisphere(wo, s.wi) || s.wi.z() == 0.0f)
        return {};
    const float denominator =
        (s.wi.dot(wm) + wo.dot(wm) / etap) * (s.wi.dot(wm) + wo.dot(wm) / etap);
    const float jacobian = std::abs(s.wi.dot(wm)) / denominator;
    s.pdf = m_microfacets.visibleDensity(wo, wm) * jacobian * pt / (pr + pt);
    float ft = T * m_microfacets.D(wm) * m_microfacets.G(wo, s.wi) *
               std::abs(s.wi.dot(wm) * wo.dot(wm) / (s.wi.z() * wo.z() * denominator));
    if (mode == Transport::Radiance)
        ft /= etap * etap;
    s.f = Color3f(ft);
    s.reflection = false;
    return s;
}

// ---------------------------------------------------------------------------- Diffuse

Color3f Diffuse::f(const Vector3f &wo, const Vector3f &wi, Transport) const {
    return sameHemisphere(wo, wi) ? Color3f(m_reflectance * kInvPi) : Color3f(0.0f);
}

float Diffuse::pdf(const Vector3f &wo, const Vector3f &wi, Transport, int lobes) const {
    if (!(lobes & kReflection) || !sameHemisphere(wo, wi))
        return 0.0f;
    return std::abs(wi.z()) * kInvPi;
}

Sample Diffuse::sample(const Vector3f &wo, float, const Point2f &u, Transport, int lobes) const {
    Sample s;
    if (!(lobes & kReflection))
        return s;
    s.wi = Warp::squareToCosineHemisphere(u);
    if (wo.z() < 0.0f)
        s.wi.z() = -s.wi.z();
    s.pdf = std::abs(s.wi.z()) * kInvPi;
    s.f = m_reflectance * kInvPi;
    return s;
}

// -------------------------------------------------------------------------- Conductor

Color3f Conductor::f(const Vector3f &wo, const Vector3f &wi, Transport) const {
    if (!sameHemisphere(wo, wi) || m_microfacets.smooth())
        return Color3f(0.0f);
    const float cosO = std::abs(wo.z()), cosI = std::abs(wi.z());
    if (cosI == 0.0f || cosO == 0.0f)
        return Color3f(0.0f);
    Vector3f wm = wi + wo;
    if (wm.squaredNorm() == 0.0f)
        return Color3f(0.0f);
    wm.normalize();
    if (wm.z() < 0.0f)
        wm = -wm;
    const Color3f F = fresnelConductor(std::abs(wo.dot(wm)), m_eta, m_k);
    return F * (m_microfacets.D(wm) * m_microfacets.G(wo, wi) / (4.0f * cosI * cosO));
}

float Conductor::pdf(const Vector3f &wo, const Vector3f &wi, Transport, int lobes) const {
    if (!(lobes & kReflection) || !sameHemisphere(wo, wi) || m_microfacets.smooth())
        return 0.0f;
    Vector3f wm = wo + wi;
    if (wm.squaredNorm() == 0.0f)
        return 0.0f;
    wm.normalize();
    if (wm.z() < 0.0f)
        wm = -wm;
    return m_microfacets.visibleDensity(wo, wm) / (4.0f * std::abs(wo.dot(wm)));
}

Sample Conductor::sample(const Vector3f &wo, float, const Point2f &u, Transport, int lobes) const {
    Sample s;
    if (!(lobes & kReflection))
        return s;
    if (m_microfacets.smooth()) {
        s.wi = Vector3f(-wo.x(), -wo.y(), wo.z());
        s.f = fresnelConductor(std::abs(s.wi.z()), m_eta, m_k) / std::abs(s.wi.z());
        s.pdf = 1.0f;
        s.specular = true;
        return s;
    }
    if (wo.z() == 0.0f)
        return s;
    const Vector3f wm = m_microfacets.sampleVisible(wo, u);
    s.wi = reflect(wo, wm);
    if (!sameHemisphere(wo, s.wi))
        return {};
    s.pdf = m_microfacets.visibleDensity(wo, wm) / (4.0f * std::abs(wo.dot(wm)));
    const float cosO = std::abs(wo.z()), cosI = std::abs(s.wi.z());
    if (cosI == 0.0f || cosO == 0.0f)
        return {};
    s.f = fresnelConductor(std::abs(wo.dot(wm)), m_eta, m_k) *
          (m_microfacets.D(wm) * m_microfacets.G(wo, s.wi) / (4.0f * cosI * cosO));
    return s;
}

// ------------------------------------------------------------------------- CoatedBSDF

template <typename Base>
Color3f CoatedBSDF<Base>::f(Vector3f wo, Vector3f wi, Transport mode) const {
    // Two-sided: seen from below, the same as from above.
    if (wo.z() < 0.0f) {
        wo = -wo;
        wi = -wi;
    }
    const Side<Base> top(&m_top, nullptr), bottom(nullptr, &m_bottom);
    // Light enters through the top; it leaves through the top (reflection) or the base.
    const bool reflection = sameHemisphere(wo, wi);
    const Side<Base> &exit = reflection ? top : bottom, &nonExit = reflection ? bottom : top;
    const float thickness = m_walk.thickness, exitZ = reflection ? thickness : 0.0f;
    const int samples = m_walk.samples;

    Color3f f(0.0f);
    // Reflection at the entrance interface itself.
    if (reflection)
        f = float(samples) * m_top.f(wo, wi, mode);

    Random r(hashDirection(wo), hashDirection(wi));
    for (int s = 0; s < samples; ++s) {
        // Into the layer through the entrance, and a direction through the exit toward wi
        // (a virtual light, for next-event estimation inside the layer).
        float uc = r();
        const Sample wos = top.sample(wo, uc, Point2f(r(), r()), mode, kTransmission);
        if (!wos.valid())
            continue;
        uc = r();
        const Sample wis = exit.sample(wi, uc, Point2f(r(), r()), flip(mode), kTransmission);
        if (!wis.valid())
            continue;

        Color3f beta = wos.f * std::abs(wos.wi.z()) / wos.pdf;
        float z = thickness;
        Vector3f w = wos.wi;
        for (int depth = 0; depth < m_walk.maxDepth; ++depth) {
            // Russian roulette once the walk has lost most of its weight.
            if (depth > 3 && beta.maxCoeff() < 0.25f) {
                const float q = std::max(0.0f, 1.0f - beta.maxCoeff());
                if (r() < q)
                    break;
                beta /= 1.0f - q;
            }
            if ((m_walk.albedo == 0.0f).all()) {
                // No medium: straight to the other interface.
                z = (z == thickness) ? 0.0f : thickness;
                beta *= transmittance(thickness, w);
            } else {
                // A free flight in the medium (σ_t = 1).
                const float dz = -std::log(1.0f - r()) * std::abs(w.z());
                const float zp = w.z() > 0.0f ? z + dz : z - dz;
                if (zp == z)
                    continue;
                if (0.0f < zp && zp < thickness) {
                    // Scattering in the medium: next-event estimation through the exit...
                    float weight = 1.0f;
                    if (!exit.specular())
                        weight = powerHeuristic(wis.pdf, henyeyGreenstein(w, -wis.wi, m_walk.g));
                    f += beta * m_walk.albedo * henyeyGreenstein(w, -wis.wi, m_walk.g) * weight *
                         transmittance(zp - exitZ, wis.wi) * wis.f / wis.pdf;
                    // ... then a new direction from the phase function.
                    const Vector3f local =
                        Warp::squareToHenyeyGreenstein(Point2f(r(), r()), m_walk.g);
                    const Vector3f scattered = Frame(w).toWorld(local);
                    const float phasePdf = henyeyGreenstein(w, scattered, m_walk.g);
                    if (phasePdf == 0.0f || scattered.z() == 0.0f)
                        continue;
                    beta *= m_walk.albedo; // the phase function's weight p/pdf is 1
                    w = scattered;
                    z = zp;
                    // ... and the light the new direction reaches through the exit.
                    if (((z < exitZ && w.z() > 0.0f) || (z > exitZ && w.z() < 0.0f)) &&
                        !exit.specular()) {
                        const Color3f fExit = exit.f(-w, wi, mode);
                        if (!(fExit == 0.0f).all()) {
                            // The other strategy's density for this direction: that of
                            // drawing −w from wi, as wis was drawn (see below).
                            const float exitPdf = exit.pdf(wi, -w, flip(mode), kTransmission);
                            f += beta * transmittance(zp - exitZ, w) * fExit *
                                 powerHeuristic(phasePdf, exitPdf);
                        }
                    }
                    continue;
                }
                z = std::clamp(zp, 0.0f, thickness);
            }
            if (z == exitZ) {
                // Reflection back into the layer at the exit interface.
                const float ucExit = r();
                const Sample bs = exit.sample(-w, ucExit, Point2f(r(), r()), mode, kReflection);
                if (!bs.valid())
                    break;
                beta *= bs.f * std::abs(bs.wi.z()) / bs.pdf;
                w = bs.wi;
            } else {
                // Scattering at the other interface: next-event estimation toward wis ...
                if (!nonExit.specular()) {
                    float weight = 1.0f;
                    if (!exit.specular())
                        weight = powerHeuristic(wis.pdf, nonExit.pdf(-w, -wis.wi, mode));
                    f += beta * nonExit.f(-w, -wis.wi, mode) * std::abs(wis.wi.z()) * weight *
                         transmittance(thickness, wis.wi) * wis.f / wis.pdf;
                }
                // ... then a reflected direction, and the light it reaches through the exit.
                const float ucNon = r();
                const Sample bs = nonExit.sample(-w, ucNon, Point2f(r(), r()), mode, kReflection);
                if (!bs.valid())
                    break;
                beta *= bs.f * std::abs(bs.wi.z()) / bs.pdf;
                w = bs.wi;
                if (!exit.specular()) {
                    const Color3f fExit = exit.f(-w, wi, mode);
                    if (!(fExit == 0.0f).all()) {
                        // MIS with the next-event estimate above, which draws the inner
                        // direction from wi (wis): its density for −w is exit.pdf(wi, −w).
                        // (pbrt-v4 weighs by exit.pdf(−w, wi), the reverse density, which
                        // differs across a rough refraction: its weights then do not sum
                        // to one, and f comes out 1–5 % off; tests/test_coated.cpp.)
                        float weight = 1.0f;
                        if (!nonExit.specular())
                            weight =
                                powerHeuristic(bs.pdf, exit.pdf(wi, -w, flip(mode), kTransmission));
                        f += beta * transmittance(thickness, bs.wi) * fExit * weight;
                    }
                }
            }
        }
    }
    return f / float(samples);
}

template <typename Base>
Sample CoatedBSDF<Base>::sample(Vector3f wo, float uc, const Point2f &u, Transport mode) const {
    const bool flipped = wo.z() < 0.0f;
    if (flipped)
        wo = -wo;
    // The entrance: reflected there, the walk is over before it starts.
    Sample bs = m_top.sample(wo, uc, u, mode);
    if (!bs.valid())
        return {};
    if (bs.reflection) {
        if (flipped)
            bs.wi = -bs.wi;
        return bs;
    }
    Vector3f w = bs.wi;
    Random r(hashDirection(wo), hashDirection(Vector3f(uc, u.x(), u.y())));
    Color3f f = bs.f * std::abs(bs.wi.z());
    float pdf = bs.pdf;
    float z = m_walk.thickness;
    const bool medium = !(m_walk.albedo == 0.0f).all();
    for (int depth = 0; depth < m_walk.maxDepth; ++depth) {
        const float rouletteBeta = f.maxCoeff() / pdf;
        if (depth > 3 && rouletteBeta < 0.25f) {
            const float q = std::max(0.0f, 1.0f - rouletteBeta);
            if (r() < q)
                return {};
            pdf *= 1.0f - q;
        }
        if (w.z() == 0.0f)
            return {};
        if (medium) {
            const float dz = -std::log(1.0f - r()) * std::abs(w.z());
            const float zp = w.z() > 0.0f ? z + dz : z - dz;
            if (zp == z)
                return {};
            if (0.0f < zp && zp < m_walk.thickness) {
                const Vector3f local = Warp::squareToHenyeyGreenstein(Point2f(r(), r()), m_walk.g);
                const Vector3f scattered = Frame(w).toWorld(local);
                const float phase = henyeyGreenstein(w, scattered, m_walk.g);
                if (phase == 0.0f || scattered.z() == 0.0f)
                    return {};
                f *= m_walk.albedo * phase;
                pdf *= phase;
                w = scattered;
                z = zp;
                continue;
            }
            z = std::clamp(zp, 0.0f, m_walk.thickness);
        } else {
            z = (z == m_walk.thickness) ? 0.0f : m_walk.thickness;
            f *= transmittance(m_walk.thickness, w);
        }
        const Side<Base> side =
            z == 0.0f ? Side<Base>(nullptr, &m_bottom) : Side<Base>(&m_top, nullptr);
        const float ucInterface = r();
        const Sample next = side.sample(-w, ucInterface, Point2f(r(), r()), mode);
        if (!next.valid())
            return {};
        f *= next.f;
        pdf *= next.pdf;
        w = next.wi;
        if (!next.reflection) {
            // Out of the layers: a glossy event (its density is that of this walk).
            Sample out;
            out.f = f;
            out.wi = flipped ? Vector3f(-w) : w;
            out.pdf = pdf;
            out.reflection = sameHemisphere(wo, w);
            out.specular = false;
            return out;
        }
        f *= std::abs(next.wi.z());
    }
    return {};
}

template <typename Base>
float CoatedBSDF<Base>::pdf(Vector3f wo, Vector3f wi, Transport mode) const {
    if (wo.z() < 0.0f) {
        wo = -wo;
        wi = -wi;
    }
    Random r(hashDirection(wi), hashDirection(wo));
    const int samples = m_walk.samples;
    float pdfSum = 0.0f;
    const bool reflection = sameHemisphere(wo, wi);
    if (reflection)
        pdfSum += float(samples) * m_top.pdf(wo, wi, mode, kReflection);
    const Side<Base> top(&m_top, nullptr), bottom(nullptr, &m_bottom);
    for (int s = 0; s < samples; ++s) {
        if (reflection) {
            // The TRT term: in through the top, off the base, out through the top.
            const Side<Base> &rInterface = bottom, &tInterface = top;
            const float uc1 = r();
            const Point2f u1(r(), r());
            const Sample wos = tInterface.sample(wo, uc1, u1, mode, kTransmission);
            const float uc2 = r();
            const Point2f u2(r(), r());
            const Sample wis = tInterface.sample(wi, uc2, u2, flip(mode), kTransmission);
            if (!(wos.valid() && wis.valid()))
                continue;
            if (tInterface.specular()) {
                pdfSum += rInterface.pdf(-wos.wi, -wis.wi, mode);
            } else {
                // MIS of the two ways to estimate the product of densities.
                const float uc3 = r();
                const Point2f u3(r(), r());
                const Sample rs = rInterface.sample(-wos.wi, uc3, u3, mode);
                if (!rs.valid())
                    continue;
                if (rInterface.specular()) {
                    pdfSum += tInterface.pdf(-rs.wi, wi, mode);
                } else {
                    const float rPdf = rInterface.pdf(-wos.wi, -wis.wi, mode);
                    pdfSum += powerHeuristic(wis.pdf, rPdf) * rPdf;
                    const float tPdf = tInterface.pdf(-rs.wi, wi, mode);
                    pdfSum += powerHeuristic(rs.pdf, tPdf) * tPdf;
                }
            }
        } else {
            // The TT term: through the top and the base (an opaque base never lets light
            // through, so this only counts for bases that do).
            const float uc1 = r();
            const Point2f u1(r(), r());
            const Sample wos = top.sample(wo, uc1, u1, mode);
            if (!wos.valid() || wos.reflection)
                continue;
            const float uc2 = r();
            const Point2f u2(r(), r());
            const Sample wis = bottom.sample(wi, uc2, u2, flip(mode));
            if (!wis.valid() || wis.reflection)
                continue;
            if (top.specular())
                pdfSum += bottom.pdf(-wos.wi, wi, mode);
            else if (bottom.specular())
                pdfSum += top.pdf(wo, -wis.wi, mode);
            else
                pdfSum += 0.5f * (top.pdf(wo, -wis.wi, mode) + bottom.pdf(-wos.wi, wi, mode));
        }
    }
    // A mixture with the uniform density, so that no direction f reaches has density 0.
    return 0.1f * kInvFourPi + 0.9f * pdfSum / float(samples);
}

template class CoatedBSDF<Diffuse>;
template class CoatedBSDF<Conductor>;

} // namespace nori::layered
