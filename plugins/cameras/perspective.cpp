/*
 * perspective — a pinhole camera, as Nori's: it looks along +z of its local frame with
 * +y up; camera-space +x is the image's left (EPFL's Nori 2) or right (ETH's). A nested
 * <rfilter> replaces the default gaussian filter.
 *
 * Parameters:
 *   width       integer    1280      image width in pixels
 *   height      integer    720       image height in pixels
 *   fov         float      30        horizontal field of view in degrees, in (0, 180)
 *   nearClip    float      1e-4      distance of the near clipping plane
 *   farClip     float      1e4       distance of the far clipping plane
 *   toWorld     transform  identity  camera-to-world transform
 *   convention  string     "epfl"    "epfl": x mirrored (Nori 2, Mitsuba); "eth": not
 *                                    mirrored (the ETH course); see nori --camera-convention
 *
 *   <camera type="perspective">
 *       <transform name="toWorld"><lookat origin="0,0,4" target="0,0,0" up="0,1,0"/></transform>
 *       <float name="fov" value="45"/>
 *   </camera>
 */
#include <nori/camera.h>
#include <nori/transform.h>

namespace nori {

class PerspectiveCamera : public Camera {
public:
    explicit PerspectiveCamera(const PropertyList &props) {
        m_outputSize.x() = props.getInteger("width", 1280);
        m_outputSize.y() = props.getInteger("height", 720);
        m_fov = props.getFloat("fov", 30.0f);
        m_nearClip = props.getFloat("nearClip", 1e-4f);
        m_farClip = props.getFloat("farClip", 1e4f);
        m_cameraToWorld = props.getTransform("toWorld", Transform());
        m_convention = readConvention(props);

        if (!(m_fov > 0.0f && m_fov < 180.0f))
            throw NoriException("perspective: 'fov' must lie in (0, 180) degrees, got {}", m_fov);
        if (!(m_nearClip > 0.0f && m_farClip > m_nearClip))
            throw NoriException("perspective: need 0 < nearClip < farClip, got {} and {}",
                                m_nearClip, m_farClip);

        m_tanHalfFov = std::tan(degToRad(0.5f * m_fov));
        m_aspect = static_cast<float>(m_outputSize.x()) / static_cast<float>(m_outputSize.y());
    }

    Color3f sampleRay(Ray3f &ray, const Point2f &samplePosition,
                      const Point2f &apertureSample) const override {
        (void)apertureSample;
        // Film position to a point on the plane z = 1 of camera space; the horizontal
        // field of view spans x in [-tan(fov/2), tan(fov/2)].
        const float u = samplePosition.x() / static_cast<float>(m_outputSize.x());
        const float v = samplePosition.y() / static_cast<float>(m_outputSize.y());
        const Vector3f d = Vector3f(filmX(u, m_convention) * m_tanHalfFov,
                                    (1.0f - 2.0f * v) * m_tanHalfFov / m_aspect, 1.0f)
                               .normalized();
        // The clip planes are planes z = const, so the ray's extent depends on d.z.
        const float invZ = 1.0f / d.z();
        ray = Ray3f(m_cameraToWorld * Point3f(0.0f, 0.0f, 0.0f), m_cameraToWorld * d,
                    m_nearClip * invZ, m_farClip * invZ);
        return Color3f(1.0f);
    }

    std::string toString() const override {
        return fmt::format("PerspectiveCamera[size={}x{}, fov={}, nearClip={}, farClip={}, "
                           "convention={}, rfilter={}, toWorld=\n{}]",
                           m_outputSize.x(), m_outputSize.y(), m_fov, m_nearClip, m_farClip,
                           conventionName(m_convention), m_rfilter ? m_rfilter->toString() : "none",
                           m_cameraToWorld.toString());
    }

private:
    float m_fov, m_nearClip, m_farClip;
    float m_tanHalfFov, m_aspect;
    Transform m_cameraToWorld;
    Convention m_convention;
};

NORI_REGISTER_CLASS(PerspectiveCamera, "perspective");

} // namespace nori
