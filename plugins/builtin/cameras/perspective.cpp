/*
 * perspective — a pinhole camera, as Nori's, or a thin lens with depth of field (PBR 4th
 * ed. §5.2.3): it looks along +z of its local frame with +y up; camera-space +x is the
 * image's left (EPFL's Nori 2) or right (ETH's). With apertureRadius > 0, rays start on
 * a disk of that radius (concentric mapping) and pass through the point of the pinhole
 * ray at focalDistance, so that plane is sharp. A nested <rfilter> replaces the default
 * gaussian filter. Light tracing connects scene points to either lens (PBR 3rd ed.,
 * §16.1.1: importance We = 1/(A·lens area·cos⁴θ), A the film's area at distance 1).
 *
 * Parameters:
 *   width       integer    1280      image width in pixels
 *   height      integer    720       image height in pixels
 *   fov         float      30        horizontal field of view in degrees, in (0, 180)
 *   nearClip    float      1e-4      distance of the near clipping plane
 *   farClip     float      1e4       distance of the far clipping plane
 *   toWorld     transform  identity  camera-to-world transform
 *   convention  string     "epfl"    "epfl": x mirrored (Nori 2, Mitsuba); "eth": not
 *                                    mirrored (the ETH course); see nori --convention
 *   apertureRadius, lensRadius  float  0  radius of the lens; 0 is a pinhole (the same
 *                                     images); lensRadius: pbrt's and the courses' name
 *   focalDistance   float  10        distance (along the view axis) of the sharp plane
 *   sampleBorder    boolean  false   edge pixels see beyond the image's edge through their
 *                                    filter (pbrt-v4's film; see camera.h)
 *   screenWindow    string   (centred)  "left right bottom top": the film's extent on the
 *                                    plane at distance 1, in units of tan(fov/2), x toward
 *                                    the image's right and y up (pbrt-v4's screenwindow);
 *                                    by default -1 1 -h h, h = height/width: fov spans the
 *                                    width. An off-centre window shifts the view (a tilt-
 *                                    shift lens); one of another aspect makes pixels that
 *                                    are not square
 *   cropOffsetX, cropOffsetY, cropWidth, cropHeight  integer  (none)  render and write only
 *                                    this rectangle of pixels of the width × height image
 *   whiteBalance    float    0       white-balance the sensor for a daylight illuminant of
 *                                    this temperature in K (pbrt-v4's whitebalance); 0: not
 *
 * Also registered as: thinlens.
 *
 *   <camera type="perspective">
 *       <transform name="toWorld"><lookat origin="0,0,4" target="0,0,0" up="0,1,0"/></transform>
 *       <float name="fov" value="45"/>
 *   </camera>
 *
 *   <camera type="thinlens">
 *       <float name="apertureRadius" value="0.05"/> <float name="focalDistance" value="4"/>
 *   </camera>
 */
#include <nori/camera.h>
#include <nori/strutil.h>
#include <nori/transform.h>
#include <nori/warp.h>

namespace nori {
namespace {

class PerspectiveCamera : public Camera {
public:
    explicit PerspectiveCamera(const PropertyList &props) {
        readFilm(props);
        m_fov = props.getFloat("fov", 30.0f);
        m_nearClip = props.getFloat("nearClip", 1e-4f);
        m_farClip = props.getFloat("farClip", 1e4f);
        m_cameraToWorld = props.getTransform("toWorld", Transform());
        m_convention = readConvention(props);
        m_apertureRadius = props.getFloat(props.spelling("apertureRadius", {"lensRadius"}), 0.0f);
        m_focalDistance = props.getFloat("focalDistance", 10.0f);
        if (!(m_apertureRadius >= 0.0f) || !std::isfinite(m_apertureRadius))
            throw NoriException("perspective: 'apertureRadius' must be finite and not "
                                "negative, got {}",
                                m_apertureRadius);
        if (!(m_focalDistance > 0.0f) || !std::isfinite(m_focalDistance))
            throw NoriException("perspective: 'focalDistance' must be positive, got {}",
                                m_focalDistance);

        if (!(m_fov > 0.0f && m_fov < 180.0f))
            throw NoriException("perspective: 'fov' must lie in (0, 180) degrees, got {}", m_fov);
        if (!(m_nearClip > 0.0f && m_farClip > m_nearClip))
            throw NoriException("perspective: need 0 < nearClip < farClip, got {} and {}",
                                m_nearClip, m_farClip);

        m_tanHalfFov = std::tan(degToRad(0.5f * m_fov));
        readScreenWindow(props);
        m_worldToCamera = m_cameraToWorld.inverse();
    }

    bool canConnect() const override { return true; }

    bool connect(const Point3f &reference, const Point2f &lensSample,
                 CameraConnection &connection) const override {
        const Point3f lens = lensPoint(lensSample);
        const Point3f p = m_worldToCamera * reference;
        // In front of the lens and within the clip range (the planes z = const that
        // sampleRay's rays span).
        if (!(p.z() >= m_nearClip && p.z() <= m_farClip))
            return false;
        if (!filmPositionOf(lens, p, connection.filmPosition))
            return false;
        connection.lensPoint = m_cameraToWorld * lens;
        const Vector3f toLens = connection.lensPoint - reference;
        connection.distance = toLens.norm();
        if (!(connection.distance > 0.0f) || !std::isfinite(connection.distance))
            return false;
        connection.direction = toLens / connection.distance;
        // The film's response per unit solid angle is the density of its directions,
        // 1/(A cos³θ), and per unit of the reference's projected area that over d². The
        // lens area cancels against its sampling pdf.
        connection.importance = directionDensity((p - lens).normalized().z()) /
                                (connection.distance * connection.distance);
        return std::isfinite(connection.importance);
    }

    float pdfDirection(const Point3f &lensPoint, const Vector3f &direction) const override {
        const Point3f lens = m_worldToCamera * lensPoint;
        const Vector3f d = Vector3f(m_worldToCamera * direction).normalized();
        Point2f filmPosition;
        if (!(d.z() > 0.0f) || !filmPositionOf(lens, lens + d, filmPosition))
            return 0.0f;
        return directionDensity(d.z());
    }

    Color3f sampleRay(Ray3f &ray, const Point2f &samplePosition,
                      const Point2f &apertureSample) const override {
        // Film position to a point of the screen window on the plane z = 1 of camera
        // space (by default the horizontal field of view spans x in ±tan(fov/2)).
        const Point2f fraction = fullImageFraction(samplePosition);
        const float screenX = m_left + fraction.x() * (m_right - m_left);
        const float screenY = m_top - fraction.y() * (m_top - m_bottom);
        Vector3f d =
            Vector3f(mirrored(screenX) * m_tanHalfFov, screenY * m_tanHalfFov, 1.0f).normalized();
        const Point3f origin = lensPoint(apertureSample);
        if (m_apertureRadius > 0.0f) {
            // Thin lens: from a point of the lens disk toward where the pinhole ray meets
            // the plane of focus z = focalDistance.
            const Point3f focus = d * (m_focalDistance / d.z());
            d = Vector3f(focus - origin).normalized();
        }
        // The clip planes are planes z = const, so the ray's extent depends on d.z. The
        // world direction is normalised, and the extent with it: toWorld may scale, or
        // collapse (Nori 2's lookat with 'up' along the view; see Transform).
        const float invZ = 1.0f / d.z();
        const Vector3f worldDirection = m_cameraToWorld * d;
        const float length = worldDirection.norm();
        ray = Ray3f(m_cameraToWorld * origin, worldDirection / length, m_nearClip * invZ * length,
                    m_farClip * invZ * length);
        return Color3f(1.0f);
    }

    std::string toString() const override {
        return fmt::format("PerspectiveCamera[size={}x{}, crop={}x{}+{}+{}, fov={}, "
                           "screenWindow=[{}, {}] x [{}, {}], nearClip={}, farClip={}, "
                           "apertureRadius={}, focalDistance={}, convention={}, rfilter={}, "
                           "toWorld=\n{}]",
                           m_fullSize.x(), m_fullSize.y(), m_outputSize.x(), m_outputSize.y(),
                           m_cropOffset.x(), m_cropOffset.y(), m_fov, m_left, m_right, m_bottom,
                           m_top, m_nearClip, m_farClip, m_apertureRadius, m_focalDistance,
                           conventionName(m_convention), m_rfilter ? m_rfilter->toString() : "none",
                           m_cameraToWorld.toString());
    }

private:
    /// Where the ray from the lens point through p (both camera space, p.z > 0) crosses
    /// the plane of focus (the plane z = 1 for a pinhole), and so which film position
    /// sampleRay would have sent along it. False outside the image.
    bool filmPositionOf(const Point3f &lens, const Point3f &p, Point2f &filmPosition) const {
        const float focus = m_apertureRadius > 0.0f ? m_focalDistance : 1.0f;
        const Point3f onFocus = lens + (p - lens) * ((focus - lens.z()) / (p.z() - lens.z()));
        const float screenX = mirrored(onFocus.x() / (focus * m_tanHalfFov));
        const float screenY = onFocus.y() / (focus * m_tanHalfFov);
        return outputPosition(Point2f((screenX - m_left) / (m_right - m_left),
                                      (m_top - screenY) / (m_top - m_bottom)),
                              filmPosition);
    }

    /// The output image spans its share of the screen window at distance 1 (for a thin
    /// lens: that film scaled to the plane of focus, seen from the lens point), of area A;
    /// a ray at angle θ to the axis sees dω = cos³θ dA of it, so film positions uniform
    /// over the image send directions with density 1/(A cos³θ) (PBR 3rd ed., §16.1.1).
    float directionDensity(float cosTheta) const {
        return 1.0f / (m_outputFilmArea * cosTheta * cosTheta * cosTheta);
    }

    /// Camera-space x of the screen's x (toward the image's right) and back: EPFL's
    /// convention mirrors it (see Camera::Convention).
    float mirrored(float x) const { return m_convention == Convention::EPFL ? -x : x; }

    /// Reads `screenWindow` (its default from the image's aspect) and the area of the
    /// output image on the plane z = 1.
    void readScreenWindow(const PropertyList &props) {
        const float halfHeight =
            static_cast<float>(m_fullSize.y()) / static_cast<float>(m_fullSize.x());
        m_left = -1.0f, m_right = 1.0f, m_bottom = -halfHeight, m_top = halfHeight;
        if (props.has("screenWindow")) {
            const std::vector<float> window =
                toFloatList(props.getString("screenWindow"), "screenWindow");
            if (window.size() != 4 || !(window[0] < window[1]) || !(window[2] < window[3]) ||
                !std::isfinite(window[1] - window[0]) || !std::isfinite(window[3] - window[2]))
                throw NoriException("perspective: 'screenWindow' must be four finite numbers "
                                    "\"left right bottom top\" with left < right and bottom < "
                                    "top, got \"{}\"",
                                    props.getString("screenWindow"));
            m_left = window[0], m_right = window[1], m_bottom = window[2], m_top = window[3];
        }
        const float cropShare = static_cast<float>(double(m_outputSize.x()) * m_outputSize.y() /
                                                   (double(m_fullSize.x()) * m_fullSize.y()));
        m_outputFilmArea =
            (m_right - m_left) * (m_top - m_bottom) * m_tanHalfFov * m_tanHalfFov * cropShare;
    }

    /// The point of the lens (camera space) for an aperture sample: the centre for a
    /// pinhole, else uniform on the disk (concentric mapping).
    Point3f lensPoint(const Point2f &apertureSample) const {
        if (m_apertureRadius <= 0.0f)
            return Point3f(0.0f, 0.0f, 0.0f);
        const Point2f lens = m_apertureRadius * Warp::squareToUniformDiskConcentric(apertureSample);
        return Point3f(lens.x(), lens.y(), 0.0f);
    }

    float m_fov, m_nearClip, m_farClip, m_apertureRadius, m_focalDistance;
    float m_tanHalfFov;
    float m_left, m_right, m_bottom, m_top; ///< the screen window, in units of tan(fov/2)
    float m_outputFilmArea;
    Transform m_cameraToWorld, m_worldToCamera;
    Convention m_convention;
};

NORI_REGISTER_CLASS(PerspectiveCamera, "perspective");
NORI_REGISTER_ALIAS(PerspectiveCamera, "thinlens", thinlens);

} // namespace
} // namespace nori
