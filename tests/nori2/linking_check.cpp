// How course files link with the renderer (tests/nori2/plugins):
// - our plugin classes have internal linkage, so a course file's class of the same name
//   (Diffuse in diffuse.cpp) is another class, not a silent merge of the two (an ODR
//   clash would give both plugins one vtable);
// - the course's warp.cpp replaces our versions of the warps it defines (ours are weak
//   symbols), as Nori 2's warp assignment expects: its disk warp is the concentric map.
// Exits 1 when either does not hold.
#include <nori/bsdf.h>
#include <nori/warp.h>

#include <iostream>

int main() {
    using namespace nori;
    NoriObjectFactory::checkRegistry();
    const std::string ours =
        NoriObjectFactory::createInstance("diffuse", NoriObject::EBSDF, PropertyList())->toString();
    const std::string theirs =
        NoriObjectFactory::createInstance("nori2_diffuse", NoriObject::EBSDF, PropertyList())
            ->toString();
    std::cout << "diffuse: " << ours << "\nnori2_diffuse: " << theirs << "\n";
    const bool separate =
        ours.rfind("Diffuse[albedo=", 0) == 0 && theirs.find("\n  albedo = ") != std::string::npos;
    std::cout << (separate ? "two classes named Diffuse, kept apart\n"
                           : "the two classes named Diffuse were merged\n");

    // (0.75, 0.5): the polar map gives r = √0.75 at φ = π, the concentric map r = 0.5 at φ = 0.
    const Point2f disk = Warp::squareToUniformDisk(Point2f(0.75f, 0.5f));
    const bool replaced = std::abs(disk.x() - 0.5f) < 1e-6f && std::abs(disk.y()) < 1e-6f;
    std::cout << "Warp::squareToUniformDisk(0.75, 0.5) = " << disk.toString() << ": "
              << (replaced ? "the course's warp" : "not the course's warp") << "\n";
    return separate && replaced ? 0 : 1;
}
