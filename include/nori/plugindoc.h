// The doc comment at the top of every plugin file, embedded in the programs by the
// build: what `nori --list-plugins NAME` prints, what docs/plugins.md is made of, and
// where the automatic tests find each plugin's examples. Its format:
//
//   /*
//    * name — one sentence on what it models (the reference, in one line).
//    * More description, any number of lines.
//    *
//    * Parameters:                               (or: "No parameters." and any text)
//    *   name     type     default   meaning
//    *                               the meaning continues, indented
//    *   a, b     color    0.5       several names may share a line
//    *
//    * Exempt from the sampling test: the reason. (optional: sampling plugins only)
//    *
//    * Also registered as: other, names.        (optional: NORI_REGISTER_ALIAS)
//    *
//    *   <bsdf type="name"> ... </bsdf>           (examples: paragraphs starting with '<')
//    */
//
// Columns of a parameter line are separated by two or more spaces.
#pragma once

#include <nori/object.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace nori {

struct ParameterDoc {
    std::vector<std::string> names; ///< usually one; "eta, k" gives two
    std::string type;               ///< boolean integer float string color point vector
                                    ///< transform texture color/texture float/texture
    std::string defaultValue;       ///< "(required)", "—" (none) or a value
    std::string meaning;
};

struct PluginDoc {
    std::string name;    ///< the first word of the comment
    std::string summary; ///< the first sentence after the dash
    std::string text;    ///< the whole comment without its " * " margin
    std::vector<ParameterDoc> parameters;
    std::vector<std::string> examples; ///< XML snippets, one object each
    std::string exemption;             ///< why the sampling test does not apply, or ""
    std::vector<std::string> aliases;  ///< other names it is registered under
    /// Whether `name` is the plugin's name or one of its aliases.
    bool names(const std::string &name) const {
        return name == this->name ||
               std::find(aliases.begin(), aliases.end(), name) != aliases.end();
    }

    /// Whether `parameter` is one of the documented names.
    bool documents(const std::string &parameter) const;
};

/// The parameters that every plugin of a kind takes, read by its base class (see
/// NoriObject::readCommonProperties) and documented once for the kind.
const std::vector<ParameterDoc> &commonParameters(NoriObject::EClassType type);

/// Parses a doc comment (the text from "/*" to "*/"). Throws NoriException saying what
/// is malformed.
PluginDoc parsePluginDoc(const std::string &comment);

/// Records the doc comments of source files (absolute paths, as __FILE__ gives them);
/// called by the code the build generates from plugins/ (scripts/embed_plugin_docs.cmake).
bool registerDocComments(const std::vector<std::pair<const char *, const char *>> &files) noexcept;

/// The doc comment of the file that registered plugin `name` (see NoriObjectFactory),
/// or "" when that file has none.
std::string docCommentOf(NoriObject::EClassType type, const std::string &name);

/// Whether plugin `name` comes from one of the project's own files (not a user's; see
/// NoriObjectFactory::registerShippedFiles); the doc test holds those to a complete doc
/// comment.
bool isShippedPlugin(NoriObject::EClassType type, const std::string &name);
/// What --list-plugins and the automatic tests say about a plugin without a doc comment.
extern const char *const kUndocumentedHint;

} // namespace nori

namespace nori {

/// A source path shortened to where "plugins/" (or "tests/") starts, for messages.
std::string shortSourcePath(const std::string &sourceFile);

} // namespace nori
