/*
 * spot — a point light that shines into a cone: full intensity I within beamWidth β of
 * its axis, falling off to zero at cutoffAngle c. By default smoothly, I(θ) =
 * I·smoothstep(cos c, cos β, cos θ) as pbrt-v4 defines it (PBR 4th ed. §12.1.1), of power
 * Φ = 2π I [(1 − cos β) + (cos β − cos c)/2] (the smoothstep averages ½ over the ring);
 * with falloff "linear", I(θ) = I·(c − θ)/(c − β) on the ring as Mitsuba (0.6 and 3)
 * defines it, of power Φ = 2π I [1 + (sin β − sin c)/(c − β)] (∫ (c − θ) sin θ dθ over
 * [β, c] is (c − β) cos β + sin β − sin c). A delta light: BSDF-sampled rays never hit it.
 *
 * Parameters:
 *   position     point      (0, 0, 0)  where the light is
 *   target       point      —          a point on its axis (default: along +z) ...
 *   direction    vector     —          ... or the axis itself (the courses' spelling)
 *   toWorld      transform  —          instead of position and target: the light sits at
 *                                      the origin of this frame and shines along its +z
 *   intensity    color      —          radiant intensity I on the axis (W/sr) ...
 *   power        color      —          ... or the emitted power Φ (W): exactly one
 *   cutoffAngle  float      30         half-angle (degrees) where the light stops
 *   beamWidth    float      20         half-angle (degrees) of full intensity, at most
 *                                      cutoffAngle
 *   cosTotalWidth  float    —          instead of cutoffAngle: its cosine (pbrt's and
 *                                      the courses' spelling); a value above 1 can only
 *                                      be degrees, and is read as such, with a note
 *   cosFalloffStart  float  —          instead of beamWidth: its cosine (likewise)
 *   falloff      string     "smoothstep"  across the ring: "smoothstep" in cos θ (pbrt) or
 *                                      "linear" in θ (Mitsuba)
 *
 *   <emitter type="spot"><point name="position" value="0, 3, 0"/>
 *       <point name="target" value="0, 0, 0"/> <color name="intensity" value="20"/>
 *       <float name="cutoffAngle" value="25"/> <float name="beamWidth" value="15"/></emitter>
 */
#include <nori/emitter.h>
#include <nori/frame.h>
#include <nori/proplist.h>
#include <nori/transform.h>
#include <nori/warp.h>

#include <iostream>

namespace nori {
namespace {

/// A half-angle in degrees given as `angleName` (degrees) or as `cosineName` (its cosine,
/// pbrt-v3's spelling). Course scenes often write degrees into the cosine's name; a value
/// above 1 cannot be a cosine, so it is read as degrees, with a note.
float readHalfAngle(const PropertyList &props, const char *angleName, const char *cosineName,
                    float defaultDegrees) {
    if (props.spelling(angleName, {cosineName}) == angleName)
        return props.getFloat(angleName, defaultDegrees);
    const float value = props.getFloat(cosineName);
    if (value > 1.0f) {
        std::cerr << fmt::format("Note: {}: spot: '{}' = {} is above 1, so it is no cosine: read "
                                 "as {} degrees ('{}')\n",
                                 props.location(cosineName), cosineName, value, value, angleName);
        return value;
    }
    if (!(value >= -1.0f))
        throw NoriException("spot: '{}' must be a cosine in [-1, 1] (or degrees above 1), got {}",
                            cosineName, value);
    return radToDeg(std::acos(value));
}

class SpotLight : public Emitter {
public:
    explicit SpotLight(const PropertyList &props) {
        m_cutoffAngle = readHalfAngle(props, "cutoffAngle", "cosTotalWidth", 30.0f);
        m_beamWidth = readHalfAngle(props, "beamWidth", "cosFalloffStart", 20.0f);
        if (!(m_cutoffAngle > 0.0f && m_cutoffAngle <= 180.0f))
            throw NoriException("spot: 'cutoffAngle' must be in (0, 180] degrees, got {}",
                                m_cutoffAngle);
        if (!(m_beamWidth >= 0.0f && m_beamWidth <= m_cutoffAngle))
            throw NoriException("spot: 'beamWidth' must be in [0, cutoffAngle = {}] degrees, "
                                "got {}",
                                m_cutoffAngle, m_beamWidth);
        m_cosCutoff = std::cos(degToRad(m_cutoffAngle));
        m_cosBeam = std::cos(degToRad(m_beamWidth));
        const std::string falloffName = props.getString("falloff", "smoothstep");
        if (falloffName != "smoothstep" && falloffName != "linear")
            throw NoriException("spot: 'falloff' is \"smoothstep\" or \"linear\", got \"{}\"",
                                falloffName);
        m_linear = falloffName == "linear";
        m_intensity = readIntensity(props, "spot", solidAngle());

        if (props.has("toWorld")) {
            if (props.has("position") || props.has("target") || props.has("direction"))
                throw NoriException(
                    "spot: give 'toWorld' or 'position' and 'target' (or 'direction'), not both");
            const Transform toWorld = props.getTransform("toWorld");
            m_position = toWorld * Point3f(0.0f, 0.0f, 0.0f);
            m_axis = Vector3f(toWorld * Vector3f(0.0f, 0.0f, 1.0f)).normalized();
        } else {
            m_position = props.getPoint("position", Point3f(0.0f));
            Vector3f axis(0.0f, 0.0f, 1.0f);
            if (props.spelling("target", {"direction"}) == "direction") {
                axis = props.getVector("direction");
                if (!(axis.norm() > 0.0f) || !axis.allFinite())
                    throw NoriException("spot: 'direction' must be a finite, non-zero vector");
            } else if (props.has("target")) {
                axis = props.getPoint("target") - m_position;
                if (!(axis.norm() > 0.0f) || !axis.allFinite())
                    throw NoriException("spot: 'target' must differ from 'position'");
            }
            m_axis = axis.normalized();
        }
    }

    Color3f sample(EmitterQueryRecord &lRec, const Point2f &) const override {
        const float distanceSquared = aimAtPoint(lRec, m_position);
        if (distanceSquared == 0.0f)
            return Color3f(0.0f);
        return m_intensity * (falloff(m_axis.dot(-lRec.wi)) / distanceSquared);
    }

    // Directions drawn in proportion to the intensity (sampleFalloff): every photon
    // carries the power, I·falloff/pdf_ω = I·solidAngle.
    Color3f sampleEmission(EmissionSample &emission, const Point2f &,
                           const Point2f &directionSample) const override {
        const float cosTheta = sampleFalloff(directionSample.x());
        const Vector3f local = Warp::sphericalDirection(cosTheta, 2.0f * kPi * directionSample.y());
        const Vector3f direction = Frame(m_axis).toWorld(local);
        emission.ray = Ray3f(m_position, direction, 0.0f, kInfinity);
        emission.p = m_position;
        emission.density = emissionDensity(m_position, emission.n, direction);
        return getPower();
    }

    // The density of sampleFalloff's directions: falloff/solidAngle.
    EmissionDensity emissionDensity(const Point3f &, const Normal3f &,
                                    const Vector3f &direction) const override {
        return {1.0f, falloff(m_axis.dot(direction)) / solidAngle()};
    }

    Color3f eval(const EmitterQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const EmitterQueryRecord &) const override { return 0.0f; }
    bool isDelta() const override { return true; }
    Color3f getPower() const override { return m_intensity * solidAngle(); }
    // A point that emits about its axis up to the cutoff angle (θo = 0, θe = cutoff).
    std::optional<LightBounds> lightBounds() const override {
        LightBounds bounds;
        bounds.bounds = BoundingBox3f(m_position);
        bounds.w = m_axis;
        bounds.cosThetaO = 1.0f;
        bounds.cosThetaE = m_cosCutoff;
        bounds.phi = kPi * m_intensity.getLuminance();
        return bounds;
    }

    std::string toString() const override {
        return fmt::format("SpotLight[position=({}, {}, {}), axis=({}, {}, {}), intensity=({}, "
                           "{}, {}), cutoffAngle={}, beamWidth={}, falloff={}]",
                           m_position.x(), m_position.y(), m_position.z(), m_axis.x(), m_axis.y(),
                           m_axis.z(), m_intensity.r(), m_intensity.g(), m_intensity.b(),
                           m_cutoffAngle, m_beamWidth, m_linear ? "linear" : "smoothstep");
    }

private:
    /// 0 outside the cone, 1 inside the beam, and across the ring smoothstep(cos c, cos β,
    /// cos θ) or (c − θ)/(c − β).
    float falloff(float cosTheta) const {
        if (cosTheta >= m_cosBeam)
            return 1.0f;
        if (cosTheta <= m_cosCutoff)
            return 0.0f;
        if (m_linear) {
            const float cutoff = degToRad(m_cutoffAngle), beam = degToRad(m_beamWidth);
            return std::clamp((cutoff - std::acos(cosTheta)) / (cutoff - beam), 0.0f, 1.0f);
        }
        const float t = (cosTheta - m_cosCutoff) / (m_cosBeam - m_cosCutoff);
        return t * t * (3.0f - 2.0f * t);
    }

    /// cos θ with density ∝ falloff(cos θ) on [cos cutoff, 1], from u in [0, 1): the beam
    /// (uniform in cos θ) with probability (1 − cos beam)/(solidAngle/2π), else the ring,
    /// by inverting its CDF by bisection (both CDFs are monotonic). Smoothstep: t = (cos θ −
    /// cos c)/(cos β − cos c) has density 6t² − 4t³ and CDF 2t³ − t⁴. Linear: θ on [β, c]
    /// has density ∝ (c − θ) sin θ and unnormalised CDF (c − β) cos β + sin β − (c − θ)
    /// cos θ − sin θ.
    float sampleFalloff(float u) const {
        const float beam = 1.0f - m_cosBeam, ring = ringFraction();
        const float beamProbability = beam / (beam + ring);
        if (u < beamProbability || ring <= 0.0f)
            return 1.0f - std::min(u / beamProbability, 1.0f) * beam;
        const float v = (u - beamProbability) / (1.0f - beamProbability);
        float low = 0.0f, high = 1.0f;
        if (m_linear) {
            const double c = degToRad(m_cutoffAngle), b = degToRad(m_beamWidth);
            const double total = (c - b) * std::cos(b) + std::sin(b) - std::sin(c);
            for (int i = 0; i < 24; ++i) {
                const float t = 0.5f * (low + high);
                const double theta = b + t * (c - b);
                const double cdf = ((c - b) * std::cos(b) + std::sin(b) -
                                    (c - theta) * std::cos(theta) - std::sin(theta)) /
                                   total;
                (cdf < v ? low : high) = t;
            }
            return float(std::cos(b + 0.5 * (low + high) * (c - b)));
        }
        for (int i = 0; i < 24; ++i) { // 2⁻²⁴: float precision
            const float t = 0.5f * (low + high);
            (2.0f * t * t * t - t * t * t * t < v ? low : high) = t;
        }
        return m_cosCutoff + 0.5f * (low + high) * (m_cosBeam - m_cosCutoff);
    }

    /// ∫ falloff dω over the ring β < θ < c, over 2π: smoothstep(t) + smoothstep(1 − t) =
    /// 1, so the smoothstep ring gives half its extent, (cos β − cos c)/2; the linear one
    /// cos β + (sin β − sin c)/(c − β) (the integral above over c − β).
    float ringFraction() const {
        if (!m_linear || m_cutoffAngle == m_beamWidth)
            return 0.5f * (m_cosBeam - m_cosCutoff);
        const double c = degToRad(m_cutoffAngle), b = degToRad(m_beamWidth);
        return float(std::cos(b) + (std::sin(b) - std::sin(c)) / (c - b));
    }

    /// ∫ falloff dω: 2π [(1 − cos β) + the ring's fraction].
    float solidAngle() const { return 2.0f * kPi * ((1.0f - m_cosBeam) + ringFraction()); }

    Point3f m_position;
    Vector3f m_axis;
    Color3f m_intensity;
    float m_cutoffAngle, m_beamWidth, m_cosCutoff, m_cosBeam;
    bool m_linear = false; ///< falloff linear in θ (Mitsuba) rather than smoothstep
};

NORI_REGISTER_CLASS(SpotLight, "spot");

} // namespace
} // namespace nori
