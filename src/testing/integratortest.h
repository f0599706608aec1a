// The automatic test of an integrator plugin (nori --test-plugin NAME on an integrator):
// the integrator renders a battery of small scenes (src/testing/agreementscenes.h) that
// the built-in integrator of the same quantity renders too (Integrator::quantity:
// path_mis for radiance, ao for ambient occlusion, whitted for a Whitted-style tracer,
// ...), and the means of image regions are compared in standard errors of their
// difference, from independent batches of each. A student's
// path tracer that forgets a light-selection probability, an MIS weight or a Jacobian
// disagrees on the scene that exercises it.
#pragma once

#include "testing/plugintest.h"

namespace nori {

/// Whether `name` is registered as an integrator.
bool isIntegratorPlugin(const std::string &name);

/// Tests the integrator registered as `name` (created with no parameters, or with the
/// point light or distance its quantity needs) against the built-in of its quantity; the
/// report has a line per scene and region, and names what disagrees.
PluginTestResult testIntegratorPlugin(const std::string &name, const PluginTestOptions &options);

} // namespace nori
