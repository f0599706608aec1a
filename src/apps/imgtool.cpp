// nori-imgtool: operations on rendered images: `denoise` runs the built-in denoiser on a
// multi-layer EXR written by `nori --aovs ...`; `diff` compares a render with a reference.
#include <nori/denoiser.h>
#include <nori/layeredimage.h>
#include <nori/program.h>
#include <nori/strutil.h>

#include <cmath>
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

  diff IMAGE REFERENCE [--layer NAME] [--crop X,Y,W,H] [--tolerance T] [--metric M]
       [--out ERROR.png]
      Compares IMAGE with REFERENCE (EXR, PFM, HDR, PNG, JPEG; of one size) and prints
      one `key value` per line: rmse, relmse (Σ(a−b)²/(b²+0.01), per channel), maxabs,
      psnr (dB, the peak being REFERENCE's largest value or 1), pixels, differing (pixels
      not equal). --layer compares an AOV layer of two EXRs (default: the beauty);
      --crop only the W×H pixels from column X, row Y (a region of interest).
      --out writes the per-pixel absolute error in false colour (black, red, yellow,
      white up to the largest error). With --tolerance, exits 1 when the metric M (rmse,
      relmse or maxabs; default relmse) exceeds T.
)";

/// Reads a command's arguments in order; an option's value is the argument after it.
class ArgumentReader {
public:
    ArgumentReader(const std::vector<std::string> &arguments, std::string command)
        : m_arguments(arguments), m_command(std::move(command)) {}
    bool more() const { return m_next < m_arguments.size(); }
    const std::string &next() { return m_arguments[m_next++]; }
    /// The value after option `flag`; throws naming it when there is none.
    const std::string &valueOf(const std::string &flag) {
        if (!more())
            throw NoriException("{}: option {} needs a value", m_command, flag);
        return next();
    }

private:
    const std::vector<std::string> &m_arguments;
    std::string m_command;
    size_t m_next = 0;
};

int denoiseCommand(const std::vector<std::string> &arguments) {
    std::string input, output;
    DenoiserSettings settings;
    for (ArgumentReader reader(arguments, "denoise"); reader.more();) {
        const std::string arg = reader.next();
        const auto value = [&] { return reader.valueOf(arg); };
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

/// An image to compare: an EXR's layer, or any image file's pixels.
Bitmap loadForDiff(const std::string &file, const std::string &layer) {
    const std::string extension = toLower(std::filesystem::path(file).extension().string());
    if (extension == ".exr") {
        const LayeredImage image = LayeredImage::loadEXR(file);
        try {
            return image.layer(layer);
        } catch (const NoriException &error) {
            throw NoriException("{}: {}", file, error.what());
        }
    }
    if (!layer.empty())
        throw NoriException("diff: --layer needs EXR files; {} is not one", file);
    return Bitmap::load(file);
}

/// The W×H pixels of `image` from column X, row Y, given as "X,Y,W,H".
Bitmap cropForDiff(const Bitmap &image, const std::string &crop) {
    const std::vector<std::string> fields = tokenize(crop, ",");
    if (fields.size() != 4)
        throw NoriException("diff: --crop expects X,Y,W,H, got '{}'", crop);
    const int x = toInt(fields[0], "--crop X"), y = toInt(fields[1], "--crop Y"),
              w = toInt(fields[2], "--crop W"), h = toInt(fields[3], "--crop H");
    if (x < 0 || y < 0 || w <= 0 || h <= 0 || x > image.width() - w || y > image.height() - h)
        throw NoriException("diff: --crop {} does not fit in the {}x{} images", crop, image.width(),
                            image.height());
    Bitmap region(Eigen::Vector2i(w, h));
    region.Bitmap::Base::operator=(image.block(y, x, h, w));
    return region;
}

/// The false-colour ramp black → red → yellow → white over t in [0, 1].
Color3f falseColor(float t) {
    t = std::clamp(t, 0.0f, 1.0f) * 3.0f;
    return Color3f(std::min(t, 1.0f), std::clamp(t - 1.0f, 0.0f, 1.0f),
                   std::clamp(t - 2.0f, 0.0f, 1.0f));
}

int diffCommand(const std::vector<std::string> &arguments) {
    std::vector<std::string> files;
    std::string layer, errorImage, metric = "relmse", crop;
    double tolerance = -1.0;
    for (ArgumentReader reader(arguments, "diff"); reader.more();) {
        const std::string arg = reader.next();
        const auto value = [&] { return reader.valueOf(arg); };
        if (arg == "--layer") {
            layer = value();
        } else if (arg == "--crop") {
            crop = value();
        } else if (arg == "--out") {
            errorImage = value();
        } else if (arg == "--metric") {
            metric = value();
            if (metric != "rmse" && metric != "relmse" && metric != "maxabs")
                throw NoriException("diff: --metric must be rmse, relmse or maxabs, got '{}'",
                                    metric);
        } else if (arg == "--tolerance") {
            tolerance = toFloat(value(), arg);
            if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
                throw NoriException("diff: --tolerance must be a non-negative number");
        } else if (!arg.empty() && arg[0] == '-') {
            throw NoriException("diff: unknown option '{}'", arg);
        } else {
            files.push_back(arg);
        }
    }
    if (files.size() != 2)
        throw NoriException("diff: expects two images, IMAGE and REFERENCE (got {})", files.size());
    Bitmap image = loadForDiff(files[0], layer), reference = loadForDiff(files[1], layer);
    if (image.rows() != reference.rows() || image.cols() != reference.cols())
        throw NoriException("diff: {} is {}x{} but {} is {}x{}", files[0], image.cols(),
                            image.rows(), files[1], reference.cols(), reference.rows());
    if (!crop.empty()) {
        image = cropForDiff(image, crop);
        reference = cropForDiff(reference, crop);
    }

    double maxAbs = 0.0, peak = 1.0;
    size_t differing = 0;
    Eigen::ArrayXXf pixelError(image.rows(), image.cols());
    for (Eigen::Index y = 0; y < image.rows(); ++y)
        for (Eigen::Index x = 0; x < image.cols(); ++x) {
            const Color3f difference = (image(y, x) - reference(y, x)).abs();
            maxAbs = std::max(maxAbs, double(difference.maxCoeff()));
            peak = std::max(peak, double(reference(y, x).maxCoeff()));
            differing += (difference > 0.0f).any() || image(y, x).hasNaN() ? 1 : 0;
            pixelError(y, x) = difference.mean();
        }
    const double mse = meanSquaredError(image, reference);
    const double relmse = relativeMeanSquaredError(image, reference);
    const double psnr = 10.0 * std::log10(peak * peak / mse); // +inf when equal
    fmt::print("rmse {:.9g}\nrelmse {:.9g}\nmaxabs {:.9g}\npsnr {:.6g}\npixels {}\ndiffering {}\n",
               std::sqrt(mse), relmse, maxAbs, psnr, image.size(), differing);
    if (!errorImage.empty()) {
        Bitmap colors(Eigen::Vector2i(int(image.cols()), int(image.rows())));
        const float largest = pixelError.maxCoeff();
        for (Eigen::Index y = 0; y < image.rows(); ++y)
            for (Eigen::Index x = 0; x < image.cols(); ++x)
                // The ramp is in display values: stored linear, so that savePNG's sRGB
                // encoding gives it back.
                colors(y, x) =
                    falseColor(largest > 0.0f ? pixelError(y, x) / largest : 0.0f).toLinearRGB();
        colors.savePNG(errorImage);
    }
    if (tolerance >= 0.0) {
        const double measured = metric == "rmse"     ? std::sqrt(mse)
                                : metric == "maxabs" ? maxAbs
                                                     : relmse;
        if (!(measured <= tolerance)) {
            fmt::print("over tolerance: {} {:.9g} > {:g}\n", metric, measured, tolerance);
            return 1;
        }
    }
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
    if (command == "diff")
        return diffCommand({arguments.begin() + 1, arguments.end()});
    throw NoriException("unknown command '{}' (see nori-imgtool --help)", command);
}

} // namespace

int main(int argc, char **argv) {
    return runProgram([&] { return run(argc, argv); });
}
