// pbrt-v4 scenes in our scene format: the entities of a pbrt::Scene (pbrtscene.h) mapped
// onto our plugins and written as our XML, which our XML parser then loads through the
// one object factory. Rendering a .pbrt file and rendering its `nori convert` output are
// therefore the same load of the same XML: the same objects, the same image bit for bit.
//
// The conventions (docs/pbrt-scenes.md has the whole table):
// - pbrt-v4's surfaces reflect on both sides; ours, as Nori 2's and Mitsuba's, on the front
//   only, so every reflecting BSDF is wrapped in `twosided`. ReverseOrientation and a
//   transform that mirrors turn a shape's normals as pbrt-v4 turns them (which side emits,
//   which side is inside a dielectric or a medium).
// - Colours: an `rgb` reflectance is taken as it is; an `rgb` illuminant is that colour
//   (pbrt-v4 renders "rgb L [1 1 1]" as 1 in sRGB); spectra, named or written out, and
//   blackbodies are integrated against CIE 1931 (spectrum.h), illuminants then scaled to a
//   luminance of 1 as pbrt-v4 scales them (its lights divide by SpectrumToPhotometric).
// - pbrt-v4's camera looks along +z with +x to the image's right: our "eth" convention,
//   and `fov` spans the image's shorter axis.
#pragma once

#include <nori/pbrtscene.h>

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace nori::pbrt {

struct ConvertOptions {
    /// Where the pbrt-v4 file's relative file names resolve: its main file's folder.
    std::string sceneDirectory = ".";
    /// Where the XML will be read from: file names in it are written relative to this.
    std::string xmlDirectory = ".";
    /// Inline meshes (trianglemesh, bilinearmesh, loopsubdiv, tessellated quadrics) with
    /// more vertices than this are written as binary PLY files into `sideFileDirectory`;
    /// smaller ones stay in the XML as `trianglemesh` shapes.
    size_t inlineVertexLimit = std::numeric_limits<size_t>::max();
    /// Where PLY files and density grids (.vol, of `uniformgrid` media) are written;
    /// created when one is needed.
    std::string sideFileDirectory;
};

struct Conversion {
    std::string xml;                    ///< our scene
    std::string outputName;             ///< the Film's `filename`, "" when it names none
    std::vector<std::string> warnings;  ///< one per feature and file: what was substituted
    std::vector<std::string> sideFiles; ///< the files written into sideFileDirectory
};

/// Maps a scene onto our plugins. Throws LocatedError ("file:line:column: ...") for an
/// unknown plugin type or parameter (with a suggestion), a parameter of the wrong type, a
/// reference to a texture, material or medium that does not exist.
Conversion convertScene(const Scene &scene, const ConvertOptions &options);

/// Reads a pbrt-v4 file (readScene) and converts it, its folder as sceneDirectory.
Conversion convertFile(const std::string &path, ConvertOptions options);

/// Whether `path` names a pbrt-v4 file: .pbrt or .pbrt.gz (any case).
bool isPbrtFile(const std::string &path);

} // namespace nori::pbrt
