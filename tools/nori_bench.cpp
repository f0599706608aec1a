// nori-bench: BVH build time and ray throughput on a mesh, for three ray sets defined
// so that figures compare between renderers; with Embree 3 installed, the same rays go
// through Embree in the same process. Also writes the bumpy-sphere test mesh.
//
//   nori-bench --make-mesh 1000000 sphere.obj
//   nori-bench sphere.obj [--rays N] [--threads T]
// It first checks, ray by ray, that the BVH answers exactly as a brute-force loop on a
// small mesh, then measures with one thread (pinned to one core) and with T threads
// (default: all).
#include "app/cli.h"
#include <nori/accel.h>
#include <nori/mesh.h>
#include <nori/pcg32.h>
#include <nori/strutil.h>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#ifdef NORI_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

#include <sched.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

using namespace nori;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A sphere of radius ~1 with bumps r(θ, φ) = 1 + 0.05·sin(12θ)·sin(12φ), tessellated as
/// a latitude–longitude grid with single-vertex poles: 2·C·(R − 1) triangles for R rings
/// and C = 2R columns, with R chosen to come closest to the requested count.
/// Returns the number of triangles written.
size_t writeBumpySphere(size_t requestedTriangles, const std::string &filename) {
    const int rings = std::max(
        2, static_cast<int>(std::lround(0.5 * (1.0 + std::sqrt(1.0 + requestedTriangles)))));
    const int columns = 2 * rings;
    std::ofstream out(filename);
    if (!out)
        throw NoriException("cannot write '{}'", filename);
    auto vertex = [&](double theta, double phi) {
        const double r = 1.0 + 0.05 * std::sin(12.0 * theta) * std::sin(12.0 * phi);
        out << fmt::format("v {:.7f} {:.7f} {:.7f}\n", r * std::sin(theta) * std::cos(phi),
                           r * std::cos(theta), r * std::sin(theta) * std::sin(phi));
    };
    vertex(0.0, 0.0); // north pole: vertex 1
    for (int ring = 1; ring < rings; ++ring)
        for (int column = 0; column < columns; ++column)
            vertex(kPiDouble * ring / rings, 2.0 * kPiDouble * column / columns);
    vertex(kPiDouble, 0.0); // south pole
    const int south = 2 + (rings - 1) * columns;
    auto index = [&](int ring, int column) { return 2 + (ring - 1) * columns + column % columns; };
    size_t triangles = 0;
    for (int column = 0; column < columns; ++column) {
        out << fmt::format("f 1 {} {}\n", index(1, column + 1), index(1, column));
        out << fmt::format("f {} {} {}\n", south, index(rings - 1, column),
                           index(rings - 1, column + 1));
        triangles += 2;
        for (int ring = 1; ring + 1 < rings; ++ring) {
            out << fmt::format("f {} {} {}\n", index(ring, column), index(ring, column + 1),
                               index(ring + 1, column + 1));
            out << fmt::format("f {} {} {}\n", index(ring, column), index(ring + 1, column + 1),
                               index(ring + 1, column));
            triangles += 2;
        }
    }
    return triangles;
}

struct RaySet {
    std::string name;
    std::vector<Ray3f> rays;
    bool occlusion;
};

/// The three ray sets of the benchmark, each of (about) `count` rays.
std::vector<RaySet> makeRaySets(size_t count) {
    std::vector<RaySet> sets;
    // Primary: pinhole at (0,0,4) looking at the origin, +y up, 60° vertical fov,
    // a √N×√N grid of pixel-centre rays.
    const int resolution = static_cast<int>(std::sqrt(static_cast<double>(count)));
    const float tanHalfFov = std::tan(degToRad(30.0f));
    RaySet primary{"primary", {}, false};
    for (int y = 0; y < resolution; ++y)
        for (int x = 0; x < resolution; ++x) {
            const float u = (2.0f * (x + 0.5f) / resolution - 1.0f) * tanHalfFov;
            const float v = (1.0f - 2.0f * (y + 0.5f) / resolution) * tanHalfFov;
            primary.rays.emplace_back(Point3f(0, 0, 4), Vector3f(u, v, -1.0f).normalized(), 0.0f,
                                      kInfinity);
        }
    sets.push_back(std::move(primary));

    // Incoherent: origin uniform on the sphere of radius 3, aimed at a point uniform in
    // the unit ball (rejection sampling).
    PCG32 random(42, 54);
    RaySet incoherent{"incoherent", {}, false};
    while (incoherent.rays.size() < count) {
        const float z = 1.0f - 2.0f * random.nextFloat(), phi = 2.0f * kPi * random.nextFloat();
        const float r = safeSqrt(1.0f - z * z);
        const Point3f origin = 3.0f * Point3f(r * std::cos(phi), r * std::sin(phi), z);
        Point3f target;
        do {
            target = Point3f(2.0f * random.nextFloat() - 1.0f, 2.0f * random.nextFloat() - 1.0f,
                             2.0f * random.nextFloat() - 1.0f);
        } while (target.squaredNorm() > 1.0f);
        incoherent.rays.emplace_back(origin, Vector3f(target - origin).normalized(), 0.0f,
                                     kInfinity);
    }
    RaySet shadow{"shadow", incoherent.rays, true};
    sets.push_back(std::move(incoherent));
    sets.push_back(std::move(shadow));
    return sets;
}

struct Measurement {
    double seconds = 0.0;
    size_t hits = 0;
};

/// Traces every ray in parallel chunks (one thread: a plain loop) and counts hits.
template <typename Trace> Measurement traceAll(const RaySet &set, Trace &&trace) {
    std::atomic<size_t> hits{0};
    const auto start = std::chrono::steady_clock::now();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, set.rays.size(), 1024),
                      [&](const tbb::blocked_range<size_t> &range) {
                          size_t local = 0;
                          for (size_t i = range.begin(); i != range.end(); ++i)
                              local += trace(set.rays[i], set.occlusion) ? 1 : 0;
                          hits += local;
                      });
    return {secondsSince(start), hits.load()};
}

/// A mesh loaded through the renderer's own OBJ plugin.
std::shared_ptr<Mesh> loadMesh(const std::string &filename) {
    PropertyList props;
    props.setString("filename", filename);
    auto object = NoriObjectFactory::createInstance("obj", NoriObject::EMesh, props);
    object->activate();
    return std::dynamic_pointer_cast<Mesh>(object);
}

#ifdef NORI_HAVE_EMBREE
/// The same mesh in an Embree scene.
class EmbreeScene {
public:
    EmbreeScene(const Mesh &mesh, int threads, double &buildSeconds) {
        const std::string config = fmt::format("threads={}", threads);
        m_device = rtcNewDevice(config.c_str());
        if (!m_device)
            throw NoriException("Embree: cannot create a device");
        m_scene = rtcNewScene(m_device);
        RTCGeometry geometry = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
        const auto &positions = mesh.positions();
        const auto &faces = mesh.faces();
        auto *vertices = static_cast<float *>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    3 * sizeof(float), positions.size()));
        for (size_t i = 0; i < positions.size(); ++i)
            for (int c = 0; c < 3; ++c)
                vertices[3 * i + c] = positions[i][c];
        auto *indices = static_cast<uint32_t *>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), faces.size()));
        for (size_t i = 0; i < faces.size(); ++i)
            for (int c = 0; c < 3; ++c)
                indices[3 * i + c] = static_cast<uint32_t>(faces[i][c]);
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(m_scene, geometry);
        rtcReleaseGeometry(geometry);
        const auto start = std::chrono::steady_clock::now();
        rtcCommitScene(m_scene);
        buildSeconds = secondsSince(start);
    }
    ~EmbreeScene() {
        rtcReleaseScene(m_scene);
        rtcReleaseDevice(m_device);
    }

    bool trace(const Ray3f &ray, bool occlusion) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rayHit{};
        RTCRay &r = rayHit.ray;
        r.org_x = ray.o.x(), r.org_y = ray.o.y(), r.org_z = ray.o.z();
        r.dir_x = ray.d.x(), r.dir_y = ray.d.y(), r.dir_z = ray.d.z();
        r.tnear = ray.mint;
        r.tfar = ray.maxt;
        r.mask = ~0u;
        if (occlusion) {
            rtcOccluded1(m_scene, &context, &r);
            return r.tfar < 0.0f; // Embree sets tfar to -inf on a hit
        }
        rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(m_scene, &context, &rayHit);
        return rayHit.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }

private:
    RTCDevice m_device;
    RTCScene m_scene;
};
#endif

/// Closest hit of every ray on a small bumpy sphere, through the Accel and through a
/// brute-force loop over all triangles (the scalar watertight test); returns how many
/// rays disagree on hit, t or triangle.
size_t equalityCheck(const std::string &meshFile, size_t rayCount) {
    std::shared_ptr<Mesh> mesh = loadMesh(meshFile);
    Accel accel;
    accel.addShape(mesh.get());
    accel.build();
    size_t mismatches = 0, rays = 0;
    for (const RaySet &set : makeRaySets(rayCount)) {
        for (const Ray3f &ray : set.rays) {
            bool expected = false;
            float tExpected = 0.0f;
            uint32_t primExpected = 0;
            for (uint32_t i = 0; i < mesh->getPrimitiveCount(); ++i) {
                float t;
                Point2f coords;
                if (mesh->rayIntersect(i, ray, t, coords) && (!expected || t < tExpected)) {
                    expected = true;
                    tExpected = t;
                    primExpected = i;
                }
            }
            Intersection its;
            const bool actual = accel.rayIntersect(ray, its, set.occlusion);
            const bool same =
                set.occlusion
                    ? actual == expected
                    : actual == expected &&
                          (!expected || (its.t == tExpected && its.primIndex == primExpected));
            mismatches += same ? 0 : 1;
            ++rays;
        }
    }
    std::cout << fmt::format(
        "equality_mesh_triangles {}\nequality_rays {}\nequality_mismatches {}\n",
        mesh->getPrimitiveCount(), rays, mismatches);
    return mismatches;
}

/// Pins the calling thread to one CPU (the last), or releases it to all with cpu < 0.
void pinToCpu(int cpu) {
    cpu_set_t set;
    CPU_ZERO(&set);
    const int cpus = static_cast<int>(std::thread::hardware_concurrency());
    if (cpu >= 0)
        CPU_SET(cpu, &set);
    else
        for (int i = 0; i < cpus; ++i)
            CPU_SET(i, &set);
    if (sched_setaffinity(0, sizeof(set), &set) != 0)
        std::cerr << "Warning: cannot set the CPU affinity\n";
}

/// Builds and traces the ray sets with `threads` threads; every figure is printed with
/// the prefix (`t1_`, `tN_`). Each of `rounds` rounds builds ours and Embree's and traces
/// every set through both, one after the other, and each figure keeps its best round:
/// this VM's speed drifts by ±20% over seconds, which interleaving spreads evenly over
/// both and the best round filters out.
void measure(const Mesh &mesh, const std::vector<RaySet> &sets, int threads, int rounds,
             const std::string &prefix) {
    tbb::global_control threadLimit(tbb::global_control::max_allowed_parallelism,
                                    static_cast<size_t>(threads));
    std::cout << prefix << "threads " << threads << "\n";
    auto keepBest = [](Measurement &best, const Measurement &round) {
        if (best.seconds == 0.0 || round.seconds < best.seconds)
            best = round;
    };
    // Builds: the best round, and the first (the cold build a render does once).
    double buildSeconds = 0.0, firstBuildSeconds = 0.0;
    std::unique_ptr<Accel> accel;
    // Closest hits twice: as Embree's rtcIntersect1 answers (t and primitive), which the
    // ratios compare, and with the full hit information the renderer uses.
    std::vector<Measurement> ours(sets.size()), full(sets.size());
#ifdef NORI_HAVE_EMBREE
    double embreeBuild = 0.0, embreeFirstBuild = 0.0;
    std::vector<Measurement> theirs(sets.size());
#endif
    for (int round = 0; round < rounds; ++round) {
        accel = std::make_unique<Accel>();
        accel->addShape(&mesh);
        const auto start = std::chrono::steady_clock::now();
        accel->build();
        const double seconds = secondsSince(start);
        buildSeconds = round == 0 ? seconds : std::min(buildSeconds, seconds);
        if (round == 0)
            firstBuildSeconds = seconds;
#ifdef NORI_HAVE_EMBREE
        double embreeSeconds = 0.0;
        EmbreeScene embree(mesh, threads, embreeSeconds);
        embreeBuild = round == 0 ? embreeSeconds : std::min(embreeBuild, embreeSeconds);
        if (round == 0)
            embreeFirstBuild = embreeSeconds;
#endif
        for (size_t i = 0; i < sets.size(); ++i) {
            keepBest(ours[i], traceAll(sets[i], [&](const Ray3f &ray, bool occlusion) {
                         if (occlusion) {
                             Intersection its;
                             return accel->rayIntersect(ray, its, true);
                         }
                         float t;
                         const Shape *shape;
                         uint32_t primIndex;
                         return accel->closestHit(ray, t, shape, primIndex);
                     }));
            if (!sets[i].occlusion)
                keepBest(full[i], traceAll(sets[i], [&](const Ray3f &ray, bool) {
                             Intersection its;
                             return accel->rayIntersect(ray, its, false);
                         }));
#ifdef NORI_HAVE_EMBREE
            keepBest(theirs[i], traceAll(sets[i], [&](const Ray3f &ray, bool occlusion) {
                         return embree.trace(ray, occlusion);
                     }));
#endif
        }
    }

    std::cout << fmt::format("{}build_s {:.4f}\n{}first_build_s {:.4f}\n", prefix, buildSeconds,
                             prefix, firstBuildSeconds);
    if (threads == 1)
        std::cout << fmt::format(
            "bvh_nodes {}\nbvh_leaves {}\nbvh_max_depth {}\nbvh_sah_cost {:.2f}\n"
            "bvh_mbytes {:.1f}\n",
            accel->statistics().nodes, accel->statistics().leaves, accel->statistics().maxDepth,
            accel->statistics().sahCost, accel->memoryBytes() * 1e-6);
    auto mrays = [](const RaySet &set, const Measurement &m) {
        return static_cast<double>(set.rays.size()) / m.seconds * 1e-6;
    };
    for (size_t i = 0; i < sets.size(); ++i) {
        std::cout << fmt::format("{}{}_mrays {:.3f}\n{}{}_hits {}\n", prefix, sets[i].name,
                                 mrays(sets[i], ours[i]), prefix, sets[i].name, ours[i].hits);
        if (!sets[i].occlusion)
            std::cout << fmt::format("{}{}_with_hit_info_mrays {:.3f}\n", prefix, sets[i].name,
                                     mrays(sets[i], full[i]));
    }
#ifdef NORI_HAVE_EMBREE
    std::cout << fmt::format("{0}embree_build_s {1:.4f}\n{0}build_ratio {2:.3f}\n"
                             "{0}embree_first_build_s {3:.4f}\n{0}first_build_ratio {4:.3f}\n",
                             prefix, embreeBuild, buildSeconds / embreeBuild, embreeFirstBuild,
                             firstBuildSeconds / embreeFirstBuild);
    for (size_t i = 0; i < sets.size(); ++i)
        std::cout << fmt::format(
            "{}embree_{}_mrays {:.3f}\n{}embree_{}_hits {}\n{}{}_ratio {:.3f}\n", prefix,
            sets[i].name, mrays(sets[i], theirs[i]), prefix, sets[i].name, theirs[i].hits, prefix,
            sets[i].name, theirs[i].seconds / ours[i].seconds);
#endif
}

/// What the command line gives.
struct Arguments {
    std::string meshFile;
    size_t rayCount = 1000000;
    int threads = static_cast<int>(std::thread::hardware_concurrency());
    int rounds = 3;
    std::vector<std::string> makeMesh; ///< --make-mesh TRIANGLES OUT.obj
};

int run(const Arguments &arguments) {
    if (!arguments.makeMesh.empty()) {
        const int triangles = toInt(arguments.makeMesh[0], "--make-mesh");
        if (triangles <= 0)
            throw NoriException("--make-mesh needs a positive number of triangles, got {}",
                                triangles);
        std::cout << "triangles "
                  << writeBumpySphere(static_cast<size_t>(triangles), arguments.makeMesh[1])
                  << "\n";
        return 0;
    }
    const std::string &meshFile = arguments.meshFile;
    const size_t rayCount = arguments.rayCount;
    const int threads = arguments.threads, rounds = arguments.rounds;
    if (meshFile.empty() || rayCount == 0 || threads <= 0 || rounds <= 0)
        throw NoriException("give a mesh and positive --rays, --threads and --rounds (see "
                            "nori-bench --help)");

    // First the check that the fast paths answer exactly as the reference does.
    const std::string smallMesh = fmt::format("/tmp/nori-bench-equality-{}.obj", getpid());
    writeBumpySphere(5000, smallMesh);
    const size_t mismatches = equalityCheck(smallMesh, 20000);
    std::remove(smallMesh.c_str());
    if (mismatches > 0)
        throw NoriException("{} rays differ from the brute-force reference", mismatches);

    std::shared_ptr<Mesh> mesh = loadMesh(meshFile);
    const std::vector<RaySet> sets = makeRaySets(rayCount);
    std::cout << "triangles " << mesh->getPrimitiveCount() << "\n";
    std::cout << "rays " << sets.back().rays.size() << "\n";
#ifndef NORI_HAVE_EMBREE
    std::cout << "embree not available (install libembree-dev and rebuild to compare)\n";
#endif
    // One thread, pinned to one core, then all threads.
    pinToCpu(static_cast<int>(std::thread::hardware_concurrency()) - 1);
    measure(*mesh, sets, 1, rounds, "t1_");
    pinToCpu(-1);
    if (threads > 1)
        measure(*mesh, sets, threads, rounds, fmt::format("t{}_", threads));
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    Arguments arguments;
    return runCommandLine(
        argc, argv, "nori-bench",
        "The BVH benchmark: checks the BVH against brute force, then measures its build and "
        "its throughput for primary, incoherent and shadow rays, on one pinned thread and on "
        "all (against Embree 3 in the same run when it is installed). Prints one `name value` "
        "per line.",
        [&](CLI::App &app) {
            app.add_option("mesh", arguments.meshFile, "the mesh to trace rays against")
                ->type_name("MESH.obj");
            app.add_option("--rays", arguments.rayCount, "rays per set (default 1000000)")
                ->type_name("N");
            app.add_option("--threads", arguments.threads,
                           "threads of the second run (default: all)")
                ->type_name("T");
            app.add_option("--rounds", arguments.rounds,
                           "rounds, of which the best counts (default 3)")
                ->type_name("R");
            app.add_option("--make-mesh", arguments.makeMesh,
                           "write a bumpy sphere of about TRIANGLES triangles to OUT.obj, and stop")
                ->type_name("TRIANGLES OUT.obj")
                ->expected(2);
        },
        [&](const CLI::App &) { return run(arguments); });
}
