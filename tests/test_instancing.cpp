// Instancing: an instance hits and renders like the same mesh transformed and loaded on
// its own; normals under non-uniform scale; nested groups; course-style tmesh files;
// spawned rays; memory per instance; bad input.
#include <nori/bsdf.h>
#include <nori/instance.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/warp.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;
using nori::testing::loadScene;
using nori::testing::randomDirection;
using nori::testing::TempDir;

namespace {

/// A wavy 8×8 height field over [-1, 1]² with per-vertex normals and uvs, so that hits
/// carry interpolated normals, tangents and uv derivatives.
std::string wavyPatchObj() {
    const int n = 8;
    auto height = [](float x, float z) { return 0.2f * std::sin(3.0f * x) * std::cos(2.0f * z); };
    std::string obj;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = -1.0f + 2.0f * i / n, z = -1.0f + 2.0f * j / n;
            const Vector3f normal = Vector3f(-0.6f * std::cos(3.0f * x) * std::cos(2.0f * z), 1.0f,
                                             0.4f * std::sin(3.0f * x) * std::sin(2.0f * z))
                                        .normalized();
            obj += fmt::format("v {} {} {}\nvt {} {}\nvn {} {} {}\n", x, height(x, z), z,
                               float(i) / n, float(j) / n, normal.x(), normal.y(), normal.z());
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = 1 + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            obj += fmt::format("f {0}/{0}/{0} {1}/{1}/{1} {2}/{2}/{2}\n", a, c, b);
            obj += fmt::format("f {0}/{0}/{0} {1}/{1}/{1} {2}/{2}/{2}\n", b, c, d);
        }
    return obj;
}

/// A transform with rotation, non-uniform scale and translation, as XML and as a matrix.
struct Placement {
    std::string xml;
};

Placement randomPlacement(PCG32 &random) {
    auto r = [&](float lo, float hi) { return lo + (hi - lo) * random.nextFloat(); };
    return {fmt::format("<transform name=\"toWorld\"><scale value=\"{}, {}, {}\"/>"
                        "<rotate axis=\"{}, {}, {}\" angle=\"{}\"/>"
                        "<translate value=\"{}, {}, {}\"/></transform>",
                        r(0.3f, 1.5f), r(0.3f, 1.5f), r(0.3f, 1.5f), r(-1, 1), r(-1, 1), r(0.1f, 1),
                        r(0, 360), r(-4, 4), r(-4, 4), r(-4, 4))};
}

const char *kSceneHead = R"(<scene><integrator type="normals"/>
    <camera type="perspective"><integer name="width" value="24"/><integer name="height" value="24"/>
        <transform name="toWorld"><lookat origin="0,0,14" target="0,0,0"/></transform></camera>
    <sampler type="independent"><integer name="sampleCount" value="8"/></sampler>)";

/// The same placements of the patch, as separate meshes and as instances of one group.
std::pair<std::string, std::string> patchScenes(int count, uint64_t seed) {
    PCG32 random(seed, 3);
    std::string separate = kSceneHead, instanced = kSceneHead;
    instanced +=
        R"(<mesh type="shapegroup" id="patch"><mesh type="obj"><string name="filename" value="patch.obj"/></mesh></mesh>)";
    for (int i = 0; i < count; ++i) {
        const Placement placement = randomPlacement(random);
        separate += R"(<mesh type="obj"><string name="filename" value="patch.obj"/>)" +
                    placement.xml + "</mesh>\n";
        instanced += R"(<mesh type="instance"><ref id="patch"/>)" + placement.xml + "</mesh>\n";
    }
    return {separate + "</scene>", instanced + "</scene>"};
}

/// A scene of one instance, placed by `transformXml`, of a group holding the unit sphere
/// and the patch moved by `patchOffset`.
std::string sphereAndPatchInstance(const std::string &patchOffset,
                                   const std::string &transformXml) {
    return fmt::format(R"(<scene><integrator type="normals"/><camera type="perspective"/>
        <mesh type="shapegroup" id="g"><mesh type="sphere"/>
            <mesh type="obj"><string name="filename" value="patch.obj"/>
                <transform name="toWorld"><translate value="{}"/></transform></mesh></mesh>
        <mesh type="instance"><ref id="g"/><transform name="toWorld">{}</transform></mesh>
    </scene>)",
                       patchOffset, transformXml);
}

/// A ray from a sphere of radius 12 toward a random point of the central region.
Ray3f randomRay(PCG32 &random) {
    const Point3f origin = 12.0f * randomDirection(random);
    const Point3f target(5.0f * (2.0f * random.nextFloat() - 1.0f),
                         5.0f * (2.0f * random.nextFloat() - 1.0f),
                         5.0f * (2.0f * random.nextFloat() - 1.0f));
    return Ray3f(origin, (target - origin).normalized());
}

bool close(const Vector3f &a, const Vector3f &b, float relative) {
    return (a - b).norm() <= relative * std::max(1.0f, std::max(a.norm(), b.norm()));
}

} // namespace

TEST_CASE("Instances hit exactly like the same meshes transformed and loaded separately",
          "[instancing]") {
    TempDir dir;
    dir.write("patch.obj", wavyPatchObj());
    const auto [separateXml, instancedXml] = patchScenes(60, 17);
    auto separate = loadScene(separateXml, dir.path().string());
    auto instanced = loadScene(instancedXml, dir.path().string());
    REQUIRE(instanced->getAccel()->instanceCount() == 60);
    REQUIRE(instanced->getAccel()->statistics().primitives == 0);

    PCG32 random(5, 8);
    int both = 0, disagreements = 0, shadowMismatches = 0, fieldMismatches = 0;
    const int rays = 20000;
    for (int i = 0; i < rays; ++i) {
        Ray3f ray = randomRay(random);
        // Differentials as a camera 1/1000 rad per pixel gives them: the footprint (dp/dx,
        // du/dx, ...) comes from the hit in world space, for instances too.
        const Frame frame(ray.d);
        ray.hasDifferentials = true;
        ray.rxOrigin = ray.ryOrigin = ray.o;
        ray.rxDirection = (ray.d + 1e-3f * frame.s).normalized();
        ray.ryDirection = (ray.d + 1e-3f * frame.t).normalized();
        Intersection a, b;
        const bool hitA = separate->rayIntersect(ray, a), hitB = instanced->rayIntersect(ray, b);
        shadowMismatches += instanced->rayIntersect(ray) != hitB ? 1 : 0;
        if (hitA != hitB) {
            ++disagreements;
            continue;
        }
        if (!hitA)
            continue;
        ++both;
        // Float rounding differs between world-space triangles and a ray carried into
        // the patch's space: relative 1e-4 on t, p and the frames, which are O(1)
        // quantities computed from O(1) inputs with ~10 roundings (1e-6) amplified by
        // the transform's condition number (≤ 5 here) and grazing hits. The tangent is
        // looser (1e-3): a loaded copy averages per-triangle tangents weighted by world
        // areas, an instance maps the average of local ones.
        bool same =
            std::abs(a.t - b.t) <= 1e-4f * a.t && close(a.p, b.p, 1e-4f) &&
            a.geoFrame.n.dot(b.geoFrame.n) > 1.0f - 1e-4f &&
            a.shFrame.n.dot(b.shFrame.n) > 1.0f - 1e-4f &&
            a.shFrame.s.dot(b.shFrame.s) > 1.0f - 1e-3f &&
            close(Vector3f(a.uv.x(), a.uv.y(), 0), Vector3f(b.uv.x(), b.uv.y(), 0), 1e-4f) &&
            close(a.dpdu, b.dpdu, 1e-3f) && close(a.dpdv, b.dpdv, 1e-3f) &&
            close(a.dndu, b.dndu, 1e-3f) && close(a.dndv, b.dndv, 1e-3f) &&
            (a.pError.array() > 0.0f).all() && (b.pError.array() > 0.0f).all();
        // The footprint is ~1e-3 of t (scaled up to compare it relatively); it is the offset
        // rays' meeting with the tangent plane, ill-conditioned at grazing angles (its
        // error grows as 1/cos²: compared where cos ≥ 0.1).
        const bool sameFootprint = std::abs(a.geoFrame.n.dot(ray.d)) < 0.1f ||
                                   (close(1e3f * a.dpdx, 1e3f * b.dpdx, 1e-3f) &&
                                    close(1e3f * a.dpdy, 1e3f * b.dpdy, 1e-3f) &&
                                    close(1e3f * Vector3f(a.dudx, a.dudy, a.dvdx),
                                          1e3f * Vector3f(b.dudx, b.dudy, b.dvdx), 1e-3f) &&
                                    a.dudx != 0.0f);
        same = same && sameFootprint;
        if (!same && ++fieldMismatches <= 3)
            UNSCOPED_INFO("ray " << i << ": t " << a.t << " vs " << b.t << ", n "
                                 << a.geoFrame.n.transpose() << " vs " << b.geoFrame.n.transpose()
                                 << ", ns " << a.shFrame.n.transpose() << " vs "
                                 << b.shFrame.n.transpose() << ", uv " << a.uv.transpose() << " vs "
                                 << b.uv.transpose());
    }
    INFO(both << " rays hit both, " << disagreements << " hit only one");
    CHECK(both > 4000);
    CHECK(fieldMismatches == 0);
    // A hit/miss disagreement needs a ray within rounding of a patch's edge.
    CHECK(disagreements <= rays / 1000);
    CHECK(shadowMismatches == 0);
}

TEST_CASE("An instanced scene renders like the separately loaded one", "[instancing][render]") {
    TempDir dir;
    dir.write("patch.obj", wavyPatchObj());
    auto [separateXml, instancedXml] = patchScenes(40, 29);
    for (std::string *xml : {&separateXml, &instancedXml}) {
        const std::string lighting = R"(<integrator type="path_mis"/>
            <emitter type="constant"><color name="radiance" value="1"/></emitter>)";
        xml->replace(xml->find(R"(<integrator type="normals"/>)"),
                     std::string(R"(<integrator type="normals"/>)").size(), lighting);
    }
    auto separate = loadScene(separateXml, dir.path().string());
    auto instanced = loadScene(instancedXml, dir.path().string());
    const RenderResult a = renderScene(*separate, nori::testing::quietOptions(2));
    const RenderResult b = renderScene(*instanced, nori::testing::quietOptions(2));
    // The same sample sequences meet the same geometry: only paths whose vertices fall
    // within rounding of an edge can differ. A difference in normals, uv or the
    // transform would change most lit pixels by several percent.
    double sumA = 0, sumB = 0;
    int differing = 0;
    for (int y = 0; y < a.image.height(); ++y)
        for (int x = 0; x < a.image.width(); ++x) {
            const float la = a.image(y, x).getLuminance(), lb = b.image(y, x).getLuminance();
            sumA += la;
            sumB += lb;
            differing += std::abs(la - lb) > 0.01f * std::max(la, lb) ? 1 : 0;
        }
    CHECK(sumB == Approx(sumA).epsilon(0.002));
    CHECK(differing <= a.image.width() * a.image.height() / 50);
}

TEST_CASE("Normals of instances under non-uniform scale and rotation are the analytic ones",
          "[instancing]") {
    // A unit sphere in a group, placed by S = diag(2, 0.5, 1), a rotation R and a
    // translation: an ellipsoid whose normal at p is ∝ (R S⁻¹)⁻ᵀ·(local point) =
    // R S⁻¹ (local point): the normals integrator must return its |n|.
    auto scene = loadScene(R"(<scene><integrator type="normals"/>
        <camera type="perspective"><integer name="width" value="8"/><integer name="height" value="8"/></camera>
        <mesh type="shapegroup" id="ball"><mesh type="sphere"/></mesh>
        <mesh type="instance"><ref id="ball"/><transform name="toWorld">
            <scale value="2, 0.5, 1"/><rotate axis="1, 2, 3" angle="40"/><translate value="0.5, -0.3, 0.2"/>
        </transform></mesh></scene>)");
    const Eigen::Matrix3d linear =
        Eigen::AngleAxisd(40.0 * kPiDouble / 180.0, Eigen::Vector3d(1, 2, 3).normalized())
            .toRotationMatrix() *
        Eigen::Vector3d(2.0, 0.5, 1.0).asDiagonal();
    const Eigen::Vector3d translation(0.5, -0.3, 0.2);
    const Eigen::Matrix3d inverse = linear.inverse();

    PCG32 random(3, 4);
    std::unique_ptr<Sampler> sampler = scene->getSampler()->clone();
    int hits = 0, wrong = 0;
    for (int i = 0; i < 20000; ++i) {
        const Point3f origin = 6.0f * randomDirection(random);
        const Point3f target = 1.5f * Point3f(randomDirection(random));
        const Ray3f ray(origin, (target - origin).normalized());
        // The analytic hit, in double: the ray in sphere space against the unit sphere.
        const Eigen::Vector3d o = inverse * (origin.cast<double>() - translation);
        const Eigen::Vector3d d = inverse * ray.d.cast<double>();
        const double a = d.squaredNorm(), b = o.dot(d), c = o.squaredNorm() - 1.0;
        const double discriminant = b * b - a * c;
        const Color3f value = scene->getIntegrator()->Li(scene.get(), sampler.get(), ray);
        if (discriminant <= 0.0) {
            wrong += (value == 0.0f).all() ? 0 : (discriminant < -1e-3 ? 1 : 0);
            continue;
        }
        const Eigen::Vector3d local = o + (-b - std::sqrt(discriminant)) / a * d;
        const Eigen::Vector3d normal = (inverse.transpose() * local).normalized();
        // Skip grazing hits, where t (and whether there is a hit) is ill-conditioned.
        if (std::abs(normal.dot(ray.d.cast<double>())) < 0.05)
            continue;
        ++hits;
        const Color3f expected(normal.cast<float>().cwiseAbs().array());
        if (!value.isApprox(expected, 1e-4f) && ++wrong <= 3)
            UNSCOPED_INFO("expected " << expected.transpose() << ", got " << value.transpose());
    }
    CHECK(hits > 5000);
    CHECK(wrong == 0);
}

TEST_CASE("A mirrored instance keeps its normals outward", "[instancing]") {
    // scale (−1, 1, 1) reverses the winding; normals map by the inverse transpose, so the
    // sphere's and the patch's normals still point to the side they point to in the group.
    TempDir dir;
    dir.write("patch.obj", wavyPatchObj());
    auto scene = loadScene(sphereAndPatchInstance("3,-2,0", R"(<scale value="-1,1,1"/>)"),
                           dir.path().string());
    Intersection its;
    REQUIRE(scene->rayIntersect(Ray3f(Point3f(5, 0.1f, 0.2f), Vector3f(-1, 0, 0)), its));
    CHECK(close(its.geoFrame.n, its.p.normalized(), 1e-4f));
    CHECK(close(its.shFrame.n, its.p.normalized(), 1e-4f));
    // The patch, now around x = −3, still faces up (+y) where it faced up.
    REQUIRE(scene->rayIntersect(Ray3f(Point3f(-3.05f, 3, 0.05f), Vector3f(0, -1, 0)), its));
    CHECK(its.geoFrame.n.y() > 0.5f);
    CHECK(its.shFrame.n.y() > 0.5f);
}

TEST_CASE("Nested groups place their instances through every level", "[instancing]") {
    // ball (r = 0.25 at the origin) -> pair (two balls 1 apart in x) -> quad (two pairs 2
    // apart in y) -> two quads placed in the scene, one translated by (0, 0, -5) and one
    // rotated 90° about z and moved to (10, 0, 0): eight spheres at known centres.
    auto scene = loadScene(R"(<scene><integrator type="normals"/>
        <camera type="perspective"/>
        <mesh type="shapegroup" id="ball"><mesh type="sphere"><float name="radius" value="0.25"/></mesh></mesh>
        <mesh type="shapegroup" id="pair">
            <mesh type="instance"><ref id="ball"/></mesh>
            <mesh type="instance"><ref id="ball"/><transform name="toWorld"><translate value="1,0,0"/></transform></mesh>
        </mesh>
        <mesh type="shapegroup" id="quad">
            <mesh type="instance"><ref id="pair"/></mesh>
            <mesh type="instance"><ref id="pair"/><transform name="toWorld"><translate value="0,2,0"/></transform></mesh>
        </mesh>
        <mesh type="instance"><ref id="quad"/><transform name="toWorld"><translate value="0,0,-5"/></transform></mesh>
        <mesh type="instance"><ref id="quad"/><transform name="toWorld"><rotate axis="0,0,1" angle="90"/><translate value="10,0,0"/></transform></mesh>
    </scene>)");
    CHECK(scene->getAccel()->instanceDepth() == 3);
    std::vector<Point3f> centres;
    for (float x : {0.0f, 1.0f})
        for (float y : {0.0f, 2.0f}) {
            centres.emplace_back(x, y, -5.0f);
            centres.emplace_back(10.0f - y, x, 0.0f); // rotated: (x, y) -> (-y, x)
        }
    for (const Point3f &centre : centres) {
        // Along −z onto each sphere: no other sphere shares its (x, y).
        Intersection its;
        const Ray3f ray(centre + Point3f(0.1f, 0.0f, 5.0f), Vector3f(0, 0, -1));
        INFO("centre " << centre.transpose());
        REQUIRE(scene->rayIntersect(ray, its));
        const float expectedT = 5.0f - std::sqrt(0.25f * 0.25f - 0.1f * 0.1f);
        CHECK(its.t == Approx(expectedT).epsilon(1e-5));
        CHECK(close(its.geoFrame.n, (its.p - centre).normalized(), 1e-4f));
    }
    // Between the spheres there is nothing.
    Intersection its;
    CHECK_FALSE(scene->rayIntersect(Ray3f(Point3f(0.5f, 1.0f, 5.0f), Vector3f(0, 0, -1)), its));

    // Deeper than the supported eight levels: a clear error.
    std::string deep = R"(<scene><integrator type="normals"/><camera type="perspective"/>
        <mesh type="shapegroup" id="g0"><mesh type="sphere"/></mesh>)";
    for (int level = 1; level <= 9; ++level)
        deep += fmt::format(
            R"(<mesh type="shapegroup" id="g{}"><mesh type="instance"><ref id="g{}"/></mesh></mesh>)",
            level, level - 1);
    deep += R"(<mesh type="instance"><ref id="g9"/></mesh></scene>)";
    CHECK_THAT(errorOf([&] { loadScene(deep); }), Contains("instances nest 9 levels deep"));
}

TEST_CASE("A course-style tmesh file: copies of their parent, with their own BSDF or its",
          "[instancing]") {
    TempDir dir;
    dir.write("patch.obj", wavyPatchObj());
    // The template is invisible; three copies: two with the parent's BSDF, one with its own.
    auto scene = loadScene(R"(<scene><integrator type="normals"/><camera type="perspective"/>
        <mesh type="obj"><string name="filename" value="patch.obj"/>
            <boolean name="visible" value="false"/>
            <bsdf type="diffuse"><color name="albedo" value="0.25"/></bsdf>
            <mesh type="tmesh"><transform name="toWorld"><translate value="-3,0,0"/></transform></mesh>
            <mesh type="tmesh"><transform name="toWorld"><translate value="3,0,0"/></transform></mesh>
            <mesh type="tmesh"><transform name="toWorld"><translate value="0,0,3"/></transform>
                <bsdf type="mirror"/></mesh>
        </mesh></scene>)",
                           dir.path().string());
    auto hitAbove = [&](float x, float z, Intersection &its) {
        return scene->rayIntersect(Ray3f(Point3f(x + 0.05f, 5.0f, z + 0.05f), Vector3f(0, -1, 0)),
                                   its);
    };
    Intersection its;
    CHECK_FALSE(hitAbove(0, 0, its)); // the template itself is not rendered
    REQUIRE(hitAbove(-3, 0, its));
    CHECK(its.shape->getBSDF()->isDiffuse());
    REQUIRE(hitAbove(3, 0, its));
    CHECK(its.shape->getBSDF()->isDiffuse());
    CHECK(its.uv.x() == Approx(0.525f).margin(1e-4)); // the parent's uvs: (x + 1)/2
    REQUIRE(hitAbove(0, 3, its));
    CHECK_FALSE(its.shape->getBSDF()->isDiffuse()); // the copy's own mirror
    CHECK(scene->getAccel()->instanceCount() == 3);

    // Visible by default: the parent renders as well as its copy.
    auto visible = loadScene(R"(<scene><integrator type="normals"/><camera type="perspective"/>
        <mesh type="obj"><string name="filename" value="patch.obj"/>
            <mesh type="tmesh"><transform name="toWorld"><translate value="-3,0,0"/></transform></mesh>
        </mesh></scene>)",
                             dir.path().string());
    CHECK(visible->rayIntersect(Ray3f(Point3f(0.05f, 5.0f, 0.05f), Vector3f(0, -1, 0)), its));
    CHECK(visible->rayIntersect(Ray3f(Point3f(-2.95f, 5.0f, 0.05f), Vector3f(0, -1, 0)), its));
}

TEST_CASE("Rays spawned from instanced surfaces never hit them again", "[instancing]") {
    // A sphere of radius 300 and a patch placed far from the origin by a rotation and a
    // non-uniform scale: large coordinates make the transform's rounding matter.
    TempDir dir;
    dir.write("patch.obj", wavyPatchObj());
    auto scene = loadScene(sphereAndPatchInstance("0,-1.5,0", R"(<scale value="300, 200, 350"/>
            <rotate axis="1,1,1" angle="33"/><translate value="1000,-1000,500"/>)"),
                           dir.path().string());
    const Point3f centre(1000, -1000, 500);
    PCG32 random(9, 10);
    int tested = 0, reHits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Ray3f ray(centre + 50.0f * randomDirection(random), randomDirection(random), 0.0f,
                        kInfinity);
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            continue;
        ++tested;
        // Back the way the ray came: leaving the surface, it must not find it at t ≈ 0.
        Intersection next;
        if (scene->rayIntersect(its.spawnRay(-ray.d), next) && next.t < 1e-2f)
            ++reHits;
        // Onward through the surface: the next hit is elsewhere, not the start point.
        if (scene->rayIntersect(its.spawnRay(ray.d), next) && next.t < 1e-2f)
            ++reHits;
        // A shadow ray to a point beyond on the normal's side is not blocked by its origin.
        Vector3f side = its.geoFrame.n.dot(-ray.d) > 0.0f ? its.geoFrame.n : -its.geoFrame.n;
        if (scene->rayIntersect(its.spawnRayTo(its.p + 0.5f * side)))
            ++reHits;
    }
    CHECK(tested > 15000);
    CHECK(reHits == 0);
}

TEST_CASE("An instance costs at most 128 bytes in the acceleration structure", "[instancing]") {
    std::string xml = R"(<scene><integrator type="normals"/><camera type="perspective"/>
        <mesh type="shapegroup" id="g"><mesh type="sphere"/></mesh>)";
    PCG32 random(1, 2);
    const int count = 20000;
    for (int i = 0; i < count; ++i)
        xml += fmt::format(
            R"(<mesh type="instance"><ref id="g"/><transform name="toWorld"><translate value="{}, {}, {}"/></transform></mesh>)",
            100 * random.nextFloat(), 100 * random.nextFloat(), 100 * random.nextFloat());
    xml += "</scene>";
    // The same placements as course-style tmesh copies of an invisible sphere.
    std::string tmeshXml = R"(<scene><integrator type="normals"/><camera type="perspective"/>
        <mesh type="sphere"><boolean name="visible" value="false"/>)";
    for (size_t at = xml.find("<transform"); at != std::string::npos;
         at = xml.find("<transform", at + 1))
        tmeshXml += "<mesh type=\"tmesh\">" +
                    xml.substr(at, xml.find("</transform>", at) + 12 - at) + "</mesh>";
    tmeshXml += "</mesh></scene>";

    for (const std::string *text : {&xml, &tmeshXml}) {
        auto scene = loadScene(*text);
        const Accel &accel = *scene->getAccel();
        REQUIRE(accel.instanceCount() == count);
        const double perInstance = static_cast<double>(accel.memoryBytes()) / count;
        INFO(perInstance << " bytes per instance, " << accel.instanceStatistics().nodes
                         << " nodes");
        CHECK(perInstance <= 128.0);
    }
}

TEST_CASE("Bad instancing input gets a located error", "[instancing][errors]") {
    const std::string head = R"(<scene><integrator type="normals"/><camera type="perspective"/>
)";
    auto errorFor = [&](const std::string &body) {
        return errorOf([&] { loadFromXMLString(head + body + "</scene>"); });
    };
    // A tmesh not inside a mesh, at line 2.
    CHECK_THAT(errorFor(R"(<mesh type="tmesh"/>)"),
               Contains("<string>:2:") && Contains("must be nested inside the mesh"));
    CHECK_THAT(errorFor(R"(<mesh type="shapegroup" id="g"><mesh type="tmesh"/></mesh>)"),
               Contains("must be nested inside the mesh"));
    // A <ref> to something that is not a group.
    CHECK_THAT(errorFor(R"(<bsdf type="diffuse" id="white"/>
<mesh type="instance"><ref id="white"/></mesh>)"),
               Contains("<string>:3:") &&
                   Contains("places a <mesh type=\"shapegroup\"> (through <ref>), not a <bsdf "
                            "type=\"diffuse\">"));
    // A cycle: a group that holds an instance of itself.
    CHECK_THAT(errorFor(R"(<mesh type="shapegroup" id="loop">
  <mesh type="instance"><ref id="loop"/></mesh></mesh>)"),
               Contains("<string>:3:") && Contains("<ref> to 'loop' inside the element") &&
                   Contains("a cycle"));
    // An instance without its group, and a reference to a group not declared yet.
    CHECK_THAT(errorFor(R"(<mesh type="instance"/>)"), Contains("needs a <ref id="));
    CHECK_THAT(errorFor(R"(<mesh type="instance"><ref id="later"/></mesh>)"),
               Contains("<ref> to unknown id 'later'"));
    // Area lights on instanced geometry are refused.
    CHECK_THAT(errorFor(R"(<mesh type="shapegroup" id="g"><mesh type="sphere">
  <emitter type="area"><color name="radiance" value="1"/></emitter></mesh></mesh>)"),
               Contains("cannot hold an area light"));
    CHECK_THAT(
        errorFor(
            R"(<mesh type="sphere"><emitter type="area"><color name="radiance" value="1"/></emitter>
  <mesh type="tmesh"/></mesh>)"),
        Contains("area light on a shape with tmesh copies is not supported"));
    // A shape inside a shape, and a projective placement.
    CHECK_THAT(errorFor(R"(<mesh type="sphere"><mesh type="sphere"/></mesh>)"),
               Contains("holds no other shapes"));
    CHECK_THAT(errorFor(R"(<mesh type="shapegroup" id="g"><mesh type="sphere"/></mesh>
<mesh type="instance"><ref id="g"/><transform name="toWorld"><matrix value="1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1"/></transform></mesh>)"),
               Contains("must be affine"));
    CHECK_THAT(errorFor(R"(<mesh type="shapegroup" id="g"/>)"),
               Contains("needs at least one shape or instance"));
}

TEST_CASE("The meadow example: what nori-make-meadow writes, nested as flat", "[instancing]") {
    // The generator writes the committed files again, and the flat form (every blade an
    // instance of its own, transforms composed) hits like the three-level one.
    TempDir dir;
    const auto meadowDir = dir.path() / "meadow";
    std::filesystem::create_directory_symlink(
        std::filesystem::path(NORI_SOURCE_DIR) / "scenes/textured", dir.path() / "textured");
    const auto made =
        nori::testing::runCommand(MAKE_MEADOW_EXECUTABLE, {meadowDir.string(), "--flat"});
    REQUIRE(made.exitCode == 0);
    auto read = [](const std::filesystem::path &path) {
        std::ifstream in(path);
        std::stringstream content;
        content << in.rdbuf();
        return content.str();
    };
    const std::filesystem::path committed =
        std::filesystem::path(NORI_SOURCE_DIR) / "scenes/meadow";
    CHECK(read(meadowDir / "meadow.xml") == read(committed / "meadow.xml"));
    CHECK(read(meadowDir / "blade.obj") == read(committed / "blade.obj"));

    auto nested =
        std::dynamic_pointer_cast<Scene>(loadFromXML((meadowDir / "meadow.xml").string()));
    auto flat =
        std::dynamic_pointer_cast<Scene>(loadFromXML((meadowDir / "meadow_flat.xml").string()));
    REQUIRE(nested);
    REQUIRE(flat);
    CHECK(nested->getAccel()->instanceCount() == 64);
    CHECK(nested->getAccel()->instanceDepth() == 3);
    CHECK(flat->getAccel()->instanceCount() == 102400);

    // Rays from the camera's height down into the grass, over the whole field.
    PCG32 random(12, 34);
    int blades = 0, agree = 0;
    const int rays = 5000;
    for (int i = 0; i < rays; ++i) {
        const Point3f origin(16.0f * random.nextFloat() - 8.0f, 1.0f,
                             16.0f * random.nextFloat() - 8.0f);
        const Vector3f d =
            Vector3f(random.nextFloat() - 0.5f, -1.0f, random.nextFloat() - 0.5f).normalized();
        Intersection a, b;
        const bool hitA = nested->rayIntersect(Ray3f(origin, d), a);
        const bool hitB = flat->rayIntersect(Ray3f(origin, d), b);
        blades += hitA && a.p.y() > 1e-3f ? 1 : 0;
        agree += hitA == hitB && (!hitA || std::abs(a.t - b.t) <= 1e-4f * a.t) ? 1 : 0;
    }
    INFO(blades << " rays hit a blade, " << agree << " of " << rays << " agree");
    CHECK(blades > rays / 10); // seen from above, blades cover about a fifth of the ground
    // Composing three transforms rounds differently from applying them one by one: only
    // rays within that rounding of a blade's edge may disagree.
    CHECK(agree >= rays - rays / 200);
}
