// The parameter list of one pbrt-v4 entity as the importer reads it: every name checked
// against what pbrt-v4 reads for that plugin type (an unknown one is an error with a
// suggestion, as pbrt-v4's "parameter unused" is), values read by pbrt-v4's types, and
// spectra turned into our RGB by the one rule of pbrtimport.h.
#pragma once

#include <nori/color.h>
#include <nori/pbrtscene.h>
#include <nori/vector.h>

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace nori::pbrt {

/// How a spectral parameter is meant, which decides how a spectrum becomes RGB.
enum class SpectrumKind {
    Reflectance, ///< an albedo in [0, 1]: rgb as given, spectra under D65
    Unbounded,   ///< η, k, σ: rgb as given, spectra under D65
    Illuminant,  ///< a light: rgb as given, spectra and blackbodies at luminance 1
};

/// A spectral or float parameter's value: a constant colour, or a texture's name.
struct TextureValue {
    Color3f constant = Color3f(0.0f);
    std::string texture; ///< the texture named by a "texture" parameter, else ""
    bool isTexture() const { return !texture.empty(); }
};

/// Warnings of a conversion: one per feature and file, each starting with where it was
/// first seen.
class Warnings {
public:
    void add(const Location &where, const std::string &feature, const std::string &message);
    const std::vector<std::string> &lines() const { return m_lines; }

private:
    std::set<std::pair<std::string, std::string>> m_seen; ///< (file, feature)
    std::vector<std::string> m_lines;
};

class Parameters {
public:
    /// Checks every parameter of `entity` against `known` (pbrt-v4's names for its type);
    /// `what` names the entity in messages ("material 'conductor'"). Throws LocatedError.
    Parameters(const Entity &entity, std::string what, const std::vector<std::string> &known);

    const Entity &entity() const { return m_entity; }
    const std::string &what() const { return m_what; }
    const Parameter *find(const std::string &name) const { return m_entity.find(name); }
    bool has(const std::string &name) const { return find(name) != nullptr; }

    float getFloat(const std::string &name, float defaultValue) const;
    int getInt(const std::string &name, int defaultValue) const;
    bool getBool(const std::string &name, bool defaultValue) const;
    std::string getString(const std::string &name, const std::string &defaultValue) const;
    /// A point3, vector3 or normal3 parameter.
    Vector3f getVector(const std::string &name, const Vector3f &defaultValue) const;
    /// Arrays: floats (also of point/vector/normal/rgb types), integers, strings.
    std::vector<float> getFloats(const std::string &name) const;
    std::vector<int> getInts(const std::string &name) const;
    std::vector<std::string> getStrings(const std::string &name) const;

    /// A spectral parameter (rgb, spectrum, blackbody, a float as grey, or a texture) as
    /// RGB or a texture name; `defaultValue` when absent. `directory` resolves .spd files.
    TextureValue getSpectrum(const std::string &name, SpectrumKind kind,
                             const Color3f &defaultValue, const std::string &directory) const;
    /// A float parameter that may be a texture.
    TextureValue getFloatTexture(const std::string &name, float defaultValue) const;

    /// Throws a LocatedError at the parameter.
    [[noreturn]] void fail(const Parameter &parameter, const std::string &message) const;

private:
    const Parameter &typed(const std::string &name,
                           std::initializer_list<const char *> types) const;

    const Entity &m_entity;
    std::string m_what;
};

/// The RGB of a spectrum given as (λ, value) pairs, a pbrt-v4 named spectrum or a .spd
/// file (relative to `directory`), read as `kind` says.
Color3f spectrumToRGB(const Parameter &parameter, SpectrumKind kind, const std::string &directory);

/// The index of refraction a spectral `eta` stands for in RGB: its value at 550 nm.
float spectrumAt550(const Parameter &parameter, const std::string &directory);

} // namespace nori::pbrt
