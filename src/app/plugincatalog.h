// The catalogue of registered plugins made from their doc comments (plugindoc.h): what
// `nori --list-plugins [KIND|NAME]` prints and what docs/plugins.md is made of.
#pragma once

#include <string>

namespace nori {

/// The registered plugins of one kind ("bsdf", ...) or of every kind (""), a line each
/// with its summary, grouped by kind: what `nori --list-plugins [KIND]` prints.
std::string pluginList(const std::string &kind = "");
/// The whole doc comment of plugin `name`, with its kind and file: what
/// `nori --list-plugins NAME` prints. Throws NoriException for unknown names.
std::string pluginReference(const std::string &name);
/// docs/plugins.md: every plugin of plugins/ with its description, parameter table
/// and examples.
std::string pluginsMarkdown();

} // namespace nori
