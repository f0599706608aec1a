// Fresnel reflectance and the reflection/refraction laws, shared by every BSDF (PBR 4th
// ed. §9.3–9.5). Directions are in the local shading frame (normal +z).
#pragma once

#include <nori/color.h>
#include <nori/vector.h>

namespace nori {

/// Unpolarised Fresnel reflectance of a dielectric interface for light arriving with
/// cos θi (negative: from the interior side), as in Nori's fresnel(). 1 under total
/// internal reflection.
float fresnelDielectric(float cosThetaI, float extIOR, float intIOR);

/// Fresnel reflectance of a conductor with complex index η + ik per channel, relative to
/// the outside medium (PBR 4th ed. eq. 9.23, the exact unpolarised form).
Color3f fresnelConductor(float cosThetaI, const Color3f &eta, const Color3f &k);

/// η and k (RGB, relative to air) of a named metal: "Au", "Ag", "Cu", "Al" (Mitsuba 0.5's
/// RGB fits of measured spectra), "CuZn" (brass), "MgO", "TiO2" (pbrt-v4's measured
/// spectra in RGB, spectrum.h), every other `material` name of Mitsuba 0.6 ("Cr", "W",
/// "Ni_palik", "a-C", …: its measured spectra in RGB alike) and "none" (η = 0, k = 1: a
/// perfect mirror). Throws NoriException listing the names otherwise.
void lookupConductor(const std::string &name, Color3f &eta, Color3f &k);

/// The Fresnel diffuse reflectance F_dr(η) = 2 ∫₀¹ F(μ) μ dμ: the fraction of light arriving
/// with a cosine-weighted (diffuse) distribution that a smooth interface of relative index
/// η = η_t/η_i reflects (d'Eon and Irving 2011, eq. 6). Integrated numerically (Simpson's
/// rule on 4096 intervals past the critical angle; error below 1e-6), as Mitsuba 0.6 does
/// by default.
float fresnelDiffuseReflectance(float eta);

/// The index of refraction of a named dielectric, from Mitsuba 0.6's table ("vacuum",
/// "air", "water", "bk7", "polypropylene", "diamond", ...; Mitsuba's documentation,
/// "dielectric"). Throws NoriException listing the names otherwise.
float lookupIOR(const std::string &name);

/// Mirror reflection of w about the normal n (w pointing away from the surface),
/// renormalised: 2(w·n)n − w of float unit vectors can come out one ulp long, with a
/// z of 1.00000012 near the normal, which is no cosine.
inline Vector3f reflect(const Vector3f &w, const Vector3f &n) {
    return Vector3f(2.0f * w.dot(n) * n - w).normalized();
}

/// Refracts w (pointing away) through the interface with normal n, where eta is the
/// ratio η_t/η_i for the side w is on (n on the same side as w). Returns false under
/// total internal reflection. A template so the lens optics can run it in double.
template <typename Vector>
inline bool refract(const Vector &w, const Vector &n, typename Vector::Scalar eta, Vector &wt) {
    using Scalar = typename Vector::Scalar;
    const Scalar cosThetaI = w.dot(n);
    const Scalar sin2ThetaT = std::max(Scalar(0), Scalar(1) - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2ThetaT >= Scalar(1))
        return false;
    const Scalar cosThetaT = std::sqrt(Scalar(1) - sin2ThetaT);
    wt = Vector(-w / eta + (cosThetaI / eta - cosThetaT) * n).normalized();
    return true;
}

} // namespace nori
