// Reads Nori 2 XML scene and test files (plus our extensions: id/ref, include, default,
// $name substitution, named children) into activated objects.
#pragma once

#include <nori/object.h>

#include <map>

namespace nori {

using Defines = std::map<std::string, std::string>;

/// Loads the XML file and returns its activated root object (a scene or a test).
/// `defines` set $name variables and win over <default> elements. Every error is a
/// NoriException whose message starts with "file:line:col: ".
std::shared_ptr<NoriObject> loadFromXML(const std::string &filename, const Defines &defines = {});
/// As loadFromXML, for XML text; relative file names resolve against `directory`.
std::shared_ptr<NoriObject> loadFromXMLString(const std::string &xml,
                                              const std::string &directory = ".",
                                              const Defines &defines = {});

} // namespace nori
