// Pixel reconstruction filters. eval() is one-dimensional and normalised to integrate to
// 1 over [-radius, radius]; the 2D filter is the separable product eval(x)·eval(y).
#pragma once

#include <nori/object.h>

namespace nori {

class ReconstructionFilter : public NoriObject {
public:
    static constexpr EClassType kClassType = EReconstructionFilter;

    float getRadius() const { return m_radius; }
    virtual float eval(float x) const = 0;

    EClassType getClassType() const override { return kClassType; }

    /// The widest support a filter may have, in pixels: far beyond any useful filter, and
    /// small enough that image borders stay small.
    static constexpr float kMaxRadius = 32.0f;

protected:
    /// Validates a radius read from XML, naming the filter in the error.
    static float checkedRadius(float radius, const char *filterName);

    float m_radius = 0.5f;
};

} // namespace nori
