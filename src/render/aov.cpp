#include <nori/aov.h>
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/pathtracing.h>
#include <nori/pcg32.h>
#include <nori/raydifferential.h>
#include <nori/scene.h>
#include <nori/strutil.h>

#include <algorithm>
#include <array>

namespace nori {

namespace {

struct AOVInfo {
    AOV aov;
    const char *name;
    std::vector<std::string> channels;
};

const std::array<AOVInfo, 7> &aovTable() {
    static const std::array<AOVInfo, 7> table = {{
        {AOV::Albedo, "albedo", {"R", "G", "B"}},
        {AOV::Normal, "normal", {"X", "Y", "Z"}},
        {AOV::Depth, "depth", {"Z"}},
        {AOV::Position, "position", {"X", "Y", "Z"}},
        {AOV::SampleCount, "sampleCount", {"Y"}},
        {AOV::Variance, "variance", {"R", "G", "B"}},
        {AOV::Emission, "emission", {"R", "G", "B"}},
    }};
    return table;
}

const AOVInfo &infoOf(AOV aov) {
    return aovTable()[static_cast<size_t>(aov)];
}

/// Specular bounces followed before giving up on finding a non-specular surface.
constexpr int kMaxSpecularBounces = 8;

} // namespace

const char *aovName(AOV aov) {
    return infoOf(aov).name;
}

const std::vector<std::string> &aovChannels(AOV aov) {
    return infoOf(aov).channels;
}

std::vector<AOV> parseAOVList(const std::string &list, const std::string &where) {
    std::vector<AOV> aovs;
    for (const std::string &entry : tokenize(list)) {
        const auto &table = aovTable();
        const auto found = std::find_if(table.begin(), table.end(),
                                        [&](const AOVInfo &info) { return entry == info.name; });
        if (found == table.end()) {
            std::vector<std::string> names;
            names.reserve(table.size());
            for (const AOVInfo &info : table)
                names.push_back(info.name);
            std::string hint = didYouMean(entry, names);
            if (hint.empty())
                hint = fmt::format(" (known AOVs: {})", fmt::join(names, ", "));
            throw NoriException("{}: unknown AOV '{}'{}", where, entry, hint);
        }
        if (std::find(aovs.begin(), aovs.end(), found->aov) == aovs.end())
            aovs.push_back(found->aov);
    }
    return aovs;
}

SurfaceAOVs traceSurfaceAOVs(const Scene &scene, const Ray3f &cameraRay, uint64_t seed) {
    SurfaceAOVs result;
    PCG32 random(seed, 0x5a0f);
    Ray3f ray = cameraRay;
    for (int bounce = 0; bounce <= kMaxSpecularBounces; ++bounce) {
        Intersection its;
        if (!scene.rayIntersect(ray, its)) {
            if (bounce == 0)
                result.emission = lightAtInfinity(scene, cameraRay);
            break;
        }
        if (bounce == 0) {
            result.depth = (its.p - cameraRay.o).norm();
            result.position = its.p;
            if (const Emitter *emitter = its.shape->getEmitter())
                result.emission = emitter->eval(EmitterQueryRecord(cameraRay.o, its));
        }
        const BSDF *bsdf = its.shape->getBSDF();
        BSDFQueryRecord bRec(its, its.toLocal(-ray.d));
        if (bsdf->isDiffuse()) {
            result.albedo = bsdf->albedo(bRec);
            result.normal = its.shFrame.n;
            break;
        }
        // Smooth glass follows its more probable lobe (through it, mostly), so that the
        // features behind glass are those of one surface, not a noisy mix of the reflected
        // and the refracted one (Intel Open Image Denoise's guidance for its albedo);
        // other specular BSDFs are sampled.
        DiscreteLobe lobes[BSDF::kMaxDiscreteLobes];
        const int lobeCount = bsdf->discreteLobes(bRec, lobes);
        if (lobeCount > 0) {
            const DiscreteLobe *likeliest = std::max_element(
                lobes, lobes + lobeCount, [](const DiscreteLobe &a, const DiscreteLobe &b) {
                    return a.probability < b.probability;
                });
            if (!(likeliest->probability > 0.0f))
                break;
            bRec.wo = likeliest->wo;
            bRec.eta = likeliest->eta;
            bRec.measure = EDiscrete;
        } else {
            const float u = random.nextFloat();
            if ((bsdf->sample(bRec, Point2f(u, random.nextFloat())) == 0.0f).all())
                break;
        }
        ray = spawnScatteredRay(its, ray, bRec);
    }
    return result;
}

} // namespace nori
