// Mitsuba's scene files onto our plugins, written as our XML (see mitsubaimport.h).
// Mitsuba 0.6's documentation ("Plugin reference") and Mitsuba 3's are the specification
// of what each parameter means; the table is docs/mitsuba-scenes.md.
#include <nori/mitsubaimport.h>

#include "import/xmlwriter.h"

#include <nori/common.h>
#include <nori/filesystem.h>
#include <nori/spectrum.h>
#include <nori/strutil.h>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <pugixml.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

namespace nori::mitsuba {

namespace fs = std::filesystem;
using namespace importxml;

namespace {

/// Nested <include>s deeper than this are taken for a cycle.
constexpr int kMaxIncludeDepth = 16;

// ---- Source files and locations -----------------------------------------------------

/// One file's text, for "file:line:column" of a pugixml node.
class Source {
public:
    Source(std::string path, std::string text) : m_path(std::move(path)), m_text(std::move(text)) {
        m_lineStarts.push_back(0);
        for (size_t i = 0; i < m_text.size(); ++i)
            if (m_text[i] == '\n')
                m_lineStarts.push_back(i + 1);
    }
    const std::string &path() const { return m_path; }
    const std::string &text() const { return m_text; }
    std::string directory() const { return fs::path(m_path).parent_path().string(); }

    std::string locate(const pugi::xml_node &node) const {
        ptrdiff_t offset = node.offset_debug();
        if (offset < 0)
            return m_path;
        // pugixml points at an element's name: the column of its '<', as our parser says.
        if (offset > 0 && m_text[size_t(offset) - 1] == '<')
            --offset;
        const auto line =
            std::upper_bound(m_lineStarts.begin(), m_lineStarts.end(), size_t(offset)) - 1;
        return fmt::format("{}:{}:{}", m_path, line - m_lineStarts.begin() + 1,
                           size_t(offset) - *line + 1);
    }

private:
    std::string m_path, m_text;
    std::vector<size_t> m_lineStarts;
};

// ---- What a Mitsuba element holds ---------------------------------------------------

/// Mitsuba 2/3's snake_case names in Mitsuba 0.6's camelCase ("int_ior" → "intIOR",
/// "to_world" → "toWorld", "alpha_u" → "alphaU").
std::string camelName(const std::string &name) {
    std::string result;
    bool first = true;
    for (const std::string &part : tokenize(name, "_")) {
        if (part.empty())
            continue;
        if (first)
            result += part;
        else if (part == "ior")
            result += "IOR";
        else
            result += char(std::toupper(static_cast<unsigned char>(part[0]))) + part.substr(1);
        first = false;
    }
    return result.empty() ? name : result;
}

struct Element;

/// A property or a named child of an element, as written.
struct Value {
    enum class Kind {
        Integer,
        Float,
        Boolean,
        String,
        Color,
        Point,
        Vector,
        Transform,
        Object,
        Ref
    };
    Kind kind = Kind::String;
    std::string tag;      ///< the Mitsuba element: "float", "rgb", "spectrum", "bsdf", ...
    std::string location; ///< file:line:column
    std::string text;     ///< the value attribute (numbers, strings, rgb, spectrum)
    std::map<std::string, std::string> attributes; ///< all of them, variables substituted
    pugi::xml_node node;                           ///< for <transform>: its operations
    const Source *source = nullptr;
    std::shared_ptr<Element> object; ///< Kind::Object
    std::string refId;               ///< Kind::Ref
};

/// A Mitsuba object: <bsdf type="roughplastic" id="..." name="..."> and what it holds.
struct Element {
    std::string tag, type, id, name, location;
    const Source *source = nullptr;
    std::vector<std::pair<std::string, Value>> properties; ///< by name, in file order
    std::vector<Value> children;                           ///< unnamed objects and refs
    // What the converter read (a property left unread is an error).
    mutable std::set<std::string> queried;
    mutable std::set<std::string> used;
    mutable std::vector<std::pair<std::string, std::string>> respelled; ///< (written, meant)

    const Value *find(const std::string &property) const {
        queried.insert(property);
        for (const auto &[name, value] : properties)
            if (name == property) {
                used.insert(property);
                return &value;
            }
        // The other dialect's spelling ("high_quality_edges" in a 0.5 file), as Mitsuba
        // would only warn of it: read, and warned of by the converter.
        for (const auto &[name, value] : properties)
            if (name != property && camelName(name) == property) {
                used.insert(name);
                respelled.emplace_back(name, property);
                return &value;
            }
        return nullptr;
    }
    bool has(const std::string &property) const {
        for (const auto &entry : properties)
            if (entry.first == property)
                return true;
        return false;
    }
    /// Unnamed children of one kind (<bsdf>, <emitter>, ...), refs included.
    std::vector<const Value *> childrenOf(const std::string &tag) const {
        std::vector<const Value *> result;
        for (const Value &child : children)
            if (child.tag == tag)
                result.push_back(&child);
        return result;
    }
    std::string description() const { return fmt::format("{} '{}'", tag, type); }
};

// ---- Reading the files --------------------------------------------------------------

/// The object tags of Mitsuba's format (both dialects).
const std::set<std::string> &objectTags() {
    static const std::set<std::string> tags = {
        "integrator", "sensor",  "film",   "sampler", "rfilter", "shape",     "bsdf",
        "texture",    "emitter", "medium", "phase",   "volume",  "subsurface"};
    return tags;
}
const std::set<std::string> &propertyTags() {
    static const std::set<std::string> tags = {
        "integer",   "float", "boolean", "string",    "rgb",       "srgb", "spectrum",
        "blackbody", "point", "vector",  "transform", "animation", "color"};
    return tags;
}

class Reader {
public:
    Reader(const ConvertOptions &options, std::vector<std::unique_ptr<Source>> &sources)
        : m_options(options), m_sources(sources) {}

    /// Reads the scene file at `path` with the text `text`.
    std::shared_ptr<Element> readScene(const std::string &text, const std::string &path) {
        const Source &source = addSource(path, text);
        pugi::xml_document &document = parse(source);
        const pugi::xml_node root = document.document_element();
        if (std::string(root.name()) != "scene")
            throw LocatedError(
                source.locate(root),
                fmt::format("the root element must be a <scene>, not <{}>", root.name()));
        const std::string version = root.attribute("version").value();
        if (version.empty())
            throw LocatedError(source.locate(root),
                               "a Mitsuba <scene> has a version attribute (\"0.6.0\", "
                               "\"3.0.0\"); this file is in our own format");
        m_snakeCase = version[0] >= '2' && version[0] <= '9';
        readDefaults(root, source);
        auto scene = std::make_shared<Element>();
        scene->tag = "scene";
        scene->location = source.locate(root);
        scene->source = &source;
        readChildren(root, source, *scene, 0);
        return scene;
    }

    bool snakeCase() const { return m_snakeCase; }
    std::vector<std::string> variables() const { return {m_variables.begin(), m_variables.end()}; }

private:
    const Source &addSource(const std::string &path, const std::string &text) {
        m_sources.push_back(std::make_unique<Source>(path, text));
        return *m_sources.back();
    }

    pugi::xml_document &parse(const Source &source) {
        m_documents.push_back(std::make_unique<pugi::xml_document>());
        const pugi::xml_parse_result result = m_documents.back()->load_buffer(
            source.text().data(), source.text().size(), pugi::parse_default, pugi::encoding_utf8);
        if (!result) {
            // The line and column of the byte where pugixml stopped.
            size_t line = 1, column = 1;
            for (ptrdiff_t i = 0; i < result.offset && size_t(i) < source.text().size(); ++i) {
                if (source.text()[size_t(i)] == '\n') {
                    ++line;
                    column = 1;
                } else {
                    ++column;
                }
            }
            throw LocatedError(fmt::format("{}:{}:{}", source.path(), line, column),
                               fmt::format("malformed XML: {}", result.description()));
        }
        return *m_documents.back();
    }

    /// <default name="..." value="..."/> of the scene: values of $name unless -D gave one.
    void readDefaults(const pugi::xml_node &root, const Source &source) {
        for (const pugi::xml_node &node : root.children("default")) {
            const std::string name = node.attribute("name").value();
            if (name.empty() || !node.attribute("value"))
                throw LocatedError(source.locate(node),
                                   "<default> needs a name and a value attribute");
            m_variables.insert(name);
            m_defaults.emplace(name, node.attribute("value").value());
        }
    }

    /// The attribute's value with every $name replaced (-D first, then <default>).
    std::string substitute(const std::string &text, const Source &source,
                           const pugi::xml_node &node) {
        if (text.find('$') == std::string::npos)
            return text;
        static const std::regex variable(R"(\$([A-Za-z_][A-Za-z0-9_]*))");
        std::string result;
        auto begin = std::sregex_iterator(text.begin(), text.end(), variable);
        size_t last = 0;
        for (auto it = begin; it != std::sregex_iterator(); ++it) {
            const std::string name = (*it)[1];
            m_variables.insert(name);
            result += text.substr(last, size_t(it->position()) - last);
            if (const auto defined = m_options.defines.find(name);
                defined != m_options.defines.end())
                result += defined->second;
            else if (const auto fallback = m_defaults.find(name); fallback != m_defaults.end())
                result += fallback->second;
            else
                throw LocatedError(source.locate(node),
                                   fmt::format("${} is not defined: give it with -D {}=VALUE "
                                               "or declare <default name=\"{}\" value=\"...\"/>",
                                               name, name, name));
            last = size_t(it->position() + it->length());
        }
        return result + text.substr(last);
    }

    std::map<std::string, std::string> attributesOf(const pugi::xml_node &node,
                                                    const Source &source) {
        std::map<std::string, std::string> attributes;
        for (const pugi::xml_attribute &attribute : node.attributes())
            attributes[attribute.name()] = substitute(attribute.value(), source, node);
        return attributes;
    }

    void readChildren(const pugi::xml_node &parent, const Source &source, Element &element,
                      int depth) {
        for (const pugi::xml_node &node : parent.children()) {
            if (node.type() != pugi::node_element)
                continue;
            const std::string tag = node.name();
            if (tag == "default") {
                if (element.tag != "scene")
                    throw LocatedError(source.locate(node), "<default> belongs in the <scene>");
                continue;
            }
            if (tag == "include") {
                include(node, source, element, depth);
                continue;
            }
            readChild(node, source, element);
        }
    }

    /// <include filename="part.xml"/>: the children of that file's <scene>, here.
    void include(const pugi::xml_node &node, const Source &source, Element &element, int depth) {
        if (element.tag != "scene")
            throw LocatedError(source.locate(node), "<include> belongs in the <scene>");
        if (depth >= kMaxIncludeDepth)
            throw LocatedError(
                source.locate(node),
                fmt::format("<include> nested more than {} deep (a cycle?)", kMaxIncludeDepth));
        const std::string name = substitute(node.attribute("filename").value(), source, node);
        if (name.empty())
            throw LocatedError(source.locate(node), "<include> needs a filename");
        const fs::path path = fs::path(source.directory()) / name;
        std::string text;
        try {
            text = readTextFile(path.string(), "included Mitsuba scene");
        } catch (const NoriException &error) {
            throw LocatedError(source.locate(node), error.what());
        }
        const Source &included = addSource(path.string(), text);
        const pugi::xml_node root = parse(included).document_element();
        if (std::string(root.name()) != "scene")
            throw LocatedError(included.locate(root),
                               "an included file's root element must be a <scene>");
        readDefaults(root, included);
        readChildren(root, included, element, depth + 1);
    }

    void readChild(const pugi::xml_node &node, const Source &source, Element &element) {
        const std::string tag = node.name();
        const std::string location = source.locate(node);
        Value value;
        value.tag = tag;
        value.location = location;
        value.source = &source;
        value.attributes = attributesOf(node, source);
        const auto attribute = [&](const char *name) {
            const auto it = value.attributes.find(name);
            return it == value.attributes.end() ? std::string() : it->second;
        };
        std::string name = attribute("name");
        if (m_snakeCase)
            name = camelName(name);
        if (tag == "ref") {
            value.kind = Value::Kind::Ref;
            value.refId = attribute("id");
            if (value.refId.empty())
                throw LocatedError(location, "<ref> needs an id");
        } else if (objectTags().count(tag)) {
            value.kind = Value::Kind::Object;
            auto object = std::make_shared<Element>();
            object->tag = tag;
            object->type = attribute("type");
            object->id = attribute("id");
            object->name = name;
            object->location = location;
            object->source = &source;
            if (object->type.empty())
                throw LocatedError(location, fmt::format("<{}> needs a type", tag));
            readChildren(node, source, *object, kMaxIncludeDepth);
            value.object = object;
        } else if (propertyTags().count(tag)) {
            if (name.empty())
                throw LocatedError(location, fmt::format("<{}> needs a name", tag));
            value.text = attribute("value");
            value.node = node;
            using Kind = Value::Kind;
            static const std::map<std::string, Kind> kinds = {
                {"integer", Kind::Integer},     {"float", Kind::Float},
                {"boolean", Kind::Boolean},     {"string", Kind::String},
                {"point", Kind::Point},         {"vector", Kind::Vector},
                {"transform", Kind::Transform}, {"animation", Kind::Transform}};
            const auto kind = kinds.find(tag);
            value.kind = kind == kinds.end() ? Kind::Color : kind->second;
            if (tag == "animation")
                throw LocatedError(location, "<animation> (a moving transform) is not supported: "
                                             "there is no motion blur here");
        } else {
            std::vector<std::string> known(objectTags().begin(), objectTags().end());
            known.insert(known.end(), propertyTags().begin(), propertyTags().end());
            known.insert(known.end(), {"ref", "include", "default"});
            throw LocatedError(location,
                               fmt::format("unknown element <{}>{}", tag, didYouMean(tag, known)));
        }
        if (name.empty()) {
            element.children.push_back(std::move(value));
            return;
        }
        for (const auto &entry : element.properties)
            if (entry.first == name)
                throw LocatedError(location, fmt::format("'{}' is given twice (first at {})", name,
                                                         entry.second.location));
        element.properties.emplace_back(name, std::move(value));
    }

    const ConvertOptions &m_options;
    std::vector<std::unique_ptr<Source>> &m_sources;
    std::vector<std::unique_ptr<pugi::xml_document>> m_documents;
    std::map<std::string, std::string> m_defaults;
    std::set<std::string> m_variables;
    bool m_snakeCase = false;
};

// ---- Values -------------------------------------------------------------------------

/// How a colour is meant, which decides how a spectrum becomes RGB (mitsubaimport.h).
enum class Intent { Reflectance, Illuminant };

float parseFloat(const std::string &text, const std::string &location, const std::string &what) {
    try {
        return toFloat(trim(text), what);
    } catch (const NoriException &error) {
        throw LocatedError(location, error.what());
    }
}

/// Numbers separated by commas and/or spaces.
std::vector<float> parseNumbers(const std::string &text, const std::string &location,
                                const std::string &what) {
    std::vector<float> numbers;
    for (const std::string &token : tokenize(text, ", \t\r\n"))
        if (!token.empty())
            numbers.push_back(parseFloat(token, location, what));
    return numbers;
}

/// "#rrggbb" (or "#rgb"), decoded from sRGB.
Color3f hexColor(const std::string &text, const std::string &location) {
    std::string digits = text.substr(1);
    if (digits.size() == 3)
        digits = {digits[0], digits[0], digits[1], digits[1], digits[2], digits[2]};
    if (digits.size() != 6 ||
        digits.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
        throw LocatedError(location, fmt::format("'{}' is not a colour #rrggbb", text));
    Color3f color;
    for (int i = 0; i < 3; ++i)
        color[i] = float(std::stoi(digits.substr(2 * size_t(i), 2), nullptr, 16)) / 255.0f;
    return color.toLinearRGB();
}

/// The RGB of an <rgb>, <srgb>, <spectrum> or <blackbody> (or a <float>: a grey).
Color3f colorOf(const Value &value, Intent intent) {
    const std::string &text = value.text;
    const std::string where = value.location;
    if (value.kind == Value::Kind::Float || value.kind == Value::Kind::Integer)
        return Color3f(parseFloat(text, where, value.tag));
    if (value.kind != Value::Kind::Color)
        throw LocatedError(where, fmt::format("a colour is expected here, not a <{}>", value.tag));
    if (value.tag == "rgb" || value.tag == "srgb" || value.tag == "color") {
        if (!text.empty() && trim(text)[0] == '#')
            return hexColor(trim(text), where);
        const std::vector<float> numbers = parseNumbers(text, where, value.tag);
        if (numbers.size() != 1 && numbers.size() != 3)
            throw LocatedError(
                where, fmt::format("<{}> takes 1 or 3 numbers, got {}", value.tag, numbers.size()));
        const Color3f color =
            numbers.size() == 1 ? Color3f(numbers[0]) : Color3f(numbers[0], numbers[1], numbers[2]);
        return value.tag == "srgb" ? color.toLinearRGB() : color;
    }
    const auto toRGB = [&](const std::function<float(float)> &spectrum) {
        return intent == Intent::Illuminant ? emissionToRGB(spectrum) : reflectanceToRGB(spectrum);
    };
    if (value.tag == "blackbody") {
        const auto temperatureText = value.attributes.find("temperature");
        if (temperatureText == value.attributes.end())
            throw LocatedError(where, "<blackbody> needs a temperature (\"5000K\")");
        std::string kelvin = trim(temperatureText->second);
        if (!kelvin.empty() && (kelvin.back() == 'K' || kelvin.back() == 'k'))
            kelvin.pop_back();
        const float temperature = parseFloat(kelvin, where, "temperature");
        if (!(temperature > 0.0f))
            throw LocatedError(where, "<blackbody> needs a positive temperature");
        const auto scale = value.attributes.find("scale");
        const float factor =
            scale == value.attributes.end() ? 1.0f : parseFloat(scale->second, where, "scale");
        // Mitsuba's BlackBodySpectrum: Planck's law per nm (W/(m²·sr·nm)).
        return factor * toRGB([temperature](float lambda) {
                   return float(planck(lambda, temperature) * 1e-9);
               });
    }
    // <spectrum>: a constant, "λ:value, ..." pairs, or a file of them.
    if (const auto file = value.attributes.find("filename"); file != value.attributes.end()) {
        const fs::path path = fs::path(value.source->directory()) / file->second;
        try {
            const PiecewiseLinearSpectrum spectrum = readSpectrumFile(path.string());
            return toRGB([&spectrum](float lambda) { return spectrum(lambda); });
        } catch (const NoriException &error) {
            throw LocatedError(where, error.what());
        }
    }
    if (text.find(':') == std::string::npos) {
        const std::vector<float> numbers = parseNumbers(text, where, "spectrum");
        if (numbers.size() != 1)
            throw LocatedError(where, "<spectrum> takes one value, \"λ:value\" pairs or a "
                                      "filename");
        return Color3f(numbers[0]);
    }
    std::vector<float> lambdas, values;
    for (const std::string &pair : tokenize(text, ",")) {
        const std::string entry = trim(pair);
        if (entry.empty())
            continue;
        const size_t colon = entry.find(':');
        if (colon == std::string::npos)
            throw LocatedError(where, fmt::format("'{}' is not a pair λ:value", entry));
        lambdas.push_back(parseFloat(entry.substr(0, colon), where, "wavelength"));
        values.push_back(parseFloat(entry.substr(colon + 1), where, "spectrum value"));
    }
    try {
        const PiecewiseLinearSpectrum spectrum(lambdas, values);
        return toRGB([&spectrum](float lambda) { return spectrum(lambda); });
    } catch (const NoriException &error) {
        throw LocatedError(where, error.what());
    }
}

/// "x, y, z" from a value attribute or x=, y=, z= attributes (missing ones: `fill`).
Vector3f vectorOf(const Value &value, float fill = 0.0f) {
    if (!value.text.empty()) {
        const std::vector<float> numbers = parseNumbers(value.text, value.location, value.tag);
        if (numbers.size() == 1)
            return Vector3f(numbers[0]);
        if (numbers.size() != 3)
            throw LocatedError(value.location, fmt::format("<{}> takes 3 numbers, got {}",
                                                           value.tag, numbers.size()));
        return Vector3f(numbers[0], numbers[1], numbers[2]);
    }
    Vector3f result(fill);
    const char *axes[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i)
        if (const auto it = value.attributes.find(axes[i]); it != value.attributes.end())
            result[i] = parseFloat(it->second, value.location, axes[i]);
    return result;
}

// ---- Transforms ---------------------------------------------------------------------

/// A <transform>'s operations, as our XML writes them and as a matrix.
struct TransformOps {
    std::vector<std::pair<std::string, std::map<std::string, std::string>>> ops;
    Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
};

/// Mitsuba's Transform::lookAt (and ours): columns left, up, dir, origin.
Eigen::Matrix4d lookAtMatrix(const Eigen::Vector3d &origin, const Eigen::Vector3d &target,
                             const Eigen::Vector3d &up) {
    const Eigen::Vector3d dir = (target - origin).normalized();
    const Eigen::Vector3d left = up.normalized().cross(dir).normalized();
    const Eigen::Vector3d newUp = dir.cross(left);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<3, 1>(0, 0) = left;
    m.block<3, 1>(0, 1) = newUp;
    m.block<3, 1>(0, 2) = dir;
    m.block<3, 1>(0, 3) = origin;
    return m;
}

TransformOps transformOf(const Value &value) {
    if (value.kind != Value::Kind::Transform)
        throw LocatedError(value.location,
                           fmt::format("a <transform> is expected here, not a <{}>", value.tag));
    TransformOps result;
    for (const pugi::xml_node &node : value.node.children()) {
        if (node.type() != pugi::node_element)
            continue;
        Value op;
        op.tag = toLower(node.name());
        op.location = value.source->locate(node);
        op.source = value.source;
        for (const pugi::xml_attribute &attribute : node.attributes())
            op.attributes[attribute.name()] = attribute.value();
        if (const auto it = op.attributes.find("value"); it != op.attributes.end())
            op.text = it->second;
        Eigen::Matrix4d step = Eigen::Matrix4d::Identity();
        if (op.tag == "translate") {
            const Vector3f t = vectorOf(op, 0.0f);
            step.block<3, 1>(0, 3) = t.cast<double>();
            result.ops.push_back({"translate", {{"value", triple(t)}}});
        } else if (op.tag == "scale") {
            const Vector3f s = vectorOf(op, 1.0f);
            step.diagonal().head<3>() = s.cast<double>();
            result.ops.push_back({"scale", {{"value", triple(s)}}});
        } else if (op.tag == "rotate") {
            Value axisValue = op;
            if (const auto it = op.attributes.find("axis"); it != op.attributes.end())
                axisValue.text = it->second;
            else
                axisValue.text.clear();
            const Vector3f axis = vectorOf(axisValue, 0.0f);
            const auto angle = op.attributes.find("angle");
            if (angle == op.attributes.end() || axis.norm() == 0.0f)
                throw LocatedError(op.location, "<rotate> needs an axis and an angle");
            const float degrees = parseFloat(angle->second, op.location, "angle");
            step.topLeftCorner<3, 3>() =
                Eigen::AngleAxisd(double(degToRad(degrees)), axis.cast<double>().normalized())
                    .toRotationMatrix();
            result.ops.push_back({"rotate", {{"axis", triple(axis)}, {"angle", number(degrees)}}});
        } else if (op.tag == "matrix") {
            const std::vector<float> numbers = parseNumbers(op.text, op.location, "matrix");
            if (numbers.size() != 16 && numbers.size() != 9)
                throw LocatedError(op.location, fmt::format("<matrix> takes 16 (or 9) numbers, "
                                                            "got {}",
                                                            numbers.size()));
            const int n = numbers.size() == 16 ? 4 : 3;
            for (int row = 0; row < n; ++row)
                for (int column = 0; column < n; ++column)
                    step(row, column) = numbers[size_t(row) * size_t(n) + size_t(column)];
            std::string text;
            for (int row = 0; row < 4; ++row)
                for (int column = 0; column < 4; ++column)
                    text += fmt::format("{}{}", text.empty() ? "" : " ",
                                        float(step(row, column)) + 0.0f);
            result.ops.push_back({"matrix", {{"value", text}}});
        } else if (op.tag == "lookat") {
            const auto point = [&](const char *name, const char *fallback) {
                Value v = op;
                const auto it = op.attributes.find(name);
                v.text = it == op.attributes.end() ? fallback : it->second;
                if (v.text.empty())
                    throw LocatedError(op.location, fmt::format("<lookAt> needs {}", name));
                return vectorOf(v);
            };
            const Vector3f origin = point("origin", ""), target = point("target", ""),
                           up = point("up", "0, 1, 0");
            step = lookAtMatrix(origin.cast<double>(), target.cast<double>(), up.cast<double>());
            result.ops.push_back(
                {"lookat",
                 {{"origin", triple(origin)}, {"target", triple(target)}, {"up", triple(up)}}});
        } else {
            throw LocatedError(op.location,
                               fmt::format("unknown transform <{}>{}", node.name(),
                                           didYouMean(op.tag, {"translate", "scale", "rotate",
                                                               "matrix", "lookat"})));
        }
        result.matrix = step * result.matrix;
    }
    return result;
}

void writeTransform(pugi::xml_node parent, const std::string &name, const TransformOps &t) {
    if (t.ops.empty())
        return;
    pugi::xml_node transform = parent.append_child("transform");
    transform.append_attribute("name") = name.c_str();
    for (const auto &[tag, attributes] : t.ops) {
        pugi::xml_node op = transform.append_child(tag.c_str());
        for (const auto &[key, text] : attributes)
            op.append_attribute(key.c_str()) = text.c_str();
    }
}

// ---- The converter ------------------------------------------------------------------

class Converter {
public:
    /// `snakeCase`: the file is in Mitsuba 2/3's dialect (its definitions differ in places).
    Converter(const ConvertOptions &options, bool snakeCase)
        : m_options(options), m_snakeCase(snakeCase) {}

    Conversion convert(const Element &scene, const std::vector<std::string> &variables) {
        m_root = m_document.append_child("scene");
        // Declarations first (ids a <ref> may name), then the scene in file order.
        for (const Value &child : scene.children)
            if (child.kind == Value::Kind::Object)
                m_declared[child.object->id] = child.object.get();
        bool hasIntegrator = false, hasSensor = false;
        for (const Value &child : scene.children) {
            if (child.kind == Value::Kind::Ref)
                throw LocatedError(child.location,
                                   "a <ref> at the top of the scene refers to nothing here");
            const Element &object = *child.object;
            if (object.tag == "integrator") {
                if (hasIntegrator)
                    throw LocatedError(object.location, "a scene has one <integrator>");
                hasIntegrator = true;
                integrator(object, m_root);
            } else if (object.tag == "sensor") {
                if (hasSensor) {
                    warn(object.location, "second-sensor",
                         "a second <sensor>: only the first renders here");
                    continue;
                }
                hasSensor = true;
                sensor(object);
            } else {
                topLevel(object);
            }
        }
        if (!hasIntegrator)
            addObject(m_root, "integrator", "path_mis");
        if (!hasSensor)
            throw LocatedError(scene.location, "the scene has no <sensor>");
        for (const auto &[name, value] : scene.properties)
            throw LocatedError(value.location,
                               fmt::format("a property ('{}') at the top of the scene", name));
        Conversion conversion;
        std::ostringstream text;
        m_document.save(text, "    ");
        conversion.xml = text.str();
        conversion.warnings = m_warnings;
        conversion.variables = variables;
        return conversion;
    }

private:
    // ---- Messages and checks ----

    void warn(const std::string &location, const std::string &feature, const std::string &text) {
        const std::string file = location.substr(0, location.find(':'));
        if (m_warned.insert({file, feature}).second)
            m_warnings.push_back(fmt::format("{}: {}", location, text));
    }

    /// An error for the first property of `e` no mapping read; a warning for one written
    /// in the other dialect's spelling.
    void finish(const Element &e) {
        for (const auto &[written, meant] : e.respelled)
            warn(e.location, "spelling-" + written,
                 fmt::format("{}: '{}' is the spelling of another Mitsuba version: read as '{}'",
                             e.description(), written, meant));
        for (const auto &[name, value] : e.properties) {
            if (e.used.count(name))
                continue;
            std::vector<std::string> known(e.queried.begin(), e.queried.end());
            throw LocatedError(value.location,
                               fmt::format("{} has no parameter '{}'{}", e.description(), name,
                                           didYouMean(name, known)));
        }
    }

    /// Reads and drops parameters that change nothing here (a film's file format).
    static void ignore(const Element &e, std::initializer_list<const char *> names) {
        for (const char *name : names)
            e.find(name);
    }

    static float floatOf(const Value &value) {
        if (value.kind != Value::Kind::Float && value.kind != Value::Kind::Integer)
            throw LocatedError(value.location,
                               fmt::format("a number is expected here, not a <{}>", value.tag));
        return parseFloat(value.text, value.location, value.tag);
    }
    static float getFloat(const Element &e, const char *name, float fallback) {
        const Value *value = e.find(name);
        return value ? floatOf(*value) : fallback;
    }
    static int getInteger(const Element &e, const char *name, int fallback) {
        const Value *value = e.find(name);
        if (!value)
            return fallback;
        if (value->kind != Value::Kind::Integer)
            throw LocatedError(value->location, fmt::format("'{}' is an <integer>", name));
        try {
            return toInt(trim(value->text), name);
        } catch (const NoriException &error) {
            throw LocatedError(value->location, error.what());
        }
    }
    static bool getBoolean(const Element &e, const char *name, bool fallback) {
        const Value *value = e.find(name);
        if (!value)
            return fallback;
        if (value->kind != Value::Kind::Boolean)
            throw LocatedError(value->location, fmt::format("'{}' is a <boolean>", name));
        const std::string text = toLower(trim(value->text));
        if (text != "true" && text != "false")
            throw LocatedError(value->location,
                               fmt::format("'{}' must be true or false, got '{}'", name, text));
        return text == "true";
    }
    static std::string getString(const Element &e, const char *name, const std::string &fallback) {
        const Value *value = e.find(name);
        if (!value)
            return fallback;
        if (value->kind != Value::Kind::String)
            throw LocatedError(value->location, fmt::format("'{}' is a <string>", name));
        return value->text;
    }
    static std::optional<Vector3f> getPoint(const Element &e, const char *name) {
        const Value *value = e.find(name);
        if (!value)
            return std::nullopt;
        if (value->kind != Value::Kind::Point && value->kind != Value::Kind::Vector)
            throw LocatedError(value->location, fmt::format("'{}' is a <point> or <vector>", name));
        return vectorOf(*value);
    }
    static std::optional<TransformOps> getTransform(const Element &e, const char *name) {
        const Value *value = e.find(name);
        if (!value)
            return std::nullopt;
        return transformOf(*value);
    }
    /// A constant colour given to `name`, or nullopt when absent or a texture.
    static std::optional<Color3f> constantColor(const Element &e, const char *name, Intent intent) {
        const Value *value = e.find(name);
        if (!value || value->kind == Value::Kind::Object || value->kind == Value::Kind::Ref)
            return std::nullopt;
        return colorOf(*value, intent);
    }

    // ---- Writing parameters ----

    void copyFloat(const Element &e, const char *name, pugi::xml_node out, const char *ours) {
        if (const Value *value = e.find(name))
            addFloat(out, ours, floatOf(*value));
    }
    void copyInteger(const Element &e, const char *name, pugi::xml_node out, const char *ours) {
        if (e.has(name))
            addInteger(out, ours, getInteger(e, name, 0));
    }
    void copyBoolean(const Element &e, const char *name, pugi::xml_node out, const char *ours) {
        if (e.has(name))
            addBoolean(out, ours, getBoolean(e, name, false));
    }
    void copyString(const Element &e, const char *name, pugi::xml_node out, const char *ours) {
        if (e.has(name))
            addString(out, ours, getString(e, name, ""));
    }
    /// A file name, relative to the Mitsuba file's folder there, to our XML's folder here.
    void copyFilename(const Element &e, const char *name, pugi::xml_node out, const char *ours) {
        if (!e.has(name))
            return;
        const std::string file = getString(e, name, "");
        if (file.empty())
            throw LocatedError(e.find(name)->location, fmt::format("'{}' is empty", name));
        const fs::path absolute = fs::absolute(fs::path(e.source->directory()) / file);
        const fs::path relative =
            absolute.lexically_normal().lexically_relative(fs::absolute(m_options.xmlDirectory));
        addString(out, ours, relative.empty() ? absolute.string() : relative.generic_string());
    }
    void copyTransform(const Element &e, const char *name, pugi::xml_node out, const char *ours) {
        if (const auto t = getTransform(e, name))
            writeTransform(out, ours, *t);
    }
    /// An index of refraction: a number or a name of Mitsuba's table ("bk7", "water").
    void copyIOR(const Element &e, const char *name, pugi::xml_node out, const char *ours) {
        const Value *value = e.find(name);
        if (!value)
            return;
        if (value->kind == Value::Kind::String)
            addString(out, ours, value->text);
        else
            addFloat(out, ours, floatOf(*value));
    }
    /// Writes a texture given to a parameter (nested, or by <ref>); false for a constant.
    bool copyTexture(const Value &value, pugi::xml_node out, const char *ours) {
        if (value.kind == Value::Kind::Object)
            texture(*value.object, out, ours);
        else if (value.kind == Value::Kind::Ref)
            addRef(out, value.refId, ours);
        else
            return false;
        return true;
    }
    /// A colour or texture parameter: <color>, or the texture (nested or by <ref>).
    void copyColor(const Element &e, const char *name, pugi::xml_node out, const char *ours,
                   Intent intent = Intent::Reflectance) {
        const Value *value = e.find(name);
        if (value && !copyTexture(*value, out, ours))
            addColor(out, ours, colorOf(*value, intent));
    }
    /// A float or texture parameter.
    void copyFloatOrTexture(const Element &e, const char *name, pugi::xml_node out,
                            const char *ours) {
        const Value *value = e.find(name);
        if (!value || copyTexture(*value, out, ours))
            return;
        if (value->kind == Value::Kind::Color)
            addColor(out, ours, colorOf(*value, Intent::Reflectance));
        else
            addFloat(out, ours, floatOf(*value));
    }
    /// A scale factor we do not have (a dielectric's specularReflectance): fine at 1.
    void requireOne(const Element &e, const char *name) {
        const Value *value = e.find(name);
        if (!value)
            return;
        if (value->kind == Value::Kind::Object || value->kind == Value::Kind::Ref ||
            (colorOf(*value, Intent::Reflectance) != Color3f(1.0f)).any())
            warn(value->location, e.type + "-" + name,
                 fmt::format("{}: '{}' other than 1 is not supported: rendered as 1",
                             e.description(), name));
    }
    /// "beckmann" or "ggx"; Mitsuba's others become Beckmann, with a warning.
    void copyDistribution(const Element &e, pugi::xml_node out) {
        const Value *value = e.find("distribution");
        if (!value)
            return;
        std::string distribution = toLower(value->text);
        if (distribution == "as")
            distribution = "ashikhmin-shirley";
        if (distribution != "beckmann" && distribution != "ggx") {
            warn(value->location, "distribution-" + distribution,
                 fmt::format("{}: the '{}' microfacet distribution is rendered as Beckmann's",
                             e.description(), value->text));
            distribution = "beckmann";
        }
        addString(out, "distribution", distribution);
    }

    // ---- Scene level ----

    void topLevel(const Element &object) {
        if (object.tag == "shape")
            shape(object, m_root);
        else if (object.tag == "bsdf")
            bsdf(object, m_root);
        else if (object.tag == "texture")
            texture(object, m_root, "");
        else if (object.tag == "emitter")
            emitter(object, m_root);
        else if (object.tag == "medium")
            medium(object, m_root);
        else if (object.tag == "phase")
            phase(object, m_root);
        else if (object.tag == "subsurface")
            warn(object.location, "subsurface",
                 "<subsurface> integrators are not supported: left out");
        else
            throw LocatedError(object.location,
                               fmt::format("a <{}> does not belong at the top of the scene "
                                           "(it goes in a <sensor> or a <medium>)",
                                           object.tag));
    }

    /// Writes the id of a declared object onto our element.
    static void identify(const Element &e, pugi::xml_node node) {
        if (!e.id.empty())
            node.append_attribute("id") = e.id.c_str();
    }

    // ---- Integrators ----

    /// Mitsuba's maxDepth (path vertices; 1: only emitters seen) as our bounces.
    void copyDepths(const Element &e, pugi::xml_node out) {
        if (e.has("maxDepth")) {
            const int depth = getInteger(e, "maxDepth", -1);
            addInteger(out, "maxDepth", depth < 0 ? -1 : std::max(0, depth - 1));
        }
        if (e.has("rrDepth"))
            addInteger(out, "rrDepth", std::max(1, getInteger(e, "rrDepth", 5) - 1));
    }

    void integrator(const Element &e, pugi::xml_node parent) {
        const std::string &type = e.type;
        pugi::xml_node out;
        if (type == "path" || type == "volpath" || type == "volpath_simple" || type == "bdpt" ||
            type == "ptracer") {
            static const std::map<std::string, std::string> ours = {{"path", "path_mis"},
                                                                    {"volpath", "volpath"},
                                                                    {"volpath_simple", "volpath"},
                                                                    {"bdpt", "bdpt"},
                                                                    {"ptracer", "lighttracer"}};
            out = addObject(parent, "integrator", ours.at(type));
            copyDepths(e, out);
            ignore(e, {"strictNormals", "granularity", "lightImage", "sampleDirect"});
            if (getBoolean(e, "hideEmitters", false))
                warn(e.location, "hideEmitters",
                     "hideEmitters is not supported: lights seen directly are rendered");
        } else if (type == "direct") {
            out = addObject(parent, "integrator", "direct_mis");
            for (const char *count : {"emitterSamples", "bsdfSamples", "shadingSamples"})
                if (e.has(count) && getInteger(e, count, 1) != 1)
                    warn(e.location, "direct-samples",
                         fmt::format("direct: '{}' is taken as 1 (one light and one BSDF sample a "
                                     "pixel sample; raise the sampler's sampleCount instead)",
                                     count));
            ignore(e, {"strictNormals"});
            if (getBoolean(e, "hideEmitters", false))
                warn(e.location, "hideEmitters",
                     "hideEmitters is not supported: lights seen directly are rendered");
        } else if (type == "ao") {
            out = addObject(parent, "integrator", "ao");
            copyInteger(e, "shadingSamples", out, "sampleCount");
            const float length = getFloat(e, "rayLength", -1.0f);
            if (length > 0.0f)
                addFloat(out, "length", length);
        } else if (type == "photonmapper") {
            out = addObject(parent, "integrator", "photonmapper");
            copyInteger(e, "globalPhotons", out, "photonCount");
            copyFloat(e, "globalLookupRadius", out, "photonRadius");
            ignore(e, {"directSamples", "glossySamples", "maxDepth", "rrDepth", "causticPhotons",
                       "volumePhotons", "causticLookupRadius", "lookupSize", "granularity",
                       "hideEmitters", "maxSpecularDepth"});
        } else if (type == "sppm") {
            out = addObject(parent, "integrator", "progressivephotonmapper");
            copyInteger(e, "photonCount", out, "photonCount");
            copyFloat(e, "initialRadius", out, "photonRadius");
            copyFloat(e, "alpha", out, "alpha");
            ignore(e, {"maxDepth", "rrDepth", "granularity", "maxPasses"});
        } else if (type == "aov") {
            aovIntegrator(e, parent);
            finish(e);
            return;
        } else if (type == "adaptive" || type == "irrcache" || type == "multichannel") {
            const std::vector<const Value *> nested = e.childrenOf("integrator");
            warn(e.location, "integrator-" + type,
                 fmt::format("the '{}' integrator is not supported: its nested integrator "
                             "renders alone",
                             type));
            ignore(e, {"maxError", "pValue", "maxSampleFactor", "resolution", "quality",
                       "qualityAdjustment", "gradients", "clampNeighbor", "clampScreen", "overture",
                       "debug", "indirectOnly"});
            if (!nested.empty() && nested.front()->kind == Value::Kind::Object)
                integrator(*nested.front()->object, parent);
            else
                addObject(parent, "integrator", "path_mis");
            return;
        } else {
            static const std::vector<std::string> known = {
                "path",     "volpath",  "volpath_simple", "bdpt",   "ptracer",
                "direct",   "ao",       "photonmapper",   "sppm",   "aov",
                "adaptive", "irrcache", "multichannel",   "pssmlt", "mlt",
                "erpt",     "vpl",      "field",          "ppm"};
            if (std::find(known.begin(), known.end(), type) == known.end())
                throw LocatedError(e.location, fmt::format("unknown integrator '{}'{}", type,
                                                           didYouMean(type, known)));
            warn(e.location, "integrator-" + type,
                 fmt::format("the '{}' integrator is not supported: path_mis renders instead",
                             type));
            for (const auto &[name, value] : e.properties)
                e.find(name);
            out = addObject(parent, "integrator", "path_mis");
        }
        finish(e);
    }

    /// Mitsuba 3's aov: our `aovs` on its nested integrator (path_mis without one).
    void aovIntegrator(const Element &e, pugi::xml_node parent) {
        static const std::map<std::string, std::string> kinds = {
            {"depth", "depth"},       {"position", "position"}, {"sh_normal", "normal"},
            {"geo_normal", "normal"}, {"albedo", "albedo"},     {"normal", "normal"}};
        std::vector<std::string> ours;
        const std::string list = getString(e, "aovs", "");
        for (const std::string &entry : tokenize(list, ",")) {
            const std::string item = trim(entry);
            if (item.empty())
                continue;
            const std::string kind = item.substr(item.find(':') + 1);
            const auto it = kinds.find(kind);
            if (it == kinds.end()) {
                warn(e.location, "aov-" + kind,
                     fmt::format("aov: the '{}' layer is not one of ours (depth, position, "
                                 "normal, albedo): left out",
                                 kind));
                continue;
            }
            if (std::find(ours.begin(), ours.end(), it->second) == ours.end())
                ours.push_back(it->second);
        }
        const std::vector<const Value *> nested = e.childrenOf("integrator");
        if (!nested.empty() && nested.front()->kind == Value::Kind::Object)
            integrator(*nested.front()->object, parent);
        else
            addObject(parent, "integrator", "path_mis");
        pugi::xml_node out = parent.last_child();
        std::string joined;
        for (const std::string &name : ours)
            joined += (joined.empty() ? "" : ",") + name;
        if (!joined.empty())
            addString(out, "aovs", joined);
    }

    // ---- Sensor, film, sampler, filter ----

    void sensor(const Element &e) {
        if (e.type != "perspective" && e.type != "thinlens") {
            static const std::vector<std::string> known = {
                "perspective",     "thinlens",      "orthographic", "telecentric",      "spherical",
                "irradiancemeter", "radiancemeter", "fluencemeter", "perspective_rdist"};
            if (std::find(known.begin(), known.end(), e.type) == known.end())
                throw LocatedError(e.location, fmt::format("unknown sensor '{}'{}", e.type,
                                                           didYouMean(e.type, known)));
            throw LocatedError(e.location,
                               fmt::format("the '{}' sensor is not supported (perspective and "
                                           "thinlens are)",
                                           e.type));
        }
        // The film first: the field of view depends on its aspect.
        const Element *film = nullptr;
        const Element *sampler = nullptr;
        for (const Value &child : e.children) {
            if (child.kind != Value::Kind::Object)
                throw LocatedError(child.location, "a <ref> in a <sensor> is not supported");
            if (child.tag == "film")
                film = child.object.get();
            else if (child.tag == "sampler")
                sampler = child.object.get();
            else if (child.tag == "medium")
                warn(child.location, "sensor-medium",
                     "a medium around the sensor is not supported: left out");
            else
                throw LocatedError(child.location,
                                   fmt::format("a <{}> does not belong in a <sensor>", child.tag));
        }
        writeSampler(sampler);
        pugi::xml_node camera = addObject(m_root, "camera", "perspective");
        int width = 768, height = 576;
        if (film) {
            width = getInteger(*film, "width", 768);
            height = getInteger(*film, "height", 576);
        }
        if (width <= 0 || height <= 0)
            throw LocatedError(film ? film->location : e.location,
                               "the film's width and height must be positive");
        const double aspect = double(width) / double(height);
        // The horizontal field of view, as Mitsuba's PerspectiveCamera::configure finds it.
        double xfov = 0.0;
        if (e.has("fov") && e.has("focalLength"))
            throw LocatedError(e.location, "give a sensor fov or focalLength, not both");
        auto fromY = [&](double yfov) {
            return radToDeg(float(2.0 * std::atan(std::tan(0.5 * degToRad(float(yfov))) * aspect)));
        };
        auto fromDiagonal = [&](double dfov) {
            const double diagonal = 2.0 * std::tan(0.5 * degToRad(float(dfov)));
            const double widthAtOne = diagonal / std::sqrt(1.0 + 1.0 / (aspect * aspect));
            return radToDeg(float(2.0 * std::atan(widthAtOne * 0.5)));
        };
        if (e.has("fov")) {
            const float fov = getFloat(e, "fov", 0.0f);
            std::string axis = toLower(getString(e, "fovAxis", "x"));
            if (axis == "smaller")
                axis = aspect > 1.0 ? "y" : "x";
            else if (axis == "larger")
                axis = aspect > 1.0 ? "x" : "y";
            if (axis == "x")
                xfov = fov;
            else if (axis == "y")
                xfov = fromY(fov);
            else if (axis == "diagonal")
                xfov = fromDiagonal(fov);
            else
                throw LocatedError(e.find("fovAxis")->location,
                                   fmt::format("fovAxis must be x, y, diagonal, smaller or "
                                               "larger, got '{}'",
                                               axis));
        } else {
            // A 35 mm film's diagonal, sqrt(36² + 24²) mm, across the focal length.
            std::string focal = getString(e, "focalLength", "50mm");
            if (focal.size() > 2 && focal.substr(focal.size() - 2) == "mm")
                focal = focal.substr(0, focal.size() - 2);
            const float length = parseFloat(focal, e.location, "focalLength");
            if (!(length > 0.0f))
                throw LocatedError(e.location, "focalLength must be positive");
            xfov = fromDiagonal(2.0 * 180.0 / kPiDouble *
                                std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2.0 * length)));
        }
        if (!(xfov > 0.0 && xfov < 180.0))
            throw LocatedError(e.location, fmt::format("the horizontal field of view ({}°) must "
                                                       "lie in (0, 180)",
                                                       xfov));
        addFloat(camera, "fov", float(xfov));
        addInteger(camera, "width", width);
        addInteger(camera, "height", height);
        addFloat(camera, "nearClip", getFloat(e, "nearClip", 1e-2f));
        copyFloat(e, "farClip", camera, "farClip");
        copyTransform(e, "toWorld", camera, "toWorld");
        if (e.type == "thinlens") {
            copyFloat(e, "apertureRadius", camera, "apertureRadius");
            copyFloat(e, "focusDistance", camera, "focalDistance");
        }
        ignore(e, {"shutterOpen", "shutterClose"});
        if (film)
            writeFilm(*film, camera);
        finish(e);
    }

    void writeFilm(const Element &film, pugi::xml_node camera) {
        static const std::vector<std::string> films = {"hdrfilm", "ldrfilm", "tiledhdrfilm",
                                                       "mfilm", "specfilm"};
        if (std::find(films.begin(), films.end(), film.type) == films.end())
            throw LocatedError(film.location, fmt::format("unknown film '{}'{}", film.type,
                                                          didYouMean(film.type, films)));
        // width and height were read with the sensor.
        copyInteger(film, "cropOffsetX", camera, "cropOffsetX");
        copyInteger(film, "cropOffsetY", camera, "cropOffsetY");
        copyInteger(film, "cropWidth", camera, "cropWidth");
        copyInteger(film, "cropHeight", camera, "cropHeight");
        if (getBoolean(film, "highQualityEdges", false) || getBoolean(film, "sampleBorder", false))
            addBoolean(camera, "sampleBorder", true);
        // What only changes the file written: we write an EXR and a PNG.
        ignore(film, {"fileFormat", "pixelFormat", "componentFormat", "banner", "attachLog",
                      "gamma", "exposure", "tonemapMethod", "key", "burn", "variant", "digits",
                      "compress", "rfilter"});
        const Value *filter = nullptr;
        if (const Value *named = film.find("rfilter"); named && named->kind == Value::Kind::Object)
            filter = named;
        for (const Value &child : film.children) {
            if (child.tag != "rfilter" || child.kind != Value::Kind::Object)
                throw LocatedError(child.location,
                                   fmt::format("a <{}> does not belong in a <film>", child.tag));
            filter = &child;
        }
        if (filter)
            rfilter(*filter->object, camera);
        finish(film);
    }

    void rfilter(const Element &e, pugi::xml_node camera) {
        pugi::xml_node out;
        if (e.type == "box" || e.type == "tent") {
            out = addObject(camera, "rfilter", e.type);
            copyFloat(e, "radius", out, "radius");
        } else if (e.type == "gaussian") {
            out = addObject(camera, "rfilter", "gaussian");
            // Mitsuba 0.6's support is 4 standard deviations.
            const float stddev = getFloat(e, "stddev", 0.5f);
            addFloat(out, "stddev", stddev);
            addFloat(out, "radius", 4.0f * stddev);
        } else if (e.type == "mitchell" || e.type == "catmullrom") {
            out = addObject(camera, "rfilter", "mitchell");
            const bool catmull = e.type == "catmullrom";
            addFloat(out, "B", catmull ? 0.0f : getFloat(e, "B", 1.0f / 3.0f));
            addFloat(out, "C", catmull ? 0.5f : getFloat(e, "C", 1.0f / 3.0f));
            copyFloat(e, "radius", out, "radius");
        } else if (e.type == "lanczos") {
            warn(e.location, "lanczos",
                 "the lanczos filter is rendered with the Catmull-Rom filter (mitchell, B = 0, "
                 "C = 1/2), its nearest");
            ignore(e, {"lobes"});
            out = addObject(camera, "rfilter", "mitchell");
            addFloat(out, "B", 0.0f);
            addFloat(out, "C", 0.5f);
        } else {
            throw LocatedError(
                e.location, fmt::format("unknown rfilter '{}'{}", e.type,
                                        didYouMean(e.type, {"box", "tent", "gaussian", "mitchell",
                                                            "catmullrom", "lanczos"})));
        }
        finish(e);
    }

    /// Mitsuba's default: independent, 4 samples a pixel.
    void writeSampler(const Element *e) {
        std::string type = "independent";
        int samples = 4;
        if (e) {
            static const std::vector<std::string> known = {
                "independent", "stratified",  "ldsampler",  "halton",    "hammersley",
                "sobol",       "multijitter", "orthogonal", "correlated"};
            if (std::find(known.begin(), known.end(), e->type) == known.end())
                throw LocatedError(e->location, fmt::format("unknown sampler '{}'{}", e->type,
                                                            didYouMean(e->type, known)));
            // Low-discrepancy ones become ours, Sobol.
            type = e->type == "independent" || e->type == "stratified" ? e->type : "sobol";
            samples = getInteger(*e, "sampleCount", 4);
            ignore(*e, {"dimension", "scramble", "seed", "jitter", "strength", "resolution"});
            finish(*e);
        }
        pugi::xml_node out = addObject(m_root, "sampler", type);
        addInteger(out, "sampleCount", samples);
    }

    // ---- Shapes ----

    void shape(const Element &e, pugi::xml_node parent) {
        const std::string &type = e.type;
        static const std::set<std::string> meshes = {"obj", "ply", "serialized"};
        static const std::set<std::string> analytic = {"rectangle", "disk", "cube"};
        pugi::xml_node out;
        if (meshes.count(type)) {
            out = addObject(parent, "mesh", type);
            copyFilename(e, "filename", out, "filename");
            if (type == "serialized")
                copyInteger(e, "shapeIndex", out, "shapeIndex");
            copyTransform(e, "toWorld", out, "toWorld");
            copyBoolean(e, "faceNormals", out, "faceNormals");
            copyBoolean(e, "flipNormals", out, "flipNormals");
            // Our uv are Mitsuba's: its OBJ loader flips v by default (see the bitmap).
            if (type == "obj" && getBoolean(e, "flipTexCoords", true))
                addBoolean(out, "flipTexCoords", true);
            if (e.has("maxSmoothAngle"))
                warn(e.location, "maxSmoothAngle",
                     "maxSmoothAngle is not supported: the file's normals are used as they are");
            ignore(e, {"maxSmoothAngle", "collapse", "srgb", "loadMaterials"});
        } else if (analytic.count(type)) {
            out = addObject(parent, "mesh", type);
            const auto toWorld = getTransform(e, "toWorld");
            if (toWorld)
                writeTransform(out, "toWorld", *toWorld);
            // Mitsuba's rectangle faces its normal (0, 0, 1) transformed as a normal; ours
            // faces the side its winding does, which a mirroring toWorld turns over.
            bool flip = getBoolean(e, "flipNormals", false);
            if (type == "rectangle" && toWorld &&
                toWorld->matrix.topLeftCorner<3, 3>().determinant() < 0.0)
                flip = !flip;
            if (flip)
                addBoolean(out, "flipNormals", true);
            if (type == "cube") // each face's uv laid out as Mitsuba's vertex table does
                addString(out, "convention", "mitsuba");
        } else if (type == "sphere") {
            out = addObject(parent, "mesh", "sphere");
            Vector3f center = getPoint(e, "center").value_or(Vector3f(0.0f));
            float radius = getFloat(e, "radius", 1.0f);
            if (const auto t = getTransform(e, "toWorld")) {
                // Mitsuba places the sphere by toWorld too: only a similarity keeps it one.
                const Eigen::Matrix3d linear = t->matrix.topLeftCorner<3, 3>();
                const double scale = std::cbrt(std::abs(linear.determinant()));
                if ((linear.transpose() * linear - scale * scale * Eigen::Matrix3d::Identity())
                        .cwiseAbs()
                        .maxCoeff() > 1e-5 * scale * scale)
                    throw LocatedError(e.location, "a sphere's toWorld must keep it a sphere "
                                                   "(rotation, uniform scale, translation)");
                center = (t->matrix * Eigen::Vector4d(center.x(), center.y(), center.z(), 1.0))
                             .head<3>()
                             .cast<float>();
                radius *= float(scale);
                if ((linear / scale - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-5)
                    warn(e.location, "sphere-rotation",
                         "a rotated sphere's uv are taken about the world's axes, not its own");
            }
            addPoint(out, "center", center);
            addFloat(out, "radius", radius);
            copyBoolean(e, "flipNormals", out, "flipNormals");
            // Mitsuba's uv: u = φ/2π in [0, 1), v = θ/π (ours by default: u = ½ + φ/2π,
            // v = 1 − θ/π), about the sphere's own axes.
            addString(out, "convention", "mitsuba");
        } else if (type == "cylinder") {
            out = addObject(parent, "mesh", "cylinder");
            if (const auto p0 = getPoint(e, "p0"))
                addPoint(out, "p0", *p0);
            if (const auto p1 = getPoint(e, "p1"))
                addPoint(out, "p1", *p1);
            copyFloat(e, "radius", out, "radius");
            copyTransform(e, "toWorld", out, "toWorld");
            copyBoolean(e, "flipNormals", out, "flipNormals");
        } else if (type == "shapegroup") {
            out = addObject(parent, "mesh", "shapegroup");
            identify(e, out);
            for (const Value &child : e.children) {
                if (child.kind != Value::Kind::Object || child.tag != "shape")
                    throw LocatedError(child.location, "a shapegroup holds shapes only");
                shape(*child.object, out);
            }
            finish(e);
            return;
        } else if (type == "instance") {
            out = addObject(parent, "mesh", "instance");
            copyTransform(e, "toWorld", out, "toWorld");
            for (const Value &child : e.children) {
                if (child.kind != Value::Kind::Ref)
                    throw LocatedError(child.location,
                                       "an instance holds one <ref> to a shapegroup");
                addRef(out, child.refId);
            }
            finish(e);
            return;
        } else {
            static const std::vector<std::string> known = {
                "obj",    "ply",      "serialized", "rectangle", "disk", "cube",
                "sphere", "cylinder", "shapegroup", "instance",  "hair", "heightfield"};
            if (std::find(known.begin(), known.end(), type) == known.end())
                throw LocatedError(
                    e.location, fmt::format("unknown shape '{}'{}", type, didYouMean(type, known)));
            warn(e.location, "shape-" + type,
                 fmt::format("the '{}' shape is not supported: left out", type));
            return;
        }
        identify(e, out);
        shapeChildren(e, out);
        finish(e);
    }

    /// A shape's BSDF, area light and media.
    void shapeChildren(const Element &e, pugi::xml_node out) {
        for (const char *side : {"interior", "exterior"}) {
            const Value *value = e.find(side);
            if (!value)
                continue;
            if (value->kind == Value::Kind::Ref)
                addRef(out, value->refId, side);
            else if (value->kind == Value::Kind::Object && value->tag == "medium")
                medium(*value->object, out, side);
            else
                throw LocatedError(value->location, fmt::format("'{}' is a <medium>", side));
        }
        for (const Value &child : e.children) {
            if (child.kind == Value::Kind::Ref) {
                const auto declared = m_declared.find(child.refId);
                if (declared == m_declared.end())
                    throw LocatedError(
                        child.location,
                        fmt::format("<ref id=\"{}\">: no object has that id", child.refId));
                if (declared->second->tag == "bsdf" && declared->second->type == "normalmap") {
                    normalMapOnShape(*declared->second, out, true);
                    continue;
                }
                addRef(out, child.refId);
                continue;
            }
            const Element &object = *child.object;
            if (object.tag == "bsdf") {
                if (object.type == "normalmap")
                    normalMapOnShape(object, out, false);
                else
                    bsdf(object, out);
            } else if (object.tag == "emitter") {
                if (object.type != "area")
                    throw LocatedError(object.location, "a shape carries an 'area' emitter, not '" +
                                                            object.type + "'");
                emitter(object, out);
            } else if (object.tag == "subsurface") {
                warn(object.location, "subsurface",
                     "<subsurface> integrators are not supported: left out");
            } else if (object.tag == "medium") {
                throw LocatedError(object.location,
                                   "a shape's medium is named interior or exterior");
            } else {
                throw LocatedError(object.location,
                                   fmt::format("a <{}> does not belong in a <shape>", object.tag));
            }
        }
    }

    /// Mitsuba 3's normalmap BSDF: its texture becomes the shape's `normal`, its nested
    /// BSDF the shape's BSDF (ours are on shapes).
    void normalMapOnShape(const Element &e, pugi::xml_node shapeNode, bool byReference) {
        // Mitsuba 3 names the texture `normalmap`; Mitsuba 0.6 takes it unnamed.
        const Value *map = e.find("normalmap");
        if (!map && !m_snakeCase) {
            const std::vector<const Value *> unnamed = e.childrenOf("texture");
            if (unnamed.size() == 1)
                map = unnamed.front();
        }
        if (!map || map->kind == Value::Kind::Color)
            throw LocatedError(e.location, m_snakeCase
                                               ? "normalmap needs a texture called normalmap"
                                               : "normalmap holds one texture (the normals)");
        if (map->kind == Value::Kind::Object) {
            const Element &texture = *map->object;
            pugi::xml_node out = textureNode(texture, shapeNode, "normal");
            // Mitsuba 0.6 refuses a bitmap normal map without a gamma (the normals are data,
            // gamma 1 nearly always); Mitsuba 3 decodes it as sRGB unless `raw` is set.
            if (!m_snakeCase && texture.type == "bitmap" && !texture.has("gamma")) {
                warn(texture.location, "normalmap-gamma",
                     "normalmap: Mitsuba 0.6 needs the bitmap's gamma; read with gamma 1 (data)");
                addString(out, "colorSpace", "linear");
            }
        } else {
            addRef(shapeNode, map->refId, "normal");
        }
        const std::vector<const Value *> nested = e.childrenOf("bsdf");
        if (nested.size() != 1)
            throw LocatedError(e.location, "normalmap holds one nested BSDF");
        if (nested.front()->kind == Value::Kind::Ref)
            addRef(shapeNode, nested.front()->refId);
        else if (byReference && !e.id.empty())
            addRef(shapeNode, e.id + ".bsdf");
        else
            bsdf(*nested.front()->object, shapeNode);
        finish(e);
    }

    // ---- BSDFs ----

    /// The nested BSDFs of a wrapper (twosided, mask, blendbsdf, bumpmap).
    void nestedBSDFs(const Element &e, pugi::xml_node out, size_t minimum, size_t maximum) {
        const std::vector<const Value *> nested = e.childrenOf("bsdf");
        if (nested.size() < minimum || nested.size() > maximum)
            throw LocatedError(e.location,
                               fmt::format("{} holds {} nested BSDF{}, not {}", e.description(),
                                           minimum == maximum
                                               ? std::to_string(minimum)
                                               : fmt::format("{} or {}", minimum, maximum),
                                           maximum == 1 ? "" : "s", nested.size()));
        for (const Value *child : nested) {
            if (child->kind == Value::Kind::Ref)
                addRef(out, child->refId);
            else
                bsdf(*child->object, out);
        }
    }

    void bsdf(const Element &e, pugi::xml_node parent) {
        const std::string &type = e.type;
        pugi::xml_node out;
        const auto make = [&](const char *ours) {
            out = addObject(parent, "bsdf", ours, e.name);
            identify(e, out);
        };
        for (const Value &child : e.children)
            if (child.tag != "bsdf" && child.tag != "texture")
                throw LocatedError(child.location,
                                   fmt::format("a <{}> does not belong in a <bsdf>", child.tag));
        if (type == "diffuse" || type == "roughdiffuse") {
            make("diffuse");
            copyColor(e, "reflectance", out, "albedo");
            if (type == "roughdiffuse") {
                warn(e.location, "roughdiffuse",
                     "roughdiffuse (Oren-Nayar) is rendered as diffuse (Lambertian)");
                ignore(e, {"alpha", "useFastApprox"});
            }
        } else if (type == "twosided") {
            make("twosided");
            nestedBSDFs(e, out, 1, 2);
        } else if (type == "plastic" || type == "roughplastic") {
            make(type.c_str());
            copyIOR(e, "intIOR", out, "intIOR");
            copyIOR(e, "extIOR", out, "extIOR");
            copyColor(e, "diffuseReflectance", out, "diffuseReflectance");
            copyColor(e, "specularReflectance", out, "specularReflectance");
            copyBoolean(e, "nonlinear", out, "nonlinear");
            if (type == "roughplastic") {
                copyDistribution(e, out);
                copyFloatOrTexture(e, "alpha", out, "alpha");
            }
        } else if (type == "conductor" || type == "roughconductor") {
            make(type.c_str());
            copyString(e, "material", out, "material");
            copyColor(e, "eta", out, "eta");
            copyColor(e, "k", out, "k");
            copyIOR(e, "extEta", out, "extIOR");
            requireOne(e, "specularReflectance");
            if (type == "roughconductor") {
                copyDistribution(e, out);
                copyFloatOrTexture(e, "alpha", out, "alpha");
                copyFloatOrTexture(e, "alphaU", out, "alphaU");
                copyFloatOrTexture(e, "alphaV", out, "alphaV");
            }
        } else if (type == "dielectric" || type == "roughdielectric" || type == "thindielectric") {
            make(type.c_str());
            copyIOR(e, "intIOR", out, "intIOR");
            copyIOR(e, "extIOR", out, "extIOR");
            if (type == "thindielectric") {
                copyColor(e, "specularReflectance", out, "specularReflectance");
                copyColor(e, "specularTransmittance", out, "specularTransmittance");
            } else {
                requireOne(e, "specularReflectance");
                requireOne(e, "specularTransmittance");
            }
            if (type == "roughdielectric") {
                copyDistribution(e, out);
                copyFloatOrTexture(e, "alpha", out, "alpha");
                copyFloatOrTexture(e, "alphaU", out, "alphaU");
                copyFloatOrTexture(e, "alphaV", out, "alphaV");
            }
        } else if (type == "bumpmap") {
            make("bumpmap");
            const std::vector<const Value *> textures = e.childrenOf("texture");
            if (textures.size() != 1)
                throw LocatedError(e.location, "bumpmap holds one texture (the height)");
            if (textures.front()->kind == Value::Kind::Ref)
                addRef(out, textures.front()->refId, "height");
            else
                texture(*textures.front()->object, out, "height");
            copyFloat(e, "scale", out, "scale");
            nestedBSDFs(e, out, 1, 1);
        } else if (type == "normalmap") {
            // Declared by id and used by <ref>: the nested BSDF under the id ID.bsdf; the
            // shape that refers to it gets the normal map (normalMapOnShape).
            const std::vector<const Value *> nested = e.childrenOf("bsdf");
            if (nested.size() != 1)
                throw LocatedError(e.location, "normalmap holds one nested BSDF");
            e.find("normalmap");
            if (nested.front()->kind == Value::Kind::Object) {
                bsdf(*nested.front()->object, parent);
                parent.last_child().remove_attribute("id");
                parent.last_child().append_attribute("id") = (e.id + ".bsdf").c_str();
            }
            return;
        } else if (type == "mask") {
            make("mask");
            copyFloatOrTexture(e, "opacity", out, "opacity");
            nestedBSDFs(e, out, 1, 1);
        } else if (type == "blendbsdf") {
            make("blendbsdf");
            copyFloatOrTexture(e, "weight", out, "weight");
            nestedBSDFs(e, out, 2, 2);
        } else if (type == "principled") {
            principled(e, parent);
            return;
        } else if (type == "null") {
            make("null");
        } else if (type == "difftrans") {
            make("diffusetransmission");
            addColor(out, "reflectance", Color3f(0.0f));
            copyColor(e, "transmittance", out, "transmittance");
            if (!e.has("transmittance"))
                addColor(out, "transmittance", Color3f(0.5f));
        } else if (type == "phong" || type == "ward") {
            // Kd/π plus a glossy lobe: our rough plastic with the lobe's width.
            make("roughplastic");
            copyColor(e, "diffuseReflectance", out, "diffuseReflectance");
            copyColor(e, "specularReflectance", out, "specularReflectance");
            float alpha = 0.1f;
            if (type == "phong") {
                const float exponent = getFloat(e, "exponent", 30.0f);
                alpha = std::sqrt(2.0f / (exponent + 2.0f));
            } else {
                const float au = getFloat(e, "alphaU", 0.1f), av = getFloat(e, "alphaV", 0.1f);
                alpha = std::sqrt(au * av);
                ignore(e, {"variant"});
            }
            addString(out, "distribution", "beckmann");
            addFloat(out, "alpha", std::clamp(alpha, 1e-3f, 1.0f));
            warn(e.location, "bsdf-" + type,
                 fmt::format("{} is approximated by roughplastic (Beckmann, alpha = {:.3g}, "
                             "intIOR 1.49): a Fresnel-weighted coat instead of its lobe",
                             type, alpha));
        } else if (type == "coating" || type == "roughcoating") {
            warn(e.location, "bsdf-" + type,
                 fmt::format("{} is rendered as its nested BSDF, without the coat", type));
            ignore(e, {"intIOR", "extIOR", "thickness", "sigmaA", "specularReflectance", "alpha",
                       "distribution"});
            const std::vector<const Value *> nested = e.childrenOf("bsdf");
            if (nested.size() != 1)
                throw LocatedError(e.location, fmt::format("{} holds one nested BSDF", type));
            if (nested.front()->kind == Value::Kind::Ref)
                throw LocatedError(nested.front()->location,
                                   "a coating's nested BSDF by <ref> is not supported");
            bsdf(*nested.front()->object, parent);
            if (!e.id.empty())
                parent.last_child().append_attribute("id") = e.id.c_str();
            return;
        } else {
            static const std::vector<std::string> known = {"diffuse",
                                                           "roughdiffuse",
                                                           "twosided",
                                                           "plastic",
                                                           "roughplastic",
                                                           "conductor",
                                                           "roughconductor",
                                                           "dielectric",
                                                           "roughdielectric",
                                                           "thindielectric",
                                                           "bumpmap",
                                                           "normalmap",
                                                           "mask",
                                                           "blendbsdf",
                                                           "principled",
                                                           "null",
                                                           "difftrans",
                                                           "phong",
                                                           "ward",
                                                           "coating",
                                                           "roughcoating",
                                                           "hk",
                                                           "irawan",
                                                           "dipole",
                                                           "mixturebsdf",
                                                           "sssbrdf",
                                                           "polarizer",
                                                           "retarder"};
            if (std::find(known.begin(), known.end(), type) == known.end())
                throw LocatedError(
                    e.location, fmt::format("unknown bsdf '{}'{}", type, didYouMean(type, known)));
            warn(e.location, "bsdf-" + type,
                 fmt::format("the '{}' BSDF is not supported: a grey diffuse stands in", type));
            for (const auto &[name, value] : e.properties)
                e.find(name);
            make("diffuse");
        }
        finish(e);
    }

    /// Mitsuba 3's principled BSDF onto our disney.
    void principled(const Element &e, pugi::xml_node parent) {
        pugi::xml_node out = addObject(parent, "bsdf", "disney", e.name);
        identify(e, out);
        // Mitsuba 3's defaults where ours differ: base_color 0.5, clearcoat_gloss 0.
        if (e.has("baseColor"))
            copyColor(e, "baseColor", out, "baseColor");
        else
            addColor(out, "baseColor", Color3f(0.5f));
        if (!e.has("clearcoatGloss"))
            addFloat(out, "clearcoatGloss", 0.0f);
        for (const auto &[mitsuba, ours] : std::vector<std::pair<const char *, const char *>>{
                 {"roughness", "roughness"},
                 {"metallic", "metallic"},
                 {"specular", "specular"},
                 {"specTint", "specularTint"},
                 {"anisotropic", "anisotropic"},
                 {"sheen", "sheen"},
                 {"sheenTint", "sheenTint"},
                 {"clearcoat", "clearcoat"},
                 {"clearcoatGloss", "clearcoatGloss"}})
            copyFloatOrTexture(e, mitsuba, out, ours);
        if (e.has("eta") && !e.has("specular")) {
            // Mitsuba 3: specular = ((η − 1)/(η + 1))² / 0.08.
            const float eta = getFloat(e, "eta", 1.5f);
            const float f0 = (eta - 1.0f) / (eta + 1.0f);
            addFloat(out, "specular", f0 * f0 / 0.08f);
        } else {
            e.find("eta");
        }
        if (e.has("specTrans") && getFloat(e, "specTrans", 0.0f) > 0.0f)
            warn(e.location, "principled-specTrans",
                 "principled: specular transmission (spec_trans) is not supported: opaque");
        e.find("specTrans");
        ignore(e, {"diffuseReflectanceSampleRate", "mainSpecularSampleRate", "clearcoatSampleRate",
                   "flatness"});
        finish(e);
    }

    // ---- Textures ----

    /// A texture's (uscale, vscale, uoffset, voffset): Mitsuba 0.6's parameters, or the
    /// scale and offset of Mitsuba 3's to_uv.
    std::array<float, 4> uvMap(const Element &e) {
        std::array<float, 4> map = {getFloat(e, "uscale", 1.0f), getFloat(e, "vscale", 1.0f),
                                    getFloat(e, "uoffset", 0.0f), getFloat(e, "voffset", 0.0f)};
        if (const auto toUV = getTransform(e, "toUv")) {
            const Eigen::Matrix4d &m = toUV->matrix;
            if (m(0, 1) != 0.0 || m(1, 0) != 0.0)
                warn(e.location, "to_uv",
                     "a rotated to_uv is not supported: its scale and offset are used");
            map = {float(m(0, 0)), float(m(1, 1)), float(m(0, 3)), float(m(1, 3))};
        }
        return map;
    }

    void texture(const Element &e, pugi::xml_node parent, const std::string &name) {
        textureNode(e, parent, name);
    }

    /// Mitsuba decodes every 8-bit bitmap as sRGB unless told otherwise (0.6: `gamma`, 3:
    /// `raw`), height and normal maps included.
    pugi::xml_node textureNode(const Element &e, pugi::xml_node parent, const std::string &name) {
        pugi::xml_node out;
        const std::string ourName = name.empty() ? e.name : name;
        if (e.type == "bitmap") {
            out = addObject(parent, "texture", "image", ourName);
            identify(e, out);
            copyFilename(e, "filename", out, "filename");
            std::string filter = toLower(getString(e, "filterType", "ewa"));
            if (filter != "ewa" && filter != "trilinear" && filter != "nearest" &&
                filter != "bilinear")
                throw LocatedError(e.location, fmt::format("filterType must be ewa, trilinear, "
                                                           "bilinear or nearest, got '{}'",
                                                           filter));
            addString(out, "filter", filter);
            std::string wrap = toLower(getString(e, "wrapMode", "repeat"));
            const std::string wrapU = toLower(getString(e, "wrapModeU", wrap));
            const std::string wrapV = toLower(getString(e, "wrapModeV", wrap));
            if (wrapU != wrapV)
                warn(e.location, "wrap-uv",
                     "different wrap modes in u and v: both are "
                     "wrapModeU's");
            wrap = wrapU;
            if (wrap == "zero" || wrap == "one") {
                warn(e.location, "wrap-" + wrap,
                     fmt::format("wrapMode '{}' is rendered as clamp", wrap));
                wrap = "clamp";
            }
            if (wrap != "repeat" && wrap != "mirror" && wrap != "clamp")
                throw LocatedError(e.location,
                                   fmt::format("wrapMode must be repeat, mirror, clamp, zero or "
                                               "one, got '{}'",
                                               wrap));
            addString(out, "wrap", wrap);
            if (e.has("gamma"))
                addFloat(out, "gamma", getFloat(e, "gamma", -1.0f));
            else if (getBoolean(e, "raw", false))
                addString(out, "colorSpace", "linear");
            // Mitsuba looks up uv·(uscale, vscale) + (uoffset, voffset) with v = 0 at the
            // image's top row, ours with v = 0 at the bottom (the shapes' uv being the same:
            // see obj): v runs the other way, from 1 − voffset.
            const auto [uscale, vscale, uoffset, voffset] = uvMap(e);
            child(out, "vector", "uvScale", fmt::format("{}, {}", number(uscale), number(-vscale)));
            child(out, "vector", "uvOffset",
                  fmt::format("{}, {}", number(uoffset), number(1.0f - voffset)));
            ignore(e, {"maxAnisotropy", "cache", "channel", "format"});
            if (e.has("maxAnisotropy"))
                copyFloat(e, "maxAnisotropy", out, "maxAnisotropy");
        } else if (e.type == "checkerboard") {
            // Cells of ½ in (u·uscale + uoffset, v·vscale + voffset), even ones color0.
            out = addObject(parent, "texture", "checkerboard_color", ourName);
            identify(e, out);
            const auto [uscale, vscale, uoffset, voffset] = uvMap(e);
            child(out, "vector", "scale",
                  fmt::format("{}, {}", number(0.5f / uscale), number(0.5f / vscale)));
            child(out, "point", "delta",
                  fmt::format("{}, {}", number(-2.0f * uoffset), number(-2.0f * voffset)));
            addColor(out, "value1",
                     constantColor(e, "color0", Intent::Reflectance).value_or(Color3f(0.4f)));
            addColor(out, "value2",
                     constantColor(e, "color1", Intent::Reflectance).value_or(Color3f(0.2f)));
        } else if (e.type == "scale") {
            out = addObject(parent, "texture", "scale", ourName);
            identify(e, out);
            copyColor(e, "value", out, "tex");
            const std::vector<const Value *> nested = e.childrenOf("texture");
            for (const Value *child : nested) {
                if (child->kind == Value::Kind::Ref)
                    addRef(out, child->refId, "tex");
                else
                    texture(*child->object, out, "tex");
            }
            copyFloatOrTexture(e, "scale", out, "scale");
        } else {
            static const std::vector<std::string> known = {
                "bitmap",    "checkerboard", "scale",          "gridtexture", "wireframe",
                "curvature", "vertexcolors", "mesh_attribute", "volume"};
            if (std::find(known.begin(), known.end(), e.type) == known.end())
                throw LocatedError(e.location, fmt::format("unknown texture '{}'{}", e.type,
                                                           didYouMean(e.type, known)));
            warn(e.location, "texture-" + e.type,
                 fmt::format("the '{}' texture is not supported: a grey 0.5 stands in", e.type));
            for (const auto &[property, value] : e.properties)
                e.find(property);
            out = addObject(parent, "texture", "constant", ourName);
            identify(e, out);
            addColor(out, "value", Color3f(0.5f));
        }
        finish(e);
        return out;
    }

    // ---- Emitters ----

    void emitter(const Element &e, pugi::xml_node parent) {
        const std::string &type = e.type;
        pugi::xml_node out;
        const auto position = [&]() -> Vector3f {
            if (const auto p = getPoint(e, "position"))
                return *p;
            if (const auto t = getTransform(e, "toWorld"))
                return t->matrix.block<3, 1>(0, 3).cast<float>();
            return Vector3f(0.0f);
        };
        e.find("samplingWeight");
        if (type == "area") {
            out = addObject(parent, "emitter", "area");
            copyColor(e, "radiance", out, "radiance", Intent::Illuminant);
        } else if (type == "point") {
            out = addObject(parent, "emitter", "point");
            addPoint(out, "position", position());
            addColor(out, "intensity",
                     constantColor(e, "intensity", Intent::Illuminant).value_or(Color3f(1.0f)));
        } else if (type == "spot") {
            out = addObject(parent, "emitter", "spot");
            copyTransform(e, "toWorld", out, "toWorld");
            addColor(out, "intensity",
                     constantColor(e, "intensity", Intent::Illuminant).value_or(Color3f(1.0f)));
            const float cutoff = getFloat(e, "cutoffAngle", 20.0f);
            addFloat(out, "cutoffAngle", cutoff);
            addFloat(out, "beamWidth", getFloat(e, "beamWidth", cutoff * 0.75f));
            addString(out, "falloff", "linear");
            if (e.has("texture"))
                warn(e.location, "spot-texture", "spot: a projected texture is not supported");
            e.find("texture");
        } else if (type == "directional") {
            out = addObject(parent, "emitter", "directional");
            Vector3f direction(0.0f, 0.0f, 1.0f);
            if (const auto d = getPoint(e, "direction"))
                direction = *d;
            else if (const auto t = getTransform(e, "toWorld"))
                direction =
                    (t->matrix.topLeftCorner<3, 3>() * Eigen::Vector3d(0, 0, 1)).cast<float>();
            addVector(out, "direction", direction);
            addColor(out, "irradiance",
                     constantColor(e, "irradiance", Intent::Illuminant).value_or(Color3f(1.0f)));
        } else if (type == "envmap") {
            out = addObject(parent, "emitter", "envmap");
            copyFilename(e, "filename", out, "filename");
            copyFloat(e, "scale", out, "scale");
            copyTransform(e, "toWorld", out, "toWorld");
            if (e.has("gamma"))
                warn(e.location, "envmap-gamma",
                     "envmap: gamma is not supported (HDR images "
                     "are linear)");
            ignore(e, {"gamma", "cache", "blur"});
        } else if (type == "constant") {
            out = addObject(parent, "emitter", "constant");
            addColor(out, "radiance",
                     constantColor(e, "radiance", Intent::Illuminant).value_or(Color3f(1.0f)));
        } else if (type == "sunsky" || type == "sky" || type == "sun") {
            skyStandIn(e, parent);
            return;
        } else {
            static const std::vector<std::string> known = {
                "area",     "point",  "spot", "directional", "envmap",
                "constant", "sunsky", "sky",  "sun",         "collimated"};
            if (std::find(known.begin(), known.end(), type) == known.end())
                throw LocatedError(e.location, fmt::format("unknown emitter '{}'{}", type,
                                                           didYouMean(type, known)));
            warn(e.location, "emitter-" + type,
                 fmt::format("the '{}' emitter is not supported: left out", type));
            for (const auto &[name, value] : e.properties)
                e.find(name);
            return;
        }
        finish(e);
    }

    /// Mitsuba's sun and sky (Hošek-Wilkie 2012 in 0.5 and later) are not built here: the
    /// sun becomes a distant disk of the sun's size in its direction, the sky a constant
    /// light of the sky's mean colour, both stated in one warning.
    void skyStandIn(const Element &e, pugi::xml_node parent) {
        Vector3f sunDirection(0.0f, 1.0f, 0.0f);
        bool haveDirection = false;
        if (const auto d = getPoint(e, "sunDirection")) {
            sunDirection = d->normalized();
            haveDirection = true;
        }
        const float scale = getFloat(e, "scale", 1.0f);
        ignore(e, {"turbidity", "albedo", "year", "month", "day", "hour", "minute", "second",
                   "latitude", "longitude", "timezone", "stretch", "resolution", "skyScale",
                   "sunScale", "sunRadiusScale", "extend", "toWorld"});
        if (e.type != "sky") {
            // A cap of the sun's angular radius (0.2667°) toward it, of the radiance that
            // gives an irradiance 6 × the sky's (a clear noon), L = E / (π sin² θ).
            constexpr float kSunRadius = 0.2667f;
            pugi::xml_node sun = addObject(parent, "emitter", "distantdisk");
            addFloat(sun, "thetaA", kSunRadius);
            const float sinTheta = std::sin(degToRad(kSunRadius));
            addColor(sun, "radiance",
                     Color3f(1.0f, 0.93f, 0.85f) * (6.0f * scale / (kPi * sinTheta * sinTheta)));
            const Vector3f up = std::abs(sunDirection.y()) > 0.9f ? Vector3f(0.0f, 0.0f, 1.0f)
                                                                  : Vector3f(0.0f, 1.0f, 0.0f);
            pugi::xml_node transform = sun.append_child("transform");
            transform.append_attribute("name") = "toWorld";
            pugi::xml_node lookat = transform.append_child("lookat");
            lookat.append_attribute("origin") = "0, 0, 0";
            lookat.append_attribute("target") = triple(sunDirection).c_str();
            lookat.append_attribute("up") = triple(up).c_str();
        }
        if (e.type != "sun") {
            pugi::xml_node sky = addObject(parent, "emitter", "constant");
            addColor(sky, "radiance", Color3f(0.35f, 0.5f, 0.8f) * scale);
        }
        warn(e.location, "sky-" + e.type,
             fmt::format("the '{}' emitter (Hošek-Wilkie sky, Preetham sun) is not built here: "
                         "{}{}{}{}",
                         e.type, e.type != "sky" ? "a distant disk of the sun's size" : "",
                         e.type == "sunsky" ? " and " : "",
                         e.type != "sun" ? "a constant sky of a clear sky's mean colour" : "",
                         e.type == "sky" || haveDirection
                             ? ""
                             : " (no sunDirection: the sun is overhead)"));
        finish(e);
    }

    // ---- Media and phase functions ----

    /// Where a gridvolume's values lie, as our heterogeneous medium's parameters say it.
    struct GridPlacement {
        std::string valuesAt;
        bool fileBounds = true;
        TransformOps toWorld;
    };

    /// A gridvolume onto our heterogeneous medium `out`: its file as `ours`, and for the
    /// first grid (`density` null) the placement, which a second grid must share.
    /// Mitsuba 0.6 puts value i at i/(n - 1) of the file's bounding box (or of `min`,
    /// `max`); Mitsuba 3 at voxel centres of the unit cube, or of the file's box with
    /// use_grid_bbox (Mitsuba 0.6 and 3, gridvolume).
    GridPlacement gridVolume(const Element &grid, pugi::xml_node out, const char *ours,
                             const GridPlacement *density) {
        copyFilename(grid, "filename", out, ours);
        GridPlacement placement;
        placement.valuesAt = m_snakeCase ? "centres" : "corners";
        placement.toWorld = getTransform(grid, "toWorld").value_or(TransformOps{});
        if (m_snakeCase) {
            placement.fileBounds = getBoolean(grid, "useGridBbox", false);
            if (getString(grid, "filterType", "trilinear") != "trilinear")
                warn(grid.location, "gridvolume-filter",
                     "gridvolume: only trilinear interpolation is supported");
            if (getString(grid, "wrapMode", "clamp") != "clamp")
                warn(grid.location, "gridvolume-wrap",
                     "gridvolume: only the clamp wrap mode is supported (zero outside the grid)");
            ignore(grid, {"raw", "accel", "maxValue"});
        } else {
            const auto lower = getPoint(grid, "min"), upper = getPoint(grid, "max");
            if (lower.has_value() != upper.has_value())
                throw LocatedError(grid.location, "gridvolume: give both min and max, or neither");
            if (lower) {
                // The unit cube onto [min, max], then toWorld.
                placement.fileBounds = false;
                TransformOps box;
                box.ops.push_back({"scale", {{"value", triple(*upper - *lower)}}});
                box.ops.push_back({"translate", {{"value", triple(*lower)}}});
                box.ops.insert(box.ops.end(), placement.toWorld.ops.begin(),
                               placement.toWorld.ops.end());
                placement.toWorld = box;
            }
            ignore(grid, {"sendData"});
        }
        if (density) {
            if (density->fileBounds != placement.fileBounds ||
                density->toWorld.ops != placement.toWorld.ops)
                throw LocatedError(grid.location,
                                   "heterogeneous: the albedo grid must lie where the density "
                                   "grid lies (same to_world, bounds)");
        } else {
            if (placement.valuesAt != "centres")
                addString(out, "valuesAt", placement.valuesAt);
            if (!placement.fileBounds)
                addBoolean(out, "fileBounds", false);
            writeTransform(out, "toWorld", placement.toWorld);
        }
        finish(grid);
        return placement;
    }

    void medium(const Element &e, pugi::xml_node parent, const std::string &name = "") {
        pugi::xml_node out;
        const std::string ourName = name.empty() ? e.name : name;
        if (e.type == "homogeneous") {
            out = addObject(parent, "medium", "homogeneous", ourName);
            identify(e, out);
            if (e.has("material"))
                throw LocatedError(e.find("material")->location,
                                   "homogeneous: a named material ('material') is not supported: "
                                   "give sigmaS and sigmaA");
            copyColor(e, "sigmaS", out, "sigmaS");
            copyColor(e, "sigmaA", out, "sigmaA");
            copyColor(e, "sigmaT", out, "sigmaT");
            copyColor(e, "albedo", out, "albedo");
            copyFloat(e, "scale", out, "scale");
        } else if (e.type == "heterogeneous") {
            // Mitsuba 0.6 names the extinction grid `density`, Mitsuba 3 `sigma_t`.
            const char *densityName = m_snakeCase ? "sigmaT" : "density";
            const Value *density = e.find(densityName);
            const Value *albedo = e.find("albedo");
            const auto isGrid = [](const Value *v) {
                return v && v->kind == Value::Kind::Object && v->object->type == "gridvolume";
            };
            if (m_snakeCase && density && density->kind != Value::Kind::Object &&
                density->kind != Value::Kind::Ref && !isGrid(albedo)) {
                // Mitsuba 3's heterogeneous medium of constant sigma_t and albedo is ours,
                // homogeneous.
                out = addObject(parent, "medium", "homogeneous", ourName);
                identify(e, out);
                addColor(out, "sigmaT", colorOf(*density, Intent::Reflectance));
                if (albedo)
                    addColor(out, "albedo", colorOf(*albedo, Intent::Reflectance));
                copyFloat(e, "scale", out, "scale");
            } else {
                if (!isGrid(density))
                    throw LocatedError(density ? density->location : e.location,
                                       fmt::format("heterogeneous needs <volume "
                                                   "type=\"gridvolume\" name=\"{}\">",
                                                   m_snakeCase ? "sigma_t" : "density"));
                out = addObject(parent, "medium", "heterogeneous", ourName);
                identify(e, out);
                const GridPlacement placement =
                    gridVolume(*density->object, out, "filename", nullptr);
                if (isGrid(albedo)) {
                    gridVolume(*albedo->object, out, "albedoFilename", &placement);
                } else if (albedo && albedo->kind == Value::Kind::Object &&
                           albedo->object->type == "constvolume") {
                    addColor(out, "albedo",
                             constantColor(*albedo->object, "value", Intent::Reflectance)
                                 .value_or(Color3f(0.5f)));
                    finish(*albedo->object);
                } else if (albedo) {
                    addColor(out, "albedo", colorOf(*albedo, Intent::Reflectance));
                }
                copyFloat(e, "scale", out, "scale");
                ignore(e, {"method", "stepSize", "sampleEmitters", "hasSpectralExtinction"});
            }
        } else {
            throw LocatedError(e.location,
                               fmt::format("unknown medium '{}'{}", e.type,
                                           didYouMean(e.type, {"homogeneous", "heterogeneous"})));
        }
        for (const Value &child : e.children) {
            if (child.tag != "phase" || child.kind != Value::Kind::Object)
                throw LocatedError(child.location,
                                   fmt::format("a <{}> does not belong in a <medium>", child.tag));
            phase(*child.object, out);
        }
        finish(e);
    }

    void phase(const Element &e, pugi::xml_node parent) {
        pugi::xml_node out;
        if (e.type == "isotropic") {
            out = addObject(parent, "phase", "isotropic");
        } else if (e.type == "hg") {
            out = addObject(parent, "phase", "hg");
            copyFloat(e, "g", out, "g");
        } else {
            static const std::vector<std::string> known = {
                "isotropic", "hg", "rayleigh", "kkay", "microflake", "mixturephase"};
            if (std::find(known.begin(), known.end(), e.type) == known.end())
                throw LocatedError(e.location, fmt::format("unknown phase function '{}'{}", e.type,
                                                           didYouMean(e.type, known)));
            warn(e.location, "phase-" + e.type,
                 fmt::format("the '{}' phase function is not supported: isotropic stands in",
                             e.type));
            for (const auto &[name, value] : e.properties)
                e.find(name);
            out = addObject(parent, "phase", "isotropic");
        }
        identify(e, out);
        finish(e);
    }

    const ConvertOptions &m_options;
    bool m_snakeCase;
    pugi::xml_document m_document;
    pugi::xml_node m_root;
    std::map<std::string, const Element *> m_declared;
    std::vector<std::string> m_warnings;
    std::set<std::pair<std::string, std::string>> m_warned;
};

} // namespace

Conversion convertText(const std::string &text, const std::string &path,
                       const ConvertOptions &options) {
    std::vector<std::unique_ptr<Source>> sources;
    Reader reader(options, sources);
    const std::shared_ptr<Element> scene = reader.readScene(text, path);
    Converter converter(options, reader.snakeCase());
    return converter.convert(*scene, reader.variables());
}

Conversion convertFile(const std::string &path, const ConvertOptions &options) {
    return convertText(readTextFile(path, "Mitsuba scene"), path, options);
}

bool isMitsubaFile(const std::string &path) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return false;
    // The <scene> element is near the top: after the declaration and comments.
    std::string head(16384, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(size_t(in.gcount()));
    static const std::regex sceneWithVersion(R"(<scene\b[^>]*\bversion\s*=)");
    return std::regex_search(head, sceneWithVersion);
}

} // namespace nori::mitsuba
