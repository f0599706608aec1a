// The tables of spectraldata.cpp (see there for their sources), for spectrum.cpp.
#pragma once

#include <cstddef>

namespace nori::spectraldata {

/// The CIE 1931 2° colour matching functions x̄, ȳ, z̄ at 1 nm steps from kCieFirst nm.
constexpr size_t kCieSamples = 471;
constexpr float kCieFirst = 360.0f;
extern const float kCieX[kCieSamples], kCieY[kCieSamples], kCieZ[kCieSamples];

// (wavelength, value) pairs, interleaved: the D65 illuminant, metals' η and k, glasses' η.
extern const float kD65[];
extern const size_t kD65Size;
extern const float kAgEta[], kAgK[], kAlEta[], kAlK[], kAuEta[], kAuK[], kCuEta[], kCuK[],
    kCuZnEta[], kCuZnK[], kMgOEta[], kMgOK[], kTiO2Eta[], kTiO2K[];
extern const size_t kAgEtaSize, kAgKSize, kAlEtaSize, kAlKSize, kAuEtaSize, kAuKSize, kCuEtaSize,
    kCuKSize, kCuZnEtaSize, kCuZnKSize, kMgOEtaSize, kMgOKSize, kTiO2EtaSize, kTiO2KSize;
extern const float kGlassBK7[], kGlassBAF10[], kGlassFK51A[], kGlassLASF9[], kGlassF5[],
    kGlassF10[], kGlassF11[];
extern const size_t kGlassBK7Size, kGlassBAF10Size, kGlassFK51ASize, kGlassLASF9Size, kGlassF5Size,
    kGlassF10Size, kGlassF11Size;

/// A conductor Mitsuba 0.6 names, with its measured η and k as interleaved (λ, value)
/// pairs; the sizes count floats (mitsubaconductors.cpp).
struct MeasuredConductor {
    const char *name;
    const float *eta;
    size_t etaSize;
    const float *k;
    size_t kSize;
};
extern const MeasuredConductor kMitsubaConductors[];
extern const size_t kMitsubaConductorCount;

} // namespace nori::spectraldata
