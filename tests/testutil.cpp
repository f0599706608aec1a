#include "testutil.h"

#include <nori/camera.h>
#include <nori/integrator.h>
#include <nori/parser.h>
#include <nori/sampler.h>
#include <nori/testsamples.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <poll.h>
#include <random>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

namespace nori::testing {

TempDir::TempDir() {
    std::random_device device;
    m_path = std::filesystem::temp_directory_path() /
             fmt::format("nori-test-{}-{:08x}", getpid(), device());
    std::filesystem::create_directories(m_path);
}

TempDir::~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(m_path, ignored);
}

std::string TempDir::write(const std::string &relativeName, const std::string &content) const {
    std::filesystem::path file = m_path / relativeName;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << content;
    return file.string();
}

ProcessResult runNori(const std::vector<std::string> &arguments,
                      const std::string &interruptAfter) {
    return runCommand(NORI_EXECUTABLE, arguments, interruptAfter);
}

namespace {

/// Runs `executable`, collecting what it prints; sends SIGINT once `interruptAfter`
/// appears, and SIGKILL once `killAfterSeconds` (when not negative) have passed.
ProcessResult runProcess(const std::string &executable, const std::vector<std::string> &arguments,
                         const std::string &interruptAfter, double killAfterSeconds) {
    int pipeEnds[2];
    if (pipe(pipeEnds) != 0)
        throw NoriException("pipe() failed");
    pid_t pid = fork();
    if (pid < 0)
        throw NoriException("fork() failed");
    if (pid == 0) {
        dup2(pipeEnds[1], STDOUT_FILENO);
        dup2(pipeEnds[1], STDERR_FILENO);
        close(pipeEnds[0]);
        close(pipeEnds[1]);
        std::vector<char *> argv;
        std::string program = executable;
        argv.push_back(program.data());
        std::vector<std::string> copies(arguments);
        for (std::string &argument : copies)
            argv.push_back(argument.data());
        argv.push_back(nullptr);
        execv(program.c_str(), argv.data());
        _exit(127);
    }
    close(pipeEnds[1]);

    const auto start = std::chrono::steady_clock::now();
    ProcessResult result;
    bool interrupted = false, killed = false;
    char buffer[4096];
    for (;;) {
        int timeout = -1;
        if (killAfterSeconds >= 0.0 && !killed) {
            const double left =
                killAfterSeconds -
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (left <= 0.0) {
                kill(pid, SIGKILL);
                killed = true;
            } else {
                timeout = static_cast<int>(std::ceil(left * 1000.0));
            }
        }
        pollfd descriptor{pipeEnds[0], POLLIN, 0};
        const int ready = poll(&descriptor, 1, timeout);
        if (ready < 0 && errno == EINTR)
            continue;
        if (ready == 0)
            continue; // the deadline: killed above on the next turn
        const ssize_t count = read(pipeEnds[0], buffer, sizeof(buffer));
        if (count <= 0)
            break;
        result.output.append(buffer, static_cast<size_t>(count));
        if (!interrupted && !interruptAfter.empty() &&
            result.output.find(interruptAfter) != std::string::npos) {
            kill(pid, SIGINT);
            interrupted = true;
        }
    }
    close(pipeEnds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return result;
}

} // namespace

ProcessResult runCommand(const std::string &executable, const std::vector<std::string> &arguments,
                         const std::string &interruptAfter) {
    return runProcess(executable, arguments, interruptAfter, -1.0);
}

ProcessResult runNoriKilledAfter(const std::vector<std::string> &arguments, double seconds) {
    return runProcess(NORI_EXECUTABLE, arguments, "", seconds);
}

std::shared_ptr<Scene> litFloor(const std::string &integrator, const std::string &content) {
    auto scene = std::dynamic_pointer_cast<Scene>(
        loadFromXMLString(fmt::format(R"(<scene> <integrator type="{}"/>
            <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
            <camera type="perspective"><float name="fov" value="0.001"/>
                <integer name="width" value="1"/> <integer name="height" value="1"/>
                <transform name="toWorld"><lookat origin="0.3, 2, 1" target="0, 0, 0" up="0, 1, 0"/></transform>
            </camera>
            <mesh type="obj"><string name="filename" value="floor.obj"/>
                <transform name="toWorld"><scale value="1000"/></transform>
                <bsdf type="diffuse"><color name="albedo" value="0.5"/></bsdf></mesh> {}</scene>)",
                                      integrator, content),
                          std::string(NORI_SOURCE_DIR) + "/scenes/textured/meshes"));
    if (!scene)
        throw NoriException("litFloor: not a scene");
    return scene;
}

std::string gzip(const std::string &bytes) {
    z_stream stream{};
    if (deflateInit2(&stream, Z_BEST_SPEED, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        throw NoriException("gzip: zlib would not start");
    std::string output(deflateBound(&stream, bytes.size()) + 64, '\0');
    stream.next_in = reinterpret_cast<Bytef *>(const_cast<char *>(bytes.data()));
    stream.avail_in = static_cast<uInt>(bytes.size());
    stream.next_out = reinterpret_cast<Bytef *>(output.data());
    stream.avail_out = static_cast<uInt>(output.size());
    const int status = deflate(&stream, Z_FINISH);
    deflateEnd(&stream);
    if (status != Z_STREAM_END)
        throw NoriException("gzip: zlib could not compress {} bytes", bytes.size());
    output.resize(stream.total_out);
    return output;
}

std::shared_ptr<Scene> loadScene(const std::string &xml, const std::string &directory) {
    auto scene = std::dynamic_pointer_cast<Scene>(loadFromXMLString(xml, directory));
    if (!scene)
        throw NoriException("loadScene: the XML is not a scene");
    return scene;
}

ChiSquareReport chiSquare(const SamplingRoutine &routine, uint64_t seed, double level) {
    ChiSquareOptions options;
    options.sampleCount = 300000;
    options.seed = seed;
    options.significanceLevel = level;
    return runChiSquareTest(routine, options);
}

bool identicalImages(const Bitmap &a, const Bitmap &b) {
    if (a.width() != b.width() || a.height() != b.height())
        return false;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            if (!(a(y, x) == b(y, x)).all())
                return false;
    return true;
}

RenderOptions quietOptions(int threads) {
    RenderOptions options;
    options.threads = threads;
    return options;
}

RunningMoments estimatePixel(Scene &scene, size_t count) {
    scene.getIntegrator()->preprocess(&scene);
    std::unique_ptr<Sampler> sampler = scene.getSampler()->clone();
    const Vector2i size = scene.getCamera()->getOutputSize();
    RunningMoments moments;
    const size_t samples = scaledTestSamples(count);
    for (size_t i = 0; i < samples; ++i) {
        sampler->generate(Point2i(static_cast<int>(i % 4096), static_cast<int>(i / 4096)));
        const Point2f film = sampler->next2D();
        Ray3f ray;
        Color3f value = scene.sampleCameraRay(
            ray, Point2f(film.x() * size.x(), film.y() * size.y()), sampler->next2D());
        value *= scene.getIntegrator()->Li(&scene, sampler.get(), ray);
        moments.add(value.getLuminance());
    }
    return moments;
}

PixelTTest tTestPixel(Scene &scene, double reference, size_t samples) {
    PixelTTest test;
    test.moments = estimatePixel(scene, samples);
    test.reference = reference;
    test.result = studentTTest(test.moments.mean, test.moments.variance(), test.moments.count,
                               reference, 0.01);
    return test;
}

std::string PixelTTest::summary() const {
    return fmt::format("estimate {} (variance {}), reference {}, t = {}", moments.mean,
                       moments.variance(), reference, result.t);
}

VariantAgreement compareVariant(const AgreementScene &reference, const AgreementScene &variant,
                                const AgreementScene &control, const AgreementSettings &settings) {
    const auto referenceRegions =
        estimateRegions(reference, reference.estimators.at(0), 0, settings);
    const auto variantRegions = estimateRegions(variant, variant.estimators.at(0), 1, settings);
    const auto controlRegions = estimateRegions(control, control.estimators.at(0), 2, settings);
    VariantAgreement result;
    for (size_t region = 0; region < referenceRegions.size(); ++region) {
        result.variant.push_back(
            compareEstimates(variantRegions.at(region), referenceRegions[region], settings));
        result.control.push_back(
            compareEstimates(controlRegions.at(region), referenceRegions[region], settings));
    }
    return result;
}

std::string VariantAgreement::summary(size_t region) const {
    return fmt::format("variant: {} SE; control: {} SE; detectable bias (%): {}",
                       variant.at(region).z, control.at(region).z,
                       100 * variant.at(region).detectableBias);
}

bool samplesAgree(const RunningMoments &a, const RunningMoments &b, double &t) {
    const double standardError =
        std::sqrt(a.variance() / double(a.count) + b.variance() / double(b.count));
    t = (a.mean - b.mean) / standardError;
    const double degrees = double(std::min(a.count, b.count) - 1);
    return 2.0 * (1.0 - studentTCdf(std::abs(t), degrees)) > 0.01;
}

} // namespace nori::testing
