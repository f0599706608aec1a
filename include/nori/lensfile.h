// pbrt's tabular lens prescriptions (pbrt-v3 §6.4.1): one row per interface, front (the
// scene's side) to rear (the film's side), four numbers in millimetres and indices:
//
//   # curvature-radius  thickness  index-of-refraction  aperture-diameter
//   29.475              3.76       1.67                 25.2
//   0                   4.5        0                    17.1      <- the aperture stop
//
// Radius > 0: the centre of curvature lies toward the film (the surface bulges toward
// the scene); radius 0: a flat aperture stop. Thickness: the distance to the next
// interface (for the last row, to the film; focusing replaces it). Index: of the medium
// behind the interface, 0 meaning air. '#' starts a comment.
#pragma once

#include <string>
#include <vector>

namespace nori {

/// One interface of a lens prescription, in the file's millimetres.
struct LensInterfaceRow {
    double curvatureRadius; ///< 0 for the aperture stop
    double thickness;       ///< to the next interface, or to the film for the last row
    double eta;             ///< index of the medium behind (film side); 1 for air
    double apertureDiameter;
    int line; ///< where it stands in the file, for later errors
};

/// Parses a prescription; `fileName` only names it in errors. Throws NoriException
/// "file:line: ..." for a malformed row (not four finite numbers), a non-positive
/// aperture, a negative thickness, an index in (0, 1), a surface narrower than its
/// aperture (|radius| < aperture / 2), a stop between two different media, and a file
/// without rows or without a refracting surface. Index 0 is read as 1 (air). A file may
/// hold several stops: the first is the iris, the others are fixed (flare stops).
std::vector<LensInterfaceRow> parseLensPrescription(const std::string &text,
                                                    const std::string &fileName);

/// Reads and parses a lens file (see parseLensPrescription).
std::vector<LensInterfaceRow> readLensFile(const std::string &path);

} // namespace nori
