// The χ² test of a sharp reflection lobe, in half-vector coordinates. On the sphere's
// histogram (cos θ × φ, equal solid angle) a GGX lobe of α = 0.0025 (Disney's roughness
// 0.05) falls inside one bin, where nothing is tested. Here each direction wo is mapped
// to a point of the unit square through its half vector h = (wi + wo)/|wi + wo|:
//     u = w·s/(s + α²) + (1 − w)·s/(s + 1),   s = tan²θh,     v = φh / 2π,
// the mixture of the radial CDFs of GGX half vectors of width α and 1 (Walter et al.
// 2007, eq. 35): a lobe of width about α spreads over the fraction w of the square and a
// broad one (diffuse) over the rest, so both are resolved by one histogram. The density
// of the points is the direction's density times the Jacobian,
//     p(u, v) = p(wo) · 4|wo·h| / p_h(h),   p_h(h) = F′(s) / (π cos³θh),
// (reflection's dωo/dωh = 4|wo·h|, Walter et al. eq. 14), so the standard unit-square
// test applies unchanged. Reflection only: a sample below the surface is outside the
// domain, and fails the test.
#pragma once

#include <nori/chisquare.h>

namespace nori {

/// `reflection` (directions of the local upper hemisphere sampled for the incident
/// direction `wi`, as bsdfRoutine gives them) as points of the unit square in half-vector
/// coordinates of width `alpha`, the lobe taking the fraction `sharpShare` of the square.
SamplingRoutine halfVectorRoutine(const SamplingRoutine &reflection, const Vector3f &wi,
                                  double alpha, double sharpShare = 0.5);

} // namespace nori
