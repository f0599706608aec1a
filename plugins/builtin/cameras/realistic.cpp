/*
 * realistic — a camera behind a real lens system, traced element by element from the
 * film (Kolb et al. 1995; pbrt-v3 §6.4): depth of field, vignetting, distortion and the
 * aberrations of the prescription. Lens data are pbrt's tabular files in millimetres; the
 * scene is in metres. The film is the camera-space plane z = 0 (toWorld places it), the
 * lens looks along +z.
 *
 * Focusing moves the lens so that points focusDistance in front of the film are sharp,
 * by the thick-lens approximation. Rays are drawn from the exit pupil (an ellipse
 * tabulated over the film radius), so few are lost to vignetting. Each carries the weight
 * cos⁴θ·A/z² of the film irradiance estimate (pbrt-v3 eq. 6.3; θ the ray's angle to the
 * axis, A the area sampled, z the rear element's distance), divided by its value on the
 * axis: a uniformly bright scene renders at its radiance at the image centre, darker
 * toward the corners as the real lens vignettes.
 *
 * Ray differentials are approximate: the rays of the film positions one pixel over that
 * pass through the same point of the exit pupil's ellipse (the mirror offset where one is
 * vignetted); with neither, the chief rays (through the ellipse's centre) stand in.
 *
 * Parameters:
 *   lensFile          string     (required)  lens prescription, relative to the XML file
 *   apertureDiameter  float      the file's  iris diameter in mm (at most the file's)
 *   focusDistance     float      10          distance of the sharp plane from the film
 *   filmDiagonal      float      35          film diagonal in mm
 *   width             integer    1280        image width in pixels
 *   height            integer    720         image height in pixels
 *   toWorld           transform  identity    camera-to-world transform
 *   convention        string     "epfl"      image x mirrored ("epfl") or not ("eth")
 *   sampleBorder      boolean    false       edge pixels see beyond the image's edge
 *                                            through their filter (pbrt-v4's film)
 *   cropOffsetX, cropOffsetY, cropWidth, cropHeight  integer  (none)  render and write
 *                                            only this rectangle of the width × height image
 *   whiteBalance      float      0           white-balance the sensor for a daylight
 *                                            illuminant of this temperature in K; 0: not
 *
 *   <camera type="realistic">
 *       <string name="lensFile" value="scenes/lenses/dgauss.50mm.dat"/>
 *       <float name="apertureDiameter" value="8"/> <float name="focusDistance" value="4"/>
 *   </camera>
 */
#include <nori/camera.h>
#include <nori/lenssystem.h>
#include <nori/lowdiscrepancy.h>
#include <nori/transform.h>

#include <limits>
#include <memory>
#include <mutex>

namespace nori {
namespace {

class RealisticCamera : public Camera {
public:
    explicit RealisticCamera(const PropertyList &props) {
        m_lensFile = props.getPath("lensFile");
        m_apertureDiameter = props.getFloat("apertureDiameter", 0.0f);
        m_focusDistance = props.getFloat("focusDistance", 10.0f);
        m_filmDiagonal = props.getFloat("filmDiagonal", 35.0f);
        readFilm(props);
        m_cameraToWorld = props.getTransform("toWorld", Transform());
        m_convention = readConvention(props);

        if (props.has("apertureDiameter") &&
            !(m_apertureDiameter > 0.0f && std::isfinite(m_apertureDiameter)))
            throw NoriException("realistic: 'apertureDiameter' must be positive, got {} mm",
                                m_apertureDiameter);
        if (!(m_focusDistance > 0.0f) || !std::isfinite(m_focusDistance))
            throw NoriException("realistic: 'focusDistance' must be positive, got {}",
                                m_focusDistance);
        if (!(m_filmDiagonal > 0.0f) || !std::isfinite(m_filmDiagonal))
            throw NoriException("realistic: 'filmDiagonal' must be positive, got {} mm",
                                m_filmDiagonal);

        m_lens =
            std::make_unique<LensSystem>(readLensFile(m_lensFile), m_apertureDiameter, m_lensFile);
        m_lens->focusAt(m_focusDistance);

        m_filmSize = filmExtent(1e-3 * m_filmDiagonal, m_fullSize.x(), m_fullSize.y());
        // Focusing traced paraxial rays through every aperture, so light reaches the
        // film's centre and the weights' normalisation (axialIrradiance) is positive.
    }

    Color3f sampleRay(Ray3f &ray, const Point2f &samplePosition,
                      const Point2f &apertureSample) const override {
        const Eigen::Vector3d film = filmPoint(samplePosition);
        LensRay out;
        const double irradiance = traceThroughPupil(
            pupil(), film, Eigen::Vector2d(apertureSample.x(), apertureSample.y()), &out);
        if (irradiance == 0.0)
            return Color3f(0.0f);
        ray = toWorld(out);
        return Color3f(static_cast<float>(irradiance / m_axialIrradiance));
    }

    Color3f sampleRayDifferential(Ray3f &ray, const Point2f &samplePosition,
                                  const Point2f &apertureSample) const override {
        Color3f weight = sampleRay(ray, samplePosition, apertureSample);
        if ((weight == 0.0f).all())
            return weight;
        // The rays one pixel over pass through the same point of the rear lens: the
        // derivative of the ray by the film position at a fixed pupil point. (Through the
        // same sample u instead, a neighbour in another of the exit pupil's radial regions
        // lands elsewhere on the rear lens, and the difference holds that jump: 16 % short
        // at film (474.5, 67.4) of the test's lens.)
        double regionArea = 0.0;
        const Eigen::Vector3d rear =
            pupil().sample(filmPoint(samplePosition).head<2>(),
                           Eigen::Vector2d(apertureSample.x(), apertureSample.y()), &regionArea);
        // The change of the ray over a step h of film, scaled to one pixel (a finite
        // difference). Near the edge of the vignetted pupil the ray one pixel over, or
        // back, may be blocked where a shorter step is not; if every step is blocked, the
        // chief rays' change is added to this ray (which misses how the off-axis ray's own
        // aberrations change).
        auto neighbour = [&](const Point2f &offset, Point3f &origin, Vector3f &direction) {
            for (const float step : {1.0f, -1.0f, 0.25f, -0.25f, 0.0625f, -0.0625f}) {
                LensRay out;
                if (traceToward(filmPoint(samplePosition + step * offset), rear, &out)) {
                    const Ray3f next = toWorld(out);
                    origin = ray.o + (next.o - ray.o) / step;
                    direction = ray.d + (next.d - ray.d) / step;
                    return;
                }
            }
            origin = ray.o;
            direction = ray.d + (chiefRay(samplePosition + offset).d - chiefRay(samplePosition).d);
        };
        neighbour(Point2f(1.0f, 0.0f), ray.rxOrigin, ray.rxDirection);
        neighbour(Point2f(0.0f, 1.0f), ray.ryOrigin, ray.ryDirection);
        ray.hasDifferentials = ray.rxDirection.allFinite() && ray.ryDirection.allFinite();
        return weight;
    }

    std::string toString() const override {
        return fmt::format("RealisticCamera[lensFile=\"{}\", apertureDiameter={}, "
                           "focusDistance={}, filmDiagonal={}, size={}x{}, crop={}x{}+{}+{}, "
                           "convention={}, rfilter={}, toWorld=\n{}]",
                           m_lensFile, m_apertureDiameter, m_focusDistance, m_filmDiagonal,
                           m_fullSize.x(), m_fullSize.y(), m_outputSize.x(), m_outputSize.y(),
                           m_cropOffset.x(), m_cropOffset.y(), conventionName(m_convention),
                           m_rfilter ? m_rfilter->toString() : "none", m_cameraToWorld.toString());
    }

private:
    /// The camera-space film point of a film position in pixels. The lens inverts the
    /// image, so the point sits opposite to where its pixel looks: the top row low, and
    /// the left column on camera −x for EPFL's mirrored x (whose left looks along +x).
    Eigen::Vector3d filmPoint(const Point2f &samplePosition) const {
        const Point2f fraction = fullImageFraction(samplePosition);
        const float u = fraction.x(), v = fraction.y();
        return Eigen::Vector3d(-filmX(u, m_convention) * 0.5 * m_filmSize.x(),
                               -(1.0 - 2.0 * v) * 0.5 * m_filmSize.y(), 0.0);
    }

    /// The exit pupil and the weights' normalisation, tabulated at the first ray (0.2 s
    /// on 2 cores): loading a scene, or fuzzing the parser with one, does not pay for them.
    const ExitPupil &pupil() const {
        std::call_once(m_pupilTabulated, [this] {
            m_pupil = std::make_unique<ExitPupil>(*m_lens, 0.5e-3 * m_filmDiagonal);
            m_axialIrradiance = axialIrradiance(*m_pupil);
        });
        return *m_pupil;
    }

    /// Traces from `film` through the exit-pupil point of sample `u`; returns the estimate
    /// cos⁴θ·A/z² of the irradiance per unit radiance, or 0 when the lens blocks the ray.
    double traceThroughPupil(const ExitPupil &exitPupil, const Eigen::Vector3d &film,
                             const Eigen::Vector2d &u, LensRay *out) const {
        double regionArea = 0.0;
        const Eigen::Vector3d rear = exitPupil.sample(film.head<2>(), u, &regionArea);
        if (regionArea == 0.0 || !traceToward(film, rear, out))
            return 0.0;
        const double cosTheta = (rear - film).normalized().z(), rearZ = m_lens->rearZ();
        return cosTheta * cosTheta * cosTheta * cosTheta * regionArea / (rearZ * rearZ);
    }

    /// Traces from `film` toward the point `rear` on the rear lens; false when the lens
    /// blocks the ray.
    bool traceToward(const Eigen::Vector3d &film, const Eigen::Vector3d &rear, LensRay *out) const {
        return m_lens->traceFromFilm({film, (rear - film).normalized()}, out);
    }

    /// The film centre's irradiance per unit radiance, ∫ cos⁴θ/z² dA over the exit pupil,
    /// by quasi-Monte Carlo over its ellipse: the weights' normalisation.
    double axialIrradiance(const ExitPupil &exitPupil) const {
        constexpr int kSamples = 1 << 16;
        double sum = 0.0;
        for (int i = 0; i < kSamples; ++i)
            sum += traceThroughPupil(exitPupil, Eigen::Vector3d::Zero(),
                                     Eigen::Vector2d(radicalInverse(2, i), radicalInverse(3, i)),
                                     nullptr);
        return sum / kSamples;
    }

    /// The ray from a film position through the centre of its exit pupil's ellipse (its
    /// origin and direction are NaN when even that one is vignetted).
    Ray3f chiefRay(const Point2f &samplePosition) const {
        LensRay out;
        if (traceThroughPupil(pupil(), filmPoint(samplePosition), Eigen::Vector2d(0.5, 0.5),
                              &out) == 0.0)
            return Ray3f(Point3f::Constant(std::numeric_limits<float>::quiet_NaN()),
                         Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
        return toWorld(out);
    }

    Ray3f toWorld(const LensRay &ray) const {
        const Point3f origin = m_cameraToWorld * Point3f(ray.o.cast<float>());
        const Vector3f direction = (m_cameraToWorld * Vector3f(ray.d.cast<float>())).normalized();
        return Ray3f(origin, direction);
    }

    std::string m_lensFile;
    float m_apertureDiameter, m_focusDistance, m_filmDiagonal;
    Transform m_cameraToWorld;
    Convention m_convention;

    std::unique_ptr<LensSystem> m_lens;
    Eigen::Vector2d m_filmSize;
    // Tabulated by pupil() at the first ray.
    mutable std::once_flag m_pupilTabulated;
    mutable std::unique_ptr<ExitPupil> m_pupil;
    mutable double m_axialIrradiance = 0.0;
};

NORI_REGISTER_CLASS(RealisticCamera, "realistic");

} // namespace
} // namespace nori
