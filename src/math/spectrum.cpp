#include "math/spectraldata.h"
#include <nori/filesystem.h>
#include <nori/spectrum.h>
#include <nori/strutil.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

namespace nori {

namespace {

using namespace spectraldata;

/// ∫ s(λ) w(λ) c̄(λ) dλ for the three matching functions, at their 1 nm nodes.
template <typename Weight>
void integrateCie(const std::function<float(float)> &spectrum, Weight &&weight, double xyz[3],
                  double &normaliser) {
    xyz[0] = xyz[1] = xyz[2] = normaliser = 0.0;
    for (size_t i = 0; i < kCieSamples; ++i) {
        const float lambda = kCieFirst + static_cast<float>(i);
        const double w = weight(lambda), s = spectrum(lambda) * w;
        xyz[0] += s * kCieX[i];
        xyz[1] += s * kCieY[i];
        xyz[2] += s * kCieZ[i];
        normaliser += w * kCieY[i];
    }
}

const std::map<std::string, PiecewiseLinearSpectrum> &namedSpectra() {
    static const std::map<std::string, PiecewiseLinearSpectrum> spectra = [] {
        std::map<std::string, PiecewiseLinearSpectrum> table;
        auto add = [&](const std::string &name, const float *pairs, size_t size) {
            table.emplace(name, PiecewiseLinearSpectrum(pairs, size / 2));
        };
        add("metal-Ag-eta", kAgEta, kAgEtaSize);
        add("metal-Ag-k", kAgK, kAgKSize);
        add("metal-Al-eta", kAlEta, kAlEtaSize);
        add("metal-Al-k", kAlK, kAlKSize);
        add("metal-Au-eta", kAuEta, kAuEtaSize);
        add("metal-Au-k", kAuK, kAuKSize);
        add("metal-Cu-eta", kCuEta, kCuEtaSize);
        add("metal-Cu-k", kCuK, kCuKSize);
        add("metal-CuZn-eta", kCuZnEta, kCuZnEtaSize);
        add("metal-CuZn-k", kCuZnK, kCuZnKSize);
        add("metal-MgO-eta", kMgOEta, kMgOEtaSize);
        add("metal-MgO-k", kMgOK, kMgOKSize);
        add("metal-TiO2-eta", kTiO2Eta, kTiO2EtaSize);
        add("metal-TiO2-k", kTiO2K, kTiO2KSize);
        add("glass-BK7", kGlassBK7, kGlassBK7Size);
        add("glass-BAF10", kGlassBAF10, kGlassBAF10Size);
        add("glass-FK51A", kGlassFK51A, kGlassFK51ASize);
        add("glass-LASF9", kGlassLASF9, kGlassLASF9Size);
        add("glass-F5", kGlassF5, kGlassF5Size);
        add("glass-F10", kGlassF10, kGlassF10Size);
        add("glass-F11", kGlassF11, kGlassF11Size);
        add("stdillum-D65", kD65, kD65Size);
        return table;
    }();
    return spectra;
}

} // namespace

PiecewiseLinearSpectrum::PiecewiseLinearSpectrum(const float *interleaved, size_t count) {
    m_lambdas.reserve(count);
    m_values.reserve(count);
    for (size_t i = 0; i < count; ++i) {
        m_lambdas.push_back(interleaved[2 * i]);
        m_values.push_back(interleaved[2 * i + 1]);
    }
    *this = PiecewiseLinearSpectrum(std::move(m_lambdas), std::move(m_values));
}

PiecewiseLinearSpectrum::PiecewiseLinearSpectrum(std::vector<float> lambdas,
                                                 std::vector<float> values)
    : m_lambdas(std::move(lambdas)), m_values(std::move(values)) {
    if (m_lambdas.size() != m_values.size())
        throw NoriException("a spectrum needs as many values as wavelengths");
    for (size_t i = 1; i < m_lambdas.size(); ++i)
        if (!(m_lambdas[i] > m_lambdas[i - 1]))
            throw NoriException("a spectrum's wavelengths must increase, but {} follows {}",
                                m_lambdas[i], m_lambdas[i - 1]);
}

float PiecewiseLinearSpectrum::operator()(float lambda) const {
    if (m_lambdas.empty() || lambda < m_lambdas.front() || lambda > m_lambdas.back())
        return 0.0f;
    const auto upper = std::upper_bound(m_lambdas.begin(), m_lambdas.end(), lambda);
    if (upper == m_lambdas.end())
        return m_values.back();
    const size_t i = static_cast<size_t>(upper - m_lambdas.begin()) - 1;
    const float t = (lambda - m_lambdas[i]) / (m_lambdas[i + 1] - m_lambdas[i]);
    return (1.0f - t) * m_values[i] + t * m_values[i + 1];
}

const PiecewiseLinearSpectrum &namedSpectrum(const std::string &name) {
    const auto &spectra = namedSpectra();
    const auto it = spectra.find(name);
    if (it == spectra.end()) {
        std::vector<std::string> names;
        names.reserve(spectra.size());
        for (const auto &entry : spectra)
            names.push_back(entry.first);
        throw NoriException("unknown named spectrum '{}'{} (known: {})", name,
                            didYouMean(name, names), fmt::join(names, ", "));
    }
    return it->second;
}

bool isNamedSpectrum(const std::string &name) {
    return namedSpectra().count(name) != 0;
}

PiecewiseLinearSpectrum readSpectrumFile(const std::string &path) {
    std::istringstream in(readTextFile(path, "spectrum file"));
    std::vector<float> numbers;
    std::vector<size_t> lines;
    std::string line;
    for (size_t lineNumber = 1; std::getline(in, line); ++lineNumber) {
        const size_t comment = line.find('#');
        if (comment != std::string::npos)
            line.resize(comment);
        for (const std::string &token : tokenize(line, " \t\r,")) {
            float value = 0.0f;
            const auto [end, error] =
                std::from_chars(token.data(), token.data() + token.size(), value);
            if (error != std::errc() || end != token.data() + token.size() || !std::isfinite(value))
                throw NoriException("{}:{}: '{}' is not a number", path, lineNumber, token);
            numbers.push_back(value);
            lines.push_back(lineNumber);
        }
    }
    if (numbers.empty())
        throw NoriException("{}: the spectrum file holds no (wavelength, value) pairs", path);
    if (numbers.size() % 2 != 0)
        throw NoriException("{}:{}: a wavelength without its value (an odd count of numbers)", path,
                            lines.back());
    std::vector<float> lambdas, values;
    for (size_t i = 0; i < numbers.size(); i += 2) {
        if (!lambdas.empty() && !(numbers[i] > lambdas.back()))
            throw NoriException("{}:{}: wavelength {} does not follow {} (they must increase)",
                                path, lines[i], numbers[i], lambdas.back());
        lambdas.push_back(numbers[i]);
        values.push_back(numbers[i + 1]);
    }
    return PiecewiseLinearSpectrum(std::move(lambdas), std::move(values));
}

double planck(double lambda, double temperature) {
    if (!(temperature > 0.0))
        return 0.0;
    // B(λ, T) = 2hc²/λ⁵ / (exp(hc/(λ k_B T)) − 1), with CODATA 2010's constants (as pbrt-v4).
    constexpr double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    const double l = lambda * 1e-9;
    return (2.0 * h * c * c) /
           (std::pow(l, 5.0) * (std::exp((h * c) / (l * kb * temperature)) - 1.0));
}

float normalizedBlackbody(float lambda, float temperature) {
    const double peak = 2.8977721e-3 / temperature * 1e9; // Wien's displacement law, in nm
    const double atPeak = planck(peak, temperature);
    return atPeak > 0.0 ? static_cast<float>(planck(lambda, temperature) / atPeak) : 0.0f;
}

Color3f xyzToLinearSRGB(double x, double y, double z) {
    // IEC 61966-2-1: XYZ (D65 white) to linear sRGB.
    return Color3f(static_cast<float>(3.2404542 * x - 1.5371385 * y - 0.4985314 * z),
                   static_cast<float>(-0.9692660 * x + 1.8760108 * y + 0.0415560 * z),
                   static_cast<float>(0.0556434 * x - 0.2040259 * y + 1.0572252 * z));
}

Color3f emissionToRGB(const std::function<float(float)> &spectrum) {
    double xyz[3], normaliser;
    integrateCie(
        spectrum, [](float) { return 1.0; }, xyz, normaliser);
    return xyzToLinearSRGB(xyz[0] / normaliser, xyz[1] / normaliser, xyz[2] / normaliser);
}

Color3f reflectanceToRGB(const std::function<float(float)> &spectrum) {
    const PiecewiseLinearSpectrum &d65 = namedSpectrum("stdillum-D65");
    double xyz[3], normaliser;
    integrateCie(
        spectrum, [&](float lambda) { return double(d65(lambda)); }, xyz, normaliser);
    // D65 itself integrates to (0.95047, 1, 1.08883) here, sRGB's white: a flat 1 is (1, 1, 1).
    return xyzToLinearSRGB(xyz[0] / normaliser, xyz[1] / normaliser, xyz[2] / normaliser);
}

Eigen::Vector2d daylightChromaticity(double temperature) {
    const double cct = temperature * 1.4388 / 1.4380;
    if (cct < 4000.0) {
        // The daylight locus is not defined here: a blackbody of that temperature.
        double xyz[3], normaliser;
        integrateCie([cct](float lambda) { return static_cast<float>(planck(lambda, cct)); },
                     [](float) { return 1.0; }, xyz, normaliser);
        const double sum = xyz[0] + xyz[1] + xyz[2];
        return {xyz[0] / sum, xyz[1] / sum};
    }
    const double t = 1e3 / cct; // the locus as a cubic in 1000/T
    const double x = cct <= 7000.0 ? -4.6070 * t * t * t + 2.9678 * t * t + 0.09911 * t + 0.244063
                                   : -2.0064 * t * t * t + 1.9018 * t * t + 0.24748 * t + 0.237040;
    return {x, -3.0 * x * x + 2.870 * x - 0.275};
}

Eigen::Matrix3f whiteBalanceMatrix(float temperature) {
    if (!(temperature > 0.0f) || !std::isfinite(temperature))
        throw NoriException("white balance: the temperature must be positive, got {} K",
                            temperature);
    // Bradford's cone responses from XYZ (Lam 1985).
    Eigen::Matrix3d lmsFromXyz;
    lmsFromXyz << 0.8951, 0.2664, -0.1614, -0.7502, 1.7135, 0.0367, 0.0389, -0.0685, 1.0296;
    // sRGB's XYZ from linear RGB: the inverse of xyzToLinearSRGB's matrix.
    Eigen::Matrix3d rgbFromXyz;
    rgbFromXyz << 3.2404542, -1.5371385, -0.4985314, -0.9692660, 1.8760108, 0.0415560, 0.0556434,
        -0.2040259, 1.0572252;
    const Eigen::Matrix3d xyzFromRgb = rgbFromXyz.inverse();
    // XYZ of luminance 1 at chromaticity xy.
    auto whiteOf = [](const Eigen::Vector2d &xy) {
        return Eigen::Vector3d(xy.x() / xy.y(), 1.0, (1.0 - xy.x() - xy.y()) / xy.y());
    };
    // The target is the colour space's white as pbrt-v4 takes it: D65's spectrum's xy.
    const Eigen::Vector3d targetXyz = xyzFromRgb * Eigen::Vector3d::Ones();
    const Eigen::Vector3d sourceLms = lmsFromXyz * whiteOf(daylightChromaticity(temperature));
    const Eigen::Vector3d targetLms =
        lmsFromXyz * whiteOf(Eigen::Vector2d(targetXyz.x(), targetXyz.y()) / targetXyz.sum());
    const Eigen::Matrix3d balance =
        lmsFromXyz.inverse() * targetLms.cwiseQuotient(sourceLms).asDiagonal() * lmsFromXyz;
    return (rgbFromXyz * balance * xyzFromRgb).cast<float>();
}

} // namespace nori
