// A test-only plugin ("recorder", a <test>) that reads one property of every type and
// keeps every child with its name, so parser tests can see what reached a plugin.
#pragma once

#include <nori/test.h>
#include <nori/transform.h>

#include <vector>

namespace nori::testing {

class Recorder : public Test {
public:
    explicit Recorder(const PropertyList &props);

    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    void activate() override { ++activations; }
    bool run(const TestOptions &) override { return pass; }
    std::string toString() const override { return "Recorder[]"; }

    bool pass;
    bool flag;
    int count;
    float alpha;
    std::string label, filename;
    Color3f albedo;
    Point3f position;
    Point2f uv;
    Vector3f direction;
    Vector2f offset;
    Transform toWorld;
    int activations = 0;
    std::vector<std::pair<std::string, std::shared_ptr<NoriObject>>> children;
};

} // namespace nori::testing
