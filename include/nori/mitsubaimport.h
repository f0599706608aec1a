// Mitsuba scenes in our scene format: a Mitsuba 0.4–0.6 file (camelCase parameters) or a
// Mitsuba 2/3 file (snake_case), told apart by the `version` of its <scene>, mapped onto
// our plugins and written as our XML, which our XML parser then loads through the one
// object factory. Rendering a Mitsuba file and rendering its `nori convert` output are
// therefore the same load of the same XML: the same objects, the same image bit for bit.
//
// The conventions (docs/mitsuba-scenes.md has the whole table):
// - Most plugins have Mitsuba's names and parameters here already (ours follow Mitsuba
//   0.6's documentation); the others are renamed, and a Mitsuba plugin we do not have is
//   mapped onto the nearest of ours with one warning naming the stand-in.
// - Cameras: Mitsuba's image x is mirrored as Nori 2's (our default convention); `fov`
//   is converted to the horizontal one we take (fovAxis x, y, diagonal, smaller, larger;
//   focalLength in 35 mm film equivalent, measured along the diagonal, as Mitsuba does).
// - Depths: Mitsuba's maxDepth counts path vertices (1: only emitters seen), ours
//   bounces after the camera ray, so ours is one less; -1 stays unbounded.
// - Colours: <rgb> as given, <srgb> and hex colours decoded from sRGB, <spectrum> and
//   <blackbody> integrated against CIE 1931 (spectrum.h): under D65 for reflectances, as
//   they are for the radiance of lights.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace nori::mitsuba {

struct ConvertOptions {
    /// Values of the file's $name variables (nori -D name=value); they win over the
    /// file's <default> elements.
    std::map<std::string, std::string> defines;
    /// Where the XML will be read from: file names in it are written relative to this.
    std::string xmlDirectory = ".";
};

struct Conversion {
    std::string xml;                   ///< our scene
    std::vector<std::string> warnings; ///< one per stand-in and file: what was substituted
    /// The $name variables the file declares with <default> or uses, for -D checks.
    std::vector<std::string> variables;
};

/// Reads a Mitsuba scene file (with its <include>s) and maps it onto our plugins.
/// Throws LocatedError ("file:line:column: ...") for malformed XML, an unknown plugin or
/// parameter (with a suggestion), a value of the wrong type, an undefined $name or <ref>.
Conversion convertFile(const std::string &path, const ConvertOptions &options);

/// As convertFile, for the text of a file at `path` (which locates its relative names).
Conversion convertText(const std::string &text, const std::string &path,
                       const ConvertOptions &options);

/// Whether `path` is a Mitsuba scene: an XML file whose <scene> has a `version`
/// attribute (ours never has one). False for a file that cannot be read.
bool isMitsubaFile(const std::string &path);

} // namespace nori::mitsuba
