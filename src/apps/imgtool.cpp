// nori-imgtool: operations on rendered images. Its one command so far, `denoise`, runs
// the built-in denoiser on a multi-layer EXR written by `nori --aovs ...`.
#include <nori/denoiser.h>
#include <nori/program.h>
#include <nori/strutil.h>

#include <filesystem>
#include <iostream>

using namespace nori;

namespace {

const char *kUsage = R"(Usage: nori-imgtool <command> [options]

Commands:
  denoise IN.exr [-o OUT] [--threads N]
      Denoises the beauty of IN.exr, a render with the layers albedo, normal, depth and
      variance (nori --denoise, or nori --aovs albedo,normal,depth,variance), and writes
      OUT.exr and OUT.png (default OUT: IN_denoised beside IN). IN is left as it is.
)";

int denoiseCommand(const std::vector<std::string> &arguments) {
    std::string input, output;
    DenoiserSettings settings;
    for (size_t i = 0; i < arguments.size(); ++i) {
        const std::string &arg = arguments[i];
        auto value = [&]() -> const std::string & {
            if (i + 1 >= arguments.size())
                throw NoriException("denoise: option {} needs a value", arg);
            return arguments[++i];
        };
        if (arg == "-o" || arg == "--output") {
            output = value();
        } else if (arg == "-t" || arg == "--threads") {
            settings.threads = toInt(value(), arg);
            if (settings.threads <= 0)
                throw NoriException("denoise: {} must be a positive integer", arg);
        } else if (!arg.empty() && arg[0] == '-') {
            throw NoriException("denoise: unknown option '{}'", arg);
        } else if (input.empty()) {
            input = arg;
        } else {
            throw NoriException("denoise: more than one input ('{}' and '{}')", input, arg);
        }
    }
    if (input.empty())
        throw NoriException("denoise: no input file (see nori-imgtool --help)");
    std::filesystem::path stem(output.empty() ? input : output);
    const std::string extension = toLower(stem.extension().string());
    if (extension == ".exr" || extension == ".png")
        stem.replace_extension();
    if (output.empty())
        stem += "_denoised";

    const LayeredImage image = LayeredImage::loadEXR(input);
    Bitmap denoised;
    try {
        denoised = denoise(image, settings);
    } catch (const NoriException &error) {
        throw NoriException("{}: {}", input, error.what());
    }
    denoised.saveEXR(stem.string() + ".exr");
    denoised.savePNG(stem.string() + ".png");
    fmt::print("wrote {}.exr and {}.png\n", stem.string(), stem.string());
    return 0;
}

int run(int argc, char **argv) {
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    if (arguments.empty()) {
        fmt::print(stderr, "{}", kUsage);
        return 1;
    }
    const std::string &command = arguments[0];
    if (command == "-h" || command == "--help") {
        fmt::print("{}", kUsage);
        return 0;
    }
    if (command == "denoise")
        return denoiseCommand({arguments.begin() + 1, arguments.end()});
    throw NoriException("unknown command '{}' (see nori-imgtool --help)", command);
}

} // namespace

int main(int argc, char **argv) {
    return runProgram([&] { return run(argc, argv); });
}
