// Reading the parameters of pbrt-v4 entities (see pbrtparams.h).
#include "import/pbrtparams.h"

#include <nori/spectrum.h>
#include <nori/strutil.h>

#include <filesystem>

namespace nori::pbrt {

namespace fs = std::filesystem;

void Warnings::add(const Location &where, const std::string &feature, const std::string &message) {
    // A default entity (pbrt-v4's sampler when the file names none) stands nowhere.
    if (m_seen.emplace(where.file, feature).second)
        m_lines.push_back(where.file.empty() ? message : where.str() + ": " + message);
}

Parameters::Parameters(const Entity &entity, std::string what,
                       const std::vector<std::string> &known)
    : m_entity(entity), m_what(std::move(what)) {
    for (const Parameter &parameter : entity.parameters)
        if (std::find(known.begin(), known.end(), parameter.name) == known.end())
            fail(parameter, fmt::format("{} has no parameter '{}'{}", m_what, parameter.name,
                                        didYouMean(parameter.name, known)));
}

void Parameters::fail(const Parameter &parameter, const std::string &message) const {
    throw LocatedError(parameter.location.str(), message);
}

const Parameter &Parameters::typed(const std::string &name,
                                   std::initializer_list<const char *> types) const {
    const Parameter &parameter = *find(name);
    for (const char *type : types)
        if (parameter.type == type)
            return parameter;
    std::string expected;
    for (const char *type : types)
        expected += (expected.empty() ? "\"" : " or \"") + std::string(type) + " " + name + "\"";
    fail(parameter, fmt::format("{}: \"{} {}\" has the wrong type; expected {}", m_what,
                                parameter.type, name, expected));
}

namespace {

/// The single value of a parameter that takes one.
template <typename T>
T single(const Parameters &params, const Parameter &parameter, const std::vector<T> &values) {
    if (values.size() != 1)
        params.fail(parameter, fmt::format("{}: \"{} {}\" takes one value, got {}", params.what(),
                                           parameter.type, parameter.name, values.size()));
    return values.front();
}

} // namespace

float Parameters::getFloat(const std::string &name, float defaultValue) const {
    if (!has(name))
        return defaultValue;
    const Parameter &p = typed(name, {"float"});
    return float(single(*this, p, p.numbers));
}

int Parameters::getInt(const std::string &name, int defaultValue) const {
    if (!has(name))
        return defaultValue;
    const Parameter &p = typed(name, {"integer"});
    const double value = single(*this, p, p.numbers);
    if (value != std::floor(value) || std::abs(value) > 2e9)
        fail(p, fmt::format("{}: \"integer {}\" is {}, not an integer", m_what, name, value));
    return int(value);
}

bool Parameters::getBool(const std::string &name, bool defaultValue) const {
    if (!has(name))
        return defaultValue;
    const Parameter &p = typed(name, {"bool"});
    return single(*this, p, p.bools);
}

std::string Parameters::getString(const std::string &name, const std::string &defaultValue) const {
    if (!has(name))
        return defaultValue;
    const Parameter &p = typed(name, {"string"});
    return single(*this, p, p.strings);
}

Vector3f Parameters::getVector(const std::string &name, const Vector3f &defaultValue) const {
    if (!has(name))
        return defaultValue;
    const Parameter &p = typed(name, {"point3", "vector3", "normal3"});
    if (p.numbers.size() != 3)
        fail(p, fmt::format("{}: \"{} {}\" takes one triple, got {} numbers", m_what, p.type, name,
                            p.numbers.size()));
    return Vector3f(float(p.numbers[0]), float(p.numbers[1]), float(p.numbers[2]));
}

std::vector<float> Parameters::getFloats(const std::string &name) const {
    if (!has(name))
        return {};
    const Parameter &p =
        typed(name, {"float", "point2", "vector2", "point3", "vector3", "normal3", "rgb"});
    return {p.numbers.begin(), p.numbers.end()};
}

std::vector<int> Parameters::getInts(const std::string &name) const {
    if (!has(name))
        return {};
    const Parameter &p = typed(name, {"integer"});
    std::vector<int> values;
    values.reserve(p.numbers.size());
    for (double number : p.numbers) {
        if (number != std::floor(number) || std::abs(number) > 2e9)
            fail(p,
                 fmt::format("{}: \"integer {}\" holds {}, not an integer", m_what, name, number));
        values.push_back(int(number));
    }
    return values;
}

std::vector<std::string> Parameters::getStrings(const std::string &name) const {
    if (!has(name))
        return {};
    return typed(name, {"string"}).strings;
}

TextureValue Parameters::getSpectrum(const std::string &name, SpectrumKind kind,
                                     const Color3f &defaultValue,
                                     const std::string &directory) const {
    TextureValue value;
    value.constant = defaultValue;
    if (!has(name))
        return value;
    const Parameter &p = typed(name, {"rgb", "spectrum", "blackbody", "float", "texture"});
    if (p.type == "texture") {
        value.texture = single(*this, p, p.strings);
    } else if (p.type == "rgb") {
        if (p.numbers.size() != 3)
            fail(p, fmt::format("{}: \"rgb {}\" takes one colour, got {} numbers", m_what, name,
                                p.numbers.size()));
        value.constant = Color3f(float(p.numbers[0]), float(p.numbers[1]), float(p.numbers[2]));
        if (kind == SpectrumKind::Reflectance && (value.constant < 0.0f).any())
            fail(p, fmt::format("{}: \"rgb {}\" is a reflectance, which cannot be negative", m_what,
                                name));
    } else if (p.type == "float") {
        value.constant = Color3f(float(single(*this, p, p.numbers)));
    } else {
        value.constant = spectrumToRGB(p, kind, directory);
    }
    return value;
}

TextureValue Parameters::getFloatTexture(const std::string &name, float defaultValue) const {
    TextureValue value;
    value.constant = Color3f(defaultValue);
    if (!has(name))
        return value;
    const Parameter &p = typed(name, {"float", "texture"});
    if (p.type == "texture")
        value.texture = single(*this, p, p.strings);
    else
        value.constant = Color3f(float(single(*this, p, p.numbers)));
    return value;
}

namespace {

/// A spectrum parameter's spectrum: (λ, value) pairs, a named spectrum or a .spd file.
PiecewiseLinearSpectrum spectrumOf(const Parameter &p, const std::string &directory) {
    try {
        if (p.strings.empty()) {
            std::vector<float> interleaved(p.numbers.begin(), p.numbers.end());
            return {interleaved.data(), interleaved.size() / 2};
        }
        const std::string &name = p.strings.front();
        if (isNamedSpectrum(name))
            return namedSpectrum(name);
        const fs::path path =
            fs::path(name).is_absolute() ? fs::path(name) : fs::path(directory) / name;
        if (!fs::exists(path))
            throw NoriException(
                "'{}' is neither one of pbrt-v4's named spectra{} nor a file "
                "(looked for {})",
                name,
                didYouMean(name, {"metal-Au-eta", "metal-Au-k", "metal-Ag-eta", "metal-Ag-k",
                                  "metal-Al-eta", "metal-Al-k", "metal-Cu-eta", "metal-Cu-k",
                                  "metal-CuZn-eta", "metal-CuZn-k", "glass-BK7", "glass-BAF10",
                                  "glass-F11", "stdillum-D65"}),
                path.string());
        return readSpectrumFile(path.string());
    } catch (const LocatedError &) {
        throw;
    } catch (const NoriException &error) {
        throw LocatedError(p.location.str(),
                           fmt::format("\"spectrum {}\": {}", p.name, error.what()));
    }
}

} // namespace

Color3f spectrumToRGB(const Parameter &p, SpectrumKind kind, const std::string &directory) {
    if (p.type == "blackbody") {
        const float temperature = float(p.numbers.front());
        if (!(temperature > 0.0f))
            throw LocatedError(p.location.str(),
                               fmt::format("\"blackbody {}\" must be a positive temperature in "
                                           "kelvin, got {}",
                                           p.name, temperature));
        const Color3f rgb = emissionToRGB(
            [temperature](float lambda) { return normalizedBlackbody(lambda, temperature); });
        // As a light, pbrt-v4 scales a blackbody to a luminance of 1; elsewhere it is the
        // normalised spectrum itself.
        return kind == SpectrumKind::Illuminant ? Color3f(rgb / rgb.getLuminance()) : rgb;
    }
    const PiecewiseLinearSpectrum spectrum = spectrumOf(p, directory);
    if (kind == SpectrumKind::Illuminant) {
        const Color3f rgb = emissionToRGB([&spectrum](float lambda) { return spectrum(lambda); });
        const float luminance = rgb.getLuminance();
        if (!(luminance > 0.0f))
            throw LocatedError(p.location.str(),
                               fmt::format("\"spectrum {}\" emits no visible light", p.name));
        return rgb / luminance;
    }
    return reflectanceToRGB([&spectrum](float lambda) { return spectrum(lambda); });
}

float spectrumAt550(const Parameter &p, const std::string &directory) {
    if (p.type == "blackbody")
        throw LocatedError(p.location.str(),
                           fmt::format("\"blackbody {}\" is no index of refraction", p.name));
    return spectrumOf(p, directory)(550.0f);
}

} // namespace nori::pbrt
