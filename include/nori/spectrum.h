// Spectra and their RGB: the measured and analytic spectral distributions that scene files
// name (pbrt-v4's named spectra and .spd files, blackbody emitters), turned into the
// linear sRGB this renderer works in, once, when a scene is loaded.
//
// The method, one for every spectrum: integrate against the CIE 1931 2° colour matching
// functions at 1 nm from 360 to 830 nm (pbrt-v4's SpectrumToXYZ), then map XYZ to linear
// sRGB (IEC 61966-2-1's matrix, D65 white). An emission spectrum (a light) is integrated as
// it is, divided by ∫ȳ (so its Y is its photometric brightness relative to a flat 1); a
// reflectance or an optical constant (η, k) is integrated under D65 and divided by the
// Y of D65, so that a flat 1 comes out as white (1, 1, 1).
#pragma once

#include <nori/color.h>

#include <functional>
#include <string>
#include <vector>

namespace nori {

/// A spectrum tabulated at wavelengths (nm), linear between them and zero outside
/// (pbrt-v4's PiecewiseLinearSpectrum).
class PiecewiseLinearSpectrum {
public:
    PiecewiseLinearSpectrum() = default;
    /// From interleaved (λ, value) pairs with λ increasing; throws otherwise.
    PiecewiseLinearSpectrum(const float *interleaved, size_t count);
    PiecewiseLinearSpectrum(std::vector<float> lambdas, std::vector<float> values);
    float operator()(float lambda) const;
    bool empty() const { return m_lambdas.empty(); }

private:
    std::vector<float> m_lambdas, m_values;
};

/// pbrt-v4's named spectra: "metal-Ag-eta", "metal-Ag-k" and likewise for Al, Au, Cu,
/// CuZn, MgO, TiO2; "glass-BK7", "glass-BAF10", "glass-FK51A", "glass-LASF9", "glass-F5",
/// "glass-F10", "glass-F11"; "stdillum-D65". Throws NoriException (with a did-you-mean)
/// for other names.
const PiecewiseLinearSpectrum &namedSpectrum(const std::string &name);
/// Whether `name` is one of namedSpectrum's names.
bool isNamedSpectrum(const std::string &name);

/// A spectrum from a pbrt-v4 `.spd` file: whitespace-separated (λ, value) pairs, `#`
/// comments. Throws NoriException naming the file and line of what is malformed.
PiecewiseLinearSpectrum readSpectrumFile(const std::string &path);

/// Planck's law: the radiance a blackbody at temperature T (K) emits at λ (nm), in
/// W/(m²·sr·m).
double planck(double lambda, double temperature);
/// pbrt-v4's BlackbodySpectrum: Planck's law divided by its value at the peak
/// (Wien's displacement law, λ_max = 2.8977721 mm·K / T), so that its maximum is 1.
float normalizedBlackbody(float lambda, float temperature);

/// The linear sRGB of an emission spectrum (see above).
Color3f emissionToRGB(const std::function<float(float)> &spectrum);
/// The linear sRGB of a reflectance or an optical constant (see above).
Color3f reflectanceToRGB(const std::function<float(float)> &spectrum);
/// The linear sRGB of CIE XYZ (IEC 61966-2-1).
Color3f xyzToLinearSRGB(double x, double y, double z);

/// The CIE xy chromaticity of the daylight illuminant pbrt-v4 calls D(T) (its Spectra::D):
/// the temperature is corrected to the CCT of the current second radiation constant
/// (T·1.4388/1.4380); from 4000 K the CIE daylight locus (CIE 15:2004, eq. 3.3–3.4, which
/// pbrt-v4's spectrum reproduces to within 10⁻⁴ in x and y), below it a blackbody's.
Eigen::Vector2d daylightChromaticity(double temperature);
/// White balance (pbrt-v4's PixelSensor with a `whitebalance` temperature): the linear sRGB
/// to linear sRGB matrix that maps what is white under the daylight illuminant of
/// `temperature` (K; see daylightChromaticity) to sRGB's white, by von Kries scaling in
/// Bradford's cone space (Lam 1985; PBR 4th ed. §5.4.2). Throws NoriException unless the
/// temperature is finite and positive.
Eigen::Matrix3f whiteBalanceMatrix(float temperature);

} // namespace nori
