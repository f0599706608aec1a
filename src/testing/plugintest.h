// The automatic test of sampling plugins: every registered BSDF, phase function and
// emitter is built from the examples in its doc comment (plugindoc.h) and checked with no
// test written for it. A student's new plugin is tested the moment it compiles:
//   - χ²: sample() draws from pdf() (BSDFs at several angles, from both sides);
//   - every sample is a finite unit direction with a finite, non-negative weight;
//   - the weight sample() returns is eval·|cos θo|/pdf (f/pdf for phase functions,
//     radiance/pdf for emitters) at the direction it chose;
//   - reciprocity: f(wi, wo) = f(wo, wi), with the factor η² across a refraction;
//   - energy: a BSDF's albedo (refracted weights times η²) is at most 1;
//   - discrete lobes obey their law: mirror reflection, or refraction by Snell's law
//     with the η sample() reports; delta lights always give the same direction.
// A doc comment may exempt a plugin, with the reason ("Exempt from the sampling test:").
#pragma once

#include <string>
#include <vector>

namespace nori {

struct PluginTestOptions {
    double significanceLevel = 0.01; ///< over all χ² tests of one plugin (Šidák)
    uint64_t seed = 1;
    /// Pictures (observed | expected | difference) of χ² tests go to this folder: those
    /// of failing tests, or of all with `allPictures`. Empty: none.
    std::string pictureFolder;
    bool allPictures = false;
};

struct PluginTestResult {
    bool tested = false; ///< false: not a sampling plugin, or exempt
    bool passed = true;
    std::string report; ///< a line per check, for people
};

/// The registered BSDFs, phase functions and emitters, by name.
std::vector<std::string> samplingPlugins();

/// Tests the plugin registered as `name` from its doc examples. Throws NoriException
/// when the plugin is unknown, its doc comment is missing or malformed, or an example
/// does not load.
PluginTestResult testSamplingPlugin(const std::string &name, const PluginTestOptions &options);
/// Tests several plugins in parallel; the results are in the order of `names`.
std::vector<PluginTestResult> testSamplingPlugins(const std::vector<std::string> &names,
                                                  const PluginTestOptions &options);

} // namespace nori
