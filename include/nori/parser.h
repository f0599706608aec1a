// Reads Nori 2 XML scene and test files (plus our extensions: id/ref, include, default,
// $name substitution, named children) into activated objects.
#pragma once

#include <nori/object.h>

#include <map>
#include <vector>

namespace nori {

using Defines = std::map<std::string, std::string>;

/// How a file is read: what the command line adds to it.
struct LoadOptions {
    /// $name variables; they win over <default> elements.
    Defines defines;
    /// The `convention` ("epfl" or "eth", see convention.h) of every camera and shape
    /// that does not set its own; empty: each one's default.
    std::string convention;
    /// When set, receives the names of `defines` that no $name in the files used.
    std::vector<std::string> *unusedDefines = nullptr;

    LoadOptions() = default;
    LoadOptions(Defines defines) : defines(std::move(defines)) {} // NOLINT: implicit on purpose
};

/// Loads the XML file and returns its activated root object (a scene or a test). Every
/// error is a NoriException whose message starts with "file:line:col: ". Threads may load
/// at once: the loads take turns (Nori 2's file resolver is one per process).
std::shared_ptr<NoriObject> loadFromXML(const std::string &filename,
                                        const LoadOptions &options = {});
/// As loadFromXML, for XML text; relative file names resolve against `directory`.
std::shared_ptr<NoriObject> loadFromXMLString(const std::string &xml,
                                              const std::string &directory = ".",
                                              const LoadOptions &options = {});

} // namespace nori
