// Directional albedo tables: E(μ, p) = ∫ f(wi, wo) cos θo dωo for wi at cos θi = μ, over
// μ and one parameter p of a BSDF, both in [0, 1]. Energy-conserving layering scales the
// layer beneath by 1 − E of the layer above (Kulla & Conty 2017, "Revisiting Physically
// Based Shading at Imageworks", "albedo scaling"), which needs E for any direction.
#pragma once

#include <nori/vector.h>

#include <functional>
#include <vector>

namespace nori {

class AlbedoTable {
public:
    /// The weight f(wi, wo) cos θo / pdf(wo) of one sample: it draws wo from the sample
    /// point u in [0, 1)² for wi (in the local frame, wi.z = μ) and the parameter p.
    using SampleWeight = std::function<float(const Vector3f &wi, float p, const Point2f &u)>;

    /// Tabulates E at muCount × paramCount nodes (μ = x² and p for x, p evenly spaced from
    /// 0 to 1, so that the nodes crowd toward grazing angles, where albedos change fastest;
    /// one p node: p is ignored), each the mean weight over `samples` points of the Sobol'
    /// sequence; the nodes are computed in parallel. μ = 0 is evaluated at cos θi = 1e-4.
    AlbedoTable(int muCount, int paramCount, int samples, const SampleWeight &weight);

    /// E(μ, p), bilinear in (√μ, p) between the nodes (μ and p clamped to [0, 1]).
    float operator()(float mu, float p = 0.0f) const;
    /// An upper bound of operator()(μ, p) over every μ: the largest node of p's two rows,
    /// interpolated in p as operator() does.
    float maxOverMu(float p = 0.0f) const;

private:
    float node(int muIndex, int paramIndex) const {
        return m_values[static_cast<size_t>(paramIndex) * m_muCount + muIndex];
    }
    int m_muCount, m_paramCount;
    std::vector<float> m_values;    ///< E at (μ_i, p_j), row j
    std::vector<float> m_rowMaxima; ///< the largest E of each row
};

} // namespace nori
