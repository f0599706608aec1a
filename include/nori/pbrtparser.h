// pbrt-v4's scene file format as its parser reads it (pbrt-v4's src/pbrt/parser.cpp and
// its file-format documentation): tokens separated by white space, `#` comments to the end
// of the line, quoted strings with C escapes, `[ ]` around lists; directives with their
// positional arguments; parameter lists of `"type name" value` or `"type name" [values]`.
// This layer only reads: it hands each directive, with its arguments and parameters and
// where it stands (file:line:column), to the importer that gives it meaning.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace nori::pbrt {

/// Where a token stands: "file:line:column" (1-based).
struct Location {
    std::string file;
    int line = 1, column = 1;
    std::string str() const;
};

/// One entry of a parameter list: `"type name"` and its values, numbers (integer and
/// float types, point, vector, normal, rgb, blackbody, spectrum given as λ/value pairs),
/// strings (string, texture, spectrum by name or file) or Booleans.
struct Parameter {
    std::string type, name;
    std::vector<double> numbers;
    std::vector<std::string> strings;
    std::vector<bool> bools;
    Location location;
};

/// One directive: its name, positional arguments and parameter list.
struct Directive {
    std::string name; ///< "Shape", "Translate", "AttributeBegin", …
    /// Quoted arguments in order: the plugin type of Shape, Material, …; Texture's name,
    /// type and class; the names of NamedMaterial, MediumInterface, CoordinateSystem, …;
    /// Option's name (and its value when quoted); ActiveTransform's bare word.
    std::vector<std::string> strings;
    /// Numeric arguments: Translate's 3, Rotate's 4, LookAt's 9, Transform's 16, …;
    /// Option's value when it is a number.
    std::vector<double> numbers;
    std::vector<Parameter> parameters;
    Location location;
};

/// Reads the pbrt-v4 file at `path` (gzip-compressed when it ends in .gz) and calls
/// `visit` with each directive in order. `Include "file"` is read in place, relative to
/// the including file's folder; `Import "file"` too, between a synthetic AttributeBegin
/// and AttributeEnd (pbrt-v4 imports into a copy of the graphics state and keeps only
/// the named objects it defines). Throws LocatedError ("file:line:column: ...") for an
/// unknown directive (with a did-you-mean), a malformed argument or parameter, an
/// unterminated string or list, a file that cannot be read, Include nesting deeper than
/// 32 files or a cycle of them.
void parseFile(const std::string &path, const std::function<void(const Directive &)> &visit);

/// As parseFile, from text named `name` in messages; Include and Import are errors.
void parseString(std::string_view text, const std::string &name,
                 const std::function<void(const Directive &)> &visit);

/// The directives pbrt-v4 knows, for messages and tests.
const std::vector<std::string> &directiveNames();

} // namespace nori::pbrt
