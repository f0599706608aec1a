// The scene the checkpoint fuzz target resumes, and that its seed corpus is rendered from
// (make_checkpoint_corpus.cpp): 6 × 4 pixels with the AOV layers and per-pixel statistics
// a film keeps, so that a checkpoint's state holds every kind of block data.
#pragma once

#include <nori/aov.h>

#include <vector>

namespace nori::fuzz {

inline const char *kCheckpointScene = R"(<scene>
    <integrator type="path_mis"/>
    <sampler type="independent"><integer name="sampleCount" value="8"/></sampler>
    <camera type="perspective">
        <float name="fov" value="40"/>
        <integer name="width" value="6"/> <integer name="height" value="4"/>
        <transform name="toWorld"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <rfilter type="box"/>
    </camera>
    <mesh type="sphere"><float name="radius" value="1"/><bsdf type="diffuse"/></mesh>
    <emitter type="point"><point name="position" value="2, 3, 4"/><color name="intensity" value="20"/></emitter>
</scene>)";

/// The AOVs the scene is rendered with.
inline std::vector<AOV> checkpointAOVs() {
    return {AOV::Albedo, AOV::Variance, AOV::SampleCount};
}

} // namespace nori::fuzz
