// Cameras turn a film position (in pixels) and an aperture sample into a ray.
#pragma once

#include <nori/color.h>
#include <nori/convention.h>
#include <nori/medium.h>
#include <nori/object.h>
#include <nori/ray.h>
#include <nori/rfilter.h>

#include <optional>

namespace nori {

/// A connection from a point of the scene to the camera's lens (light tracing, BDPT's
/// t = 1 strategies; Veach 1997, §10.2; PBR 3rd ed., §16.1.1), made by Camera::connect.
struct CameraConnection {
    Point3f lensPoint;     ///< the point on the lens (world space)
    Vector3f direction;    ///< unit, from the scene point toward lensPoint
    float distance = 0.0f; ///< from the scene point to lensPoint
    Point2f filmPosition;  ///< where the film sees the point (pixels, from the top-left corner)
    /// What a unit of radiance leaving the scene point toward the lens adds to the film at
    /// filmPosition, per unit of cosine-weighted area at the scene point: We·cos θ_lens /
    /// (d²·p(lens point)), with We normalised to the film in pixels (see Splat in
    /// integrator.h). For a pinhole or thin lens 1/(A cos³θ d²), A the area of the film
    /// on the plane at distance 1 (PBR 3rd ed., §16.1.1).
    float importance = 0.0f;
};

class Camera : public NoriObject {
public:
    static constexpr EClassType kClassType = ECamera;

    /// Which way the image's x axis runs in camera space (the two Nori course lineages
    /// differ). EPFL: Nori 2 and Mitsuba mirror x, camera-space +x is the image's left;
    /// the default. ETH: no mirror, camera-space +x is the image's right.
    using Convention = CourseConvention;

    /// Generates a world-space ray for film position `samplePosition` (pixels, from the
    /// top-left corner) and returns the importance weight of the ray. A weight of zero
    /// (a lens system blocked the ray) leaves `ray` unspecified: it must not be traced.
    virtual Color3f sampleRay(Ray3f &ray, const Point2f &samplePosition,
                              const Point2f &apertureSample) const = 0;

    /// sampleRay with ray differentials: the rays through the film positions one pixel
    /// to the right and one pixel down, with the same aperture sample (Igehy 1999; pbrt-v3
    /// §6.1). Any camera gets them this way; one with a cheaper closed form may override.
    virtual Color3f sampleRayDifferential(Ray3f &ray, const Point2f &samplePosition,
                                          const Point2f &apertureSample) const;

    /// Whether connect() works: a camera with a point or thin lens can be connected to; one
    /// whose rays pass a lens system (realistic) cannot, and integrators that connect
    /// (lighttracer) reject it by name.
    virtual bool canConnect() const { return false; }
    /// Connects the scene point `reference` to a point on the lens chosen by `lensSample`
    /// (uniform over the aperture). False when the point is not seen: behind the camera,
    /// outside the clip range or outside the image. The visibility of the segment is the
    /// caller's to test. Cameras that cannot connect return false.
    virtual bool connect(const Point3f &reference, const Point2f &lensSample,
                         CameraConnection &connection) const {
        (void)reference, (void)lensSample, (void)connection;
        return false;
    }

    /// The solid-angle density with which sampleRay, its film position uniform over the
    /// image, sends a ray from `lensPoint` (world space, on the lens) along the unit
    /// `direction`: 1/(A cos³θ) for a pinhole or thin lens (PBR 3rd ed., §16.1.1), zero
    /// outside the image. What bdpt's MIS weights need of the camera; cameras that cannot
    /// connect return 0.
    virtual float pdfDirection(const Point3f &lensPoint, const Vector3f &direction) const {
        (void)lensPoint, (void)direction;
        return 0.0f;
    }

    /// The size of the image rendered and written: the crop of the full image (see
    /// getFullSize), or all of it.
    const Vector2i &getOutputSize() const { return m_outputSize; }
    /// The image the camera projects onto, of which the output is the crop that starts at
    /// getCropOffset() (the `cropOffsetX`, `cropOffsetY`, `cropWidth`, `cropHeight`
    /// parameters, Mitsuba's film's names): a crop renders exactly those pixels of the
    /// full image. Film positions given to and returned by a camera are pixels of the
    /// output image.
    const Vector2i &getFullSize() const { return m_fullSize; }
    const Vector2i &getCropOffset() const { return m_cropOffset; }
    /// Whether the camera's sensor white-balances (the `whiteBalance` parameter, a
    /// temperature in K): the render loop then passes every sample's value through
    /// sensorResponse. A linear map, it commutes with the film's filtering and averaging.
    bool balancesWhite() const { return m_whiteBalance.has_value(); }
    /// A sample's linear sRGB as the sensor records it: whiteBalanceMatrix(whiteBalance)
    /// applied (what pbrt-v4's `whitebalance` film does); the value itself without one.
    Color3f sensorResponse(const Color3f &value) const {
        if (!m_whiteBalance)
            return value;
        return Color3f(Eigen::Vector3f(*m_whiteBalance * value.matrix()).array());
    }
    const ReconstructionFilter *getReconstructionFilter() const { return m_rfilter.get(); }
    /// Whether a pixel at the image's edge sees the scene beyond the edge through its
    /// filter (the `sampleBorder` parameter), as pbrt-v4's film and Mitsuba 3's
    /// sample_border have it; by default the filter is cut at the edge. Integrators that
    /// do not splat then sample each pixel from its whole filter (filter importance
    /// sampling); those that splat (light tracing, bdpt) keep the cut filter.
    bool samplesBorder() const { return m_sampleBorder; }
    /// The medium the camera sits in (a <medium> child), or nullptr for vacuum.
    const Medium *getMedium() const { return m_medium.get(); }

    /// Accepts one <rfilter> and one <medium>.
    using NoriObject::addChild;
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Checks the image size against kMaxImageSide and kMaxImagePixels and creates the
    /// default gaussian filter (Nori's default) when none was given.
    void activate() override;

    /// The largest image: 32768 pixels on a side, 2^27 (134 million) pixels in all,
    /// which the render loop holds in about 4 GiB.
    static constexpr int kMaxImageSide = 32768;
    static constexpr int64_t kMaxImagePixels = int64_t(1) << 27;

    EClassType getClassType() const override { return kClassType; }

protected:
    /// Reads the `convention` parameter ("epfl", the default, or "eth"); `nori
    /// --convention` sets it for cameras whose XML does not.
    static Convention readConvention(const PropertyList &props) {
        return readCourseConvention(props);
    }
    /// The camera-space x of the film's horizontal position u in [0, 1], on the plane
    /// where the film spans x in [−1, 1]: 1 − 2u (EPFL) or 2u − 1 (ETH).
    static float filmX(float u, Convention convention) {
        return convention == Convention::EPFL ? 1.0f - 2.0f * u : 2.0f * u - 1.0f;
    }
    static const char *conventionName(Convention convention) {
        return courseConventionName(convention);
    }
    /// Reads what our cameras share of a film: `width` and `height` (1280 × 720 by
    /// default), the crop (see getFullSize), `sampleBorder` (see samplesBorder) and
    /// `whiteBalance` (see balancesWhite; 0, the default, for none). Throws NoriException
    /// for a crop outside the image.
    void readFilm(const PropertyList &props);
    /// The film position `samplePosition` (pixels of the output image) as a fraction of
    /// the full image: (0, 0) its top-left corner, (1, 1) its bottom-right one.
    Point2f fullImageFraction(const Point2f &samplePosition) const {
        return Point2f(
            (samplePosition + m_cropOffset.cast<float>()).cwiseQuotient(m_fullSize.cast<float>()));
    }
    /// The inverse of fullImageFraction: false when the position lies outside the output
    /// image.
    bool outputPosition(const Point2f &fraction, Point2f &samplePosition) const;

    Vector2i m_outputSize;
    Vector2i m_fullSize;
    Vector2i m_cropOffset = Vector2i::Zero();
    std::optional<Eigen::Matrix3f> m_whiteBalance;
    std::shared_ptr<ReconstructionFilter> m_rfilter;
    std::shared_ptr<Medium> m_medium;
    bool m_sampleBorder = false;
};

} // namespace nori
