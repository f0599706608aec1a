// The albedo table of BSDFs: ∫ f(wi, wo) |cos θo| dωo for wi at a few angles, each the
// mean weight of 10⁶ samples with its standard error (fixed seed), for the figures of
// docs/materials.md. Usage: nori-bsdf-albedo ['<bsdf .../>' ...]; without arguments, the
// plastics and coated diffuse BSDFs of issue 72 (their defaults and a few more).
#include <nori/bsdf.h>
#include <nori/parser.h>
#include <nori/pcg32.h>

#include <cmath>
#include <iostream>
#include <vector>

using namespace nori;

int main(int argc, char **argv) {
    std::vector<std::string> bsdfs;
    for (int i = 1; i < argc; ++i)
        bsdfs.emplace_back(argv[i]);
    if (bsdfs.empty())
        bsdfs = {
            R"(<bsdf type="plastic"/>)",
            R"(<bsdf type="plastic"><boolean name="nonlinear" value="true"/></bsdf>)",
            R"(<bsdf type="roughplastic"/>)",
            R"(<bsdf type="roughplastic"><float name="alpha" value="0.4"/></bsdf>)",
            R"(<bsdf type="roughplastic"><string name="distribution" value="ggx"/>
                <float name="alpha" value="0.4"/></bsdf>)",
            R"(<bsdf type="coateddiffuse"/>)",
            R"(<bsdf type="coateddiffuse"><float name="roughness" value="0.1"/></bsdf>)",
            R"(<bsdf type="coateddiffuse"><float name="roughness" value="0.1"/>
                <color name="albedo" value="0.8"/><float name="thickness" value="0.1"/></bsdf>)",
        };
    constexpr int kSamples = 1000000;
    const float angles[] = {0.0f, 45.0f, 80.0f};
    std::cout << "| BSDF | 0° | 45° | 80° |\n| --- | --- | --- | --- |\n";
    try {
        for (const std::string &xml : bsdfs) {
            const auto bsdf = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(xml));
            if (!bsdf)
                throw NoriException("not a <bsdf>: {}", xml);
            std::cout << "| " << bsdf->toString() << " |";
            for (const float degrees : angles) {
                const float theta = degrees * kPi / 180.0f;
                const Vector3f wi(std::sin(theta), 0.0f, std::cos(theta));
                PCG32 random(7, 1);
                double sum = 0.0, sum2 = 0.0;
                for (int i = 0; i < kSamples; ++i) {
                    BSDFQueryRecord bRec(wi);
                    const float u = random.nextFloat();
                    const double value =
                        bsdf->sample(bRec, Point2f(u, random.nextFloat())).getLuminance();
                    sum += value;
                    sum2 += value * value;
                }
                const double mean = sum / kSamples;
                const double error =
                    std::sqrt(std::max(0.0, sum2 / kSamples - mean * mean) / kSamples);
                std::cout << fmt::format(" {:.4f} ± {:.4f} |", mean, error);
            }
            std::cout << "\n";
        }
    } catch (const NoriException &error) {
        std::cerr << "Error: " << error.what() << "\n";
        return 1;
    }
    return 0;
}
