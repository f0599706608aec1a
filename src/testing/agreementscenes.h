// The scenes of the agreement tests: the matrix every built-in estimator must pass
// (nori-agreement, ctest label `agreement`), and the battery a user's integrator is put
// through by `nori --test-plugin NAME`. Every file a scene reads (meshes, an environment
// map, textures, a density grid, a lens) is generated here, so they run anywhere.
#pragma once

#include "testing/agreement.h"

namespace nori {

/// The matrix's sky (an environment map file, written at the path given): blue above
/// the horizon, brighter toward the zenith, a dark ground, and a sun of 3×3 texels of
/// the 64×32 map, of radiance `sun`, at 40° from the zenith.
std::function<void(const std::string &path)> skyMap(float sun);

/// The agreement matrix: Cornell box, glossy plates, a sky with a sun over diffuse, rough
/// conductor and glass, spot and directional lights, a textured normal-mapped plane,
/// homogeneous and heterogeneous media with Henyey–Greenstein g = ±0.7, instanced
/// geometry, Disney at three parameter sets, a thin-lens and a realistic camera; each
/// with every integrator and sampler that applies.
std::vector<AgreementScene> agreementMatrixScenes();

/// The battery of a user's integrator (its <integrator> element): lights of very unequal
/// power, delta lights, an environment map with a sun, glossy and specular surfaces; on
/// each, the built-in integrator `referenceType` with `referenceParameters` (XML) first,
/// labelled by its type, and the integrator second ("tested"). `courseScenes`: only the scenes a course assignment's
/// integrator renders (area lights; diffuse, glossy, mirror and glass surfaces), for the
/// integrators of other quantities than radiance. `withMedia`: also the matrix's scene of
/// a homogeneous and a heterogeneous medium, with volpath first.
std::vector<AgreementScene> integratorTestScenes(const std::string &integratorXML,
                                                 bool withMedia = false,
                                                 const std::string &referenceType = "path_mis",
                                                 const std::string &referenceParameters = "",
                                                 bool courseScenes = false);

} // namespace nori
