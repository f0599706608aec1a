#include <nori/object.h>
#include <nori/plugindoc.h>
#include <nori/strutil.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace nori {

namespace {

// "color/texture": a <color> or a <texture> child of that name; "texture": a texture only.
const std::vector<std::string> kParameterTypes = {
    "boolean", "integer",   "float",   "string",        "color",        "point",
    "vector",  "transform", "texture", "color/texture", "float/texture"};

std::map<std::string, std::string> &docComments() {
    static std::map<std::string, std::string> comments;
    return comments;
}

size_t indentOf(const std::string &line) {
    const size_t indent = line.find_first_not_of(' ');
    return indent == std::string::npos ? line.size() : indent;
}

/// The comment's lines without "/*", "*/" and the " * " margin.
std::vector<std::string> commentLines(const std::string &comment) {
    const size_t open = comment.find("/*"), close = comment.rfind("*/");
    if (open == std::string::npos || close == std::string::npos || close < open + 2)
        throw NoriException("a doc comment is a /* ... */ block");
    std::istringstream in(comment.substr(open + 2, close - open - 2));
    std::vector<std::string> lines;
    std::string line;
    while (std::getline(in, line)) {
        const size_t star = line.find_first_not_of(" \t");
        if (star != std::string::npos && line[star] == '*') {
            line = line.substr(star + 1);
            if (!line.empty() && line[0] == ' ')
                line.erase(0, 1);
        }
        lines.push_back(line.find_first_not_of(" \t\r") == std::string::npos ? "" : line);
    }
    while (!lines.empty() && lines.front().empty())
        lines.erase(lines.begin());
    while (!lines.empty() && lines.back().empty())
        lines.pop_back();
    return lines;
}

/// Groups lines into paragraphs separated by blank lines.
std::vector<std::vector<std::string>> paragraphsOf(const std::vector<std::string> &lines) {
    std::vector<std::vector<std::string>> paragraphs(1);
    for (const std::string &line : lines) {
        if (line.empty()) {
            if (!paragraphs.back().empty())
                paragraphs.emplace_back();
        } else {
            paragraphs.back().push_back(line);
        }
    }
    if (paragraphs.back().empty())
        paragraphs.pop_back();
    return paragraphs;
}

/// Splits a parameter line into its columns (two or more spaces apart).
std::vector<std::string> columnsOf(const std::string &line) {
    std::vector<std::string> columns;
    size_t position = 0;
    while (position < line.size()) {
        size_t gap = line.find("  ", position);
        if (gap == std::string::npos)
            gap = line.size();
        columns.push_back(line.substr(position, gap - position));
        position = line.find_first_not_of(' ', gap);
        if (position == std::string::npos)
            break;
    }
    return columns;
}

ParameterDoc parseParameterLine(const std::string &line) {
    const std::vector<std::string> columns = columnsOf(trim(line));
    if (columns.size() < 4)
        throw NoriException("parameter line '{}' needs four columns two spaces apart: name, "
                            "type, default, meaning",
                            trim(line));
    ParameterDoc parameter;
    for (const std::string &name : tokenize(columns[0], ", ")) {
        // An XML name: a letter or '_', then letters, digits or '_'. Anything else is a
        // line broken in the wrong place (a reflowed comment) read as a parameter.
        const bool identifier =
            (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
            std::all_of(name.begin(), name.end(), [](char c) {
                return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
            });
        if (!identifier)
            throw NoriException("parameter line '{}' names '{}', which is not a parameter name "
                                "(a letter, then letters, digits or '_'): is it the end of the "
                                "line above, wrapped?",
                                trim(line), name);
        parameter.names.push_back(name);
    }
    parameter.type = columns[1];
    parameter.defaultValue = columns[2];
    for (size_t i = 3; i < columns.size(); ++i)
        parameter.meaning += (i > 3 ? "  " : "") + columns[i];
    if (std::find(kParameterTypes.begin(), kParameterTypes.end(), parameter.type) ==
        kParameterTypes.end())
        throw NoriException("parameter '{}' has the type '{}', not one of {}", columns[0],
                            parameter.type, fmt::join(kParameterTypes, " "));
    return parameter;
}

/// The paragraph as one example: its lines without their common indentation.
std::string exampleOf(const std::vector<std::string> &paragraph) {
    size_t indent = std::string::npos;
    for (const std::string &line : paragraph)
        indent = std::min(indent, indentOf(line));
    std::string example;
    for (const std::string &line : paragraph)
        example += line.substr(indent) + "\n";
    return example;
}

/// Text up to the end of its first sentence: a period followed by a space and a capital
/// letter, or the end.
std::string firstSentence(const std::string &text) {
    for (size_t i = 0; i + 2 < text.size(); ++i)
        if (text[i] == '.' && text[i + 1] == ' ' &&
            std::isupper(static_cast<unsigned char>(text[i + 2])))
            return text.substr(0, i + 1);
    return text;
}

} // namespace

bool PluginDoc::documents(const std::string &parameter) const {
    for (const ParameterDoc &doc : parameters)
        if (std::find(doc.names.begin(), doc.names.end(), parameter) != doc.names.end())
            return true;
    return false;
}

PluginDoc parsePluginDoc(const std::string &comment) {
    PluginDoc doc;
    const std::vector<std::string> lines = commentLines(comment);
    for (const std::string &line : lines)
        doc.text += line + "\n";
    const auto paragraphs = paragraphsOf(lines);
    if (paragraphs.empty())
        throw NoriException("the doc comment is empty");

    // "name — what it models ...": the first paragraph.
    std::string first;
    for (const std::string &line : paragraphs[0])
        first += (first.empty() ? "" : " ") + trim(line);
    const std::string dash = "\xE2\x80\x94"; // U+2014 EM DASH
    const size_t separator = first.find(" " + dash + " ");
    if (separator == std::string::npos || separator == 0)
        throw NoriException("the doc comment must start with 'name — what it models', not '{}'",
                            first.substr(0, 60));
    doc.name = first.substr(0, separator);
    doc.summary = firstSentence(first.substr(separator + dash.size() + 2));

    bool inParameters = false, sawParameters = false;
    for (size_t p = 1; p < paragraphs.size(); ++p) {
        const std::vector<std::string> &paragraph = paragraphs[p];
        const std::string head = trim(paragraph[0]);
        if (head == "Parameters:") {
            inParameters = sawParameters = true;
            for (size_t i = 1; i < paragraph.size(); ++i) {
                if (indentOf(paragraph[i]) > 2 && !doc.parameters.empty())
                    doc.parameters.back().meaning += " " + trim(paragraph[i]);
                else
                    doc.parameters.push_back(parseParameterLine(paragraph[i]));
            }
        } else if (head.rfind("No parameters", 0) == 0) {
            sawParameters = true;
            inParameters = false;
        } else if (head.rfind("Also registered as:", 0) == 0) {
            std::string names;
            for (const std::string &line : paragraph)
                names += " " + trim(line);
            names = names.substr(names.find(':') + 1);
            for (const std::string &alias : tokenize(names, ", ."))
                doc.aliases.push_back(alias);
            inParameters = false;
        } else if (head.rfind("Exempt from the sampling test:", 0) == 0) {
            std::string reason;
            for (const std::string &line : paragraph)
                reason += (reason.empty() ? "" : " ") + trim(line);
            doc.exemption =
                trim(reason.substr(std::string("Exempt from the sampling test:").size()));
            inParameters = false;
        } else if (head[0] == '<') {
            doc.examples.push_back(exampleOf(paragraph));
            inParameters = false;
        } else if (inParameters && indentOf(paragraph[0]) == 2) {
            for (const std::string &line : paragraph) {
                if (indentOf(line) > 2 && !doc.parameters.empty())
                    doc.parameters.back().meaning += " " + trim(line);
                else
                    doc.parameters.push_back(parseParameterLine(line));
            }
        } else {
            inParameters = false;
        }
    }
    if (!sawParameters)
        throw NoriException("the doc comment of '{}' has neither 'Parameters:' nor 'No parameters'",
                            doc.name);
    return doc;
}

bool registerDocComments(const std::vector<std::pair<const char *, const char *>> &files) noexcept {
    try {
        for (const auto &[file, comment] : files)
            docComments()[file] = comment;
        return true;
    } catch (...) {
        return false;
    }
}

bool isShippedPlugin(NoriObject::EClassType type, const std::string &name) {
    return NoriObjectFactory::isShippedFile(NoriObjectFactory::entry(type, name).sourceFile);
}

const char *const kUndocumentedHint =
    "undocumented: its file starts with no doc comment, so it has no parameter list, and the "
    "sampling tests of a BSDF, phase function or emitter use its default parameters only "
    "(an integrator is tested all the same); docs/nori2.md says how to write one";

std::string docCommentOf(NoriObject::EClassType type, const std::string &name) {
    const auto it = docComments().find(NoriObjectFactory::entry(type, name).sourceFile);
    return it == docComments().end() ? "" : it->second;
}

} // namespace nori

namespace nori {

std::string shortSourcePath(const std::string &sourceFile) {
    for (const char *root : {"/plugins/", "/tests/", "/docs/"}) {
        const size_t position = sourceFile.rfind(root);
        if (position != std::string::npos)
            return sourceFile.substr(position + 1);
    }
    return sourceFile;
}

const std::vector<ParameterDoc> &commonParameters(NoriObject::EClassType type) {
    static const std::vector<ParameterDoc> none;
    static const std::vector<ParameterDoc> integrator = {
        {{"aovs"},
         "string",
         "\"\"",
         "AOV layers written beside the beauty in the EXR: a list of albedo, normal, depth, "
         "position, sampleCount, variance, emission (nori --aovs adds more)"}};
    static const std::vector<ParameterDoc> sampler = {
        {{"sampleCount"}, "integer", "1", "samples per pixel (nori --spp overrides it)"},
        {{"seed"}, "integer", "0", "selects another set of sample sequences"},
        {{"maxTolerance"},
         "float",
         "0",
         "adaptive sampling: after minSamples and after every pass, a pixel stops once "
         "1.96·σ/√n of its luminance is at most maxTolerance·μ, σ and μ measured on "
         "separate decision samples (a quarter as many) so the image stays unbiased (0: off)"},
        {{"minSamples"}, "integer", "16", "adaptive sampling: samples before a pixel may stop"}};
    static const std::vector<ParameterDoc> shape = {
        {{"alpha"},
         "float/texture",
         "1",
         "opacity: below 1 the surface is partly absent (an alpha mask, a leaf's cut-out); "
         "every ray passes through the holes"}};
    switch (type) {
    case NoriObject::EMesh:
        return shape;
    case NoriObject::EIntegrator:
        return integrator;
    case NoriObject::ESampler:
        return sampler;
    default:
        return none;
    }
}

} // namespace nori
