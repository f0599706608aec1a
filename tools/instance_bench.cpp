// nori-bench-instances: the figures of instancing. A shape group holding one mesh is
// placed N times (random rotations and translations) in a scene built through the
// object factory, as the XML parser builds it; for each N it prints the scene build time
// (creating the instances, adding them, building the two-level BVH) and the memory per
// instance: the growth of the bytes allocated through operator new (counted by the
// replacements below) once the scene is built, when the instance objects (what reading
// the XML costs) are freed, and the acceleration structure's own count of its bytes.
//
//   nori-bench --make-mesh 10000 mesh.obj
//   nori-bench-instances mesh.obj [N ...]        (default: 10000 100000 1000000)
#include "app/cli.h"
#include <nori/instance.h>
#include <nori/pcg32.h>
#include <nori/scene.h>
#include <nori/strutil.h>

#include <malloc.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <new>

using namespace nori;

namespace {

/// Bytes allocated through operator new and not yet freed (malloc_usable_size of each
/// block: what the allocator really holds for it).
std::atomic<size_t> g_liveBytes{0};

void *countedAllocation(void *block) {
    if (!block)
        throw std::bad_alloc();
    g_liveBytes += malloc_usable_size(block);
    return block;
}

void countedFree(void *block) {
    if (block)
        g_liveBytes -= malloc_usable_size(block);
    std::free(block);
}

} // namespace

void *operator new(size_t size) {
    return countedAllocation(std::malloc(size));
}
void *operator new[](size_t size) {
    return countedAllocation(std::malloc(size));
}
void *operator new(size_t size, std::align_val_t alignment) {
    return countedAllocation(std::aligned_alloc(static_cast<size_t>(alignment),
                                                (size + static_cast<size_t>(alignment) - 1) &
                                                    ~(static_cast<size_t>(alignment) - 1)));
}
void operator delete(void *block) noexcept {
    countedFree(block);
}
void operator delete[](void *block) noexcept {
    countedFree(block);
}
void operator delete(void *block, size_t) noexcept {
    countedFree(block);
}
void operator delete[](void *block, size_t) noexcept {
    countedFree(block);
}
void operator delete(void *block, std::align_val_t) noexcept {
    countedFree(block);
}
void operator delete(void *block, size_t, std::align_val_t) noexcept {
    countedFree(block);
}

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

size_t heapBytes() {
    return g_liveBytes.load();
}

std::shared_ptr<NoriObject> create(const std::string &name, NoriObject::EClassType type,
                                   const PropertyList &props = {}) {
    return NoriObjectFactory::createInstance(name, type, props);
}

/// The group of one mesh, activated.
std::shared_ptr<ShapeGroup> makeGroup(const std::string &meshFile) {
    PropertyList meshProps;
    meshProps.setString("filename", meshFile);
    auto mesh = create("obj", NoriObject::EMesh, meshProps);
    mesh->activate();
    auto group = std::static_pointer_cast<ShapeGroup>(create("shapegroup", NoriObject::EMesh));
    group->addChild(mesh, "");
    group->activate();
    return group;
}

void measure(const std::shared_ptr<ShapeGroup> &group, size_t count) {
    auto scene = std::static_pointer_cast<Scene>(create("scene", NoriObject::EScene));
    scene->addChild(create("normals", NoriObject::EIntegrator), "");
    scene->addChild(create("perspective", NoriObject::ECamera), "");
    scene->addChild(create("independent", NoriObject::ESampler), "");
    PCG32 random(7, count);
    // Instances spread over a cube whose side grows with N, so density stays alike.
    const float side = 4.0f * std::cbrt(static_cast<float>(count));
    const size_t before = heapBytes();
    const auto start = std::chrono::steady_clock::now();
    for (size_t i = 0; i < count; ++i) {
        PropertyList props;
        const Vector3f axis(2.0f * random.nextFloat() - 1.0f, 2.0f * random.nextFloat() - 1.0f,
                            2.0f * random.nextFloat() - 1.0f);
        const Transform toWorld =
            Transform::translate(
                side * Vector3f(random.nextFloat(), random.nextFloat(), random.nextFloat())) *
            Transform::rotate(axis.norm() > 0.0f ? axis : Vector3f(0, 1, 0),
                              360.0f * random.nextFloat());
        props.setTransform("toWorld", toWorld);
        auto instance = create("instance", NoriObject::EMesh, props);
        instance->addChild(group, "");
        instance->activate();
        scene->addChild(instance, "");
    }
    const double createSeconds = secondsSince(start);
    const auto buildStart = std::chrono::steady_clock::now();
    scene->activate();
    const double buildSeconds = secondsSince(buildStart);
    const size_t after = heapBytes();
    const Accel &accel = *scene->getAccel();
    std::cout << fmt::format(
        "{:>8} instances: build {:.3f} s (creating and adding them {:.3f} s, two-level BVH "
        "{:.3f} s); heap {:.1f} bytes/instance, acceleration structure {:.1f} "
        "bytes/instance ({} top-level nodes)\n",
        count, createSeconds + buildSeconds, createSeconds, buildSeconds,
        static_cast<double>(after - before) / count,
        static_cast<double>(accel.memoryBytes()) / count, accel.instanceStatistics().nodes);
}

int run(const std::string &meshFile, std::vector<size_t> counts) {
    if (counts.empty())
        counts = {10000, 100000, 1000000};
    const auto start = std::chrono::steady_clock::now();
    auto group = makeGroup(meshFile);
    std::cout << fmt::format("mesh {}: {} triangles, loaded and its BVH built in {:.3f} s\n",
                             meshFile, group->target()->accel->statistics().primitives,
                             secondsSince(start));
    for (size_t count : counts)
        measure(group, count);
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    std::string meshFile;
    std::vector<size_t> counts;
    return runCommandLine(
        argc, argv, "nori-bench-instances",
        "The figures of instancing: places a mesh N times with random rotations and "
        "translations, as the parser does, and prints the build time and the bytes each "
        "instance costs.",
        [&](CLI::App &app) {
            app.add_option("mesh", meshFile, "the mesh to instance")
                ->type_name("MESH.obj")
                ->required();
            app.add_option("counts", counts, "instance counts (default 10000 100000 1000000)")
                ->type_name("N")
                ->check(CLI::PositiveNumber);
        },
        [&](const CLI::App &) { return run(meshFile, counts); });
}
