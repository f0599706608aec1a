#include "recorder.h"

namespace nori::testing {

Recorder::Recorder(const PropertyList &props) {
    pass = props.getBoolean("pass", true);
    flag = props.getBoolean("flag", false);
    count = props.getInteger("count", 0);
    alpha = props.getFloat("alpha", 0.0f);
    label = props.getString("label", "");
    filename = props.has("filename") ? props.getPath("filename") : "";
    albedo = props.getColor("albedo", Color3f(0.0f));
    position = props.getPoint("position", Point3f(0.0f));
    uv = props.getPoint2("uv", Point2f(0.0f));
    direction = props.getVector("direction", Vector3f(0.0f));
    offset = props.getVector2("offset", Vector2f(0.0f));
    toWorld = props.getTransform("toWorld", Transform());
}

void Recorder::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    children.emplace_back(name, child);
}

NORI_REGISTER_CLASS(Recorder, "recorder");

} // namespace nori::testing
