// nori-imgtool: operations on rendered images: `denoise` runs the built-in denoiser on a
// multi-layer EXR written by `nori --aovs ...`; `diff` compares a render with a reference;
// `convert` changes an image's format; `info` prints its size, layers and statistics.
#include <nori/denoiser.h>
#include <nori/imagefile.h>
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

  convert IN OUT [--layer NAME] [--exposure EV] [--encoding srgb|linear]
      Writes IN (EXR, PFM, HDR, PNG, JPEG) as OUT, in the format of OUT's extension:
      .exr, .pfm, .hdr (linear floats) or .png (8 bits). --layer picks an AOV layer of
      an EXR (default: the beauty); --exposure scales the values by 2^EV; --encoding
      says how 8-bit files (PNG, JPEG in; PNG out) encode values: sRGB (the default,
      as for display) or linear (data such as normal maps).

  info IMAGE [--layer NAME]
      Prints one `key value` per line: file, width, height, layers (EXR; `(beauty)` is
      the R, G, B layer), then for each layer (or the one named) its statistics, keyed
      by the layer's name and a dot (none for the beauty): channels, min, max and mean
      (per channel, over finite values; 8-bit files: the stored values in [0, 1]), nan
      and inf (counts of values).
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

/// How 8-bit files encode values: "srgb" (display) or "linear" (data).
bool isSRGBEncoding(const std::string &encoding, const std::string &command) {
    if (encoding != "srgb" && encoding != "linear")
        throw NoriException("{}: --encoding must be srgb or linear, got '{}'", command, encoding);
    return encoding == "srgb";
}

/// An image file's pixels, linear: an EXR's layer (the beauty when `layer` is empty), or
/// any other image, whose 8-bit values are decoded as sRGB when `srgb` is set.
Bitmap loadImage(const std::string &file, const std::string &layer, bool srgb,
                 const std::string &command) {
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
        throw NoriException("{}: --layer needs EXR files; {} is not one", command, file);
    ImageFile decoded = readImageFile(file);
    if (decoded.integerEncoded && srgb)
        for (Color3f &pixel : decoded.pixels.reshaped())
            pixel = pixel.toLinearRGB();
    return std::move(decoded.pixels);
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
    Bitmap image = loadImage(files[0], layer, true, "diff"),
           reference = loadImage(files[1], layer, true, "diff");
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

int convertCommand(const std::vector<std::string> &arguments) {
    std::vector<std::string> files;
    std::string layer, encoding = "srgb";
    float exposure = 0.0f;
    for (ArgumentReader reader(arguments, "convert"); reader.more();) {
        const std::string arg = reader.next();
        const auto value = [&] { return reader.valueOf(arg); };
        if (arg == "--layer") {
            layer = value();
        } else if (arg == "--exposure") {
            exposure = toFloat(value(), arg);
            if (!std::isfinite(exposure) || std::abs(exposure) > 100.0f)
                throw NoriException("convert: --exposure must be a number of stops in [-100, 100]");
        } else if (arg == "--encoding") {
            encoding = value();
        } else if (!arg.empty() && arg[0] == '-') {
            throw NoriException("convert: unknown option '{}'", arg);
        } else {
            files.push_back(arg);
        }
    }
    if (files.size() != 2)
        throw NoriException("convert: expects IN and OUT (got {} files)", files.size());
    const bool srgb = isSRGBEncoding(encoding, "convert");
    const std::string extension = toLower(std::filesystem::path(files[1]).extension().string());
    if (extension != ".exr" && extension != ".pfm" && extension != ".hdr" && extension != ".png")
        throw NoriException("convert: cannot write '{}': the output's extension must be .exr, "
                            ".pfm, .hdr or .png",
                            files[1]);
    Bitmap image = loadImage(files[0], layer, srgb, "convert");
    if (extension == ".png") {
        image.savePNG(files[1], exposure, srgb);
        return 0;
    }
    const float scale = std::exp2(exposure);
    for (Color3f &pixel : image.reshaped())
        pixel *= scale;
    if (extension == ".exr")
        image.saveEXR(files[1]);
    else if (extension == ".pfm")
        image.savePFM(files[1]);
    else
        image.saveHDR(files[1]);
    return 0;
}

/// Prints the statistics of one layer's channels, keys prefixed by `prefix`.
void printLayerStatistics(const std::string &prefix, const std::vector<std::string> &names,
                          const std::vector<const LayeredImage::Channel *> &channels) {
    std::vector<double> minima, maxima, means;
    size_t nans = 0, infinities = 0;
    for (const LayeredImage::Channel *channel : channels) {
        double lowest = kInfinity, highest = -kInfinity, sum = 0.0;
        size_t finite = 0;
        for (float value : channel->reshaped()) {
            if (std::isnan(value)) {
                ++nans;
            } else if (std::isinf(value)) {
                ++infinities;
            } else {
                lowest = std::min(lowest, double(value));
                highest = std::max(highest, double(value));
                sum += value;
                ++finite;
            }
        }
        // A channel with no finite value has no statistics: nan, as the counts explain.
        const double none = std::nan("");
        minima.push_back(finite ? lowest : none);
        maxima.push_back(finite ? highest : none);
        means.push_back(finite ? sum / double(finite) : none);
    }
    fmt::print("{}channels {}\n{}min {:.9g}\n{}max {:.9g}\n{}mean {:.9g}\n{}nan {}\n{}inf {}\n",
               prefix, fmt::join(names, " "), prefix, fmt::join(minima, " "), prefix,
               fmt::join(maxima, " "), prefix, fmt::join(means, " "), prefix, nans, prefix,
               infinities);
}

int infoCommand(const std::vector<std::string> &arguments) {
    std::string file, layer;
    bool layerGiven = false;
    for (ArgumentReader reader(arguments, "info"); reader.more();) {
        const std::string arg = reader.next();
        if (arg == "--layer") {
            layer = reader.valueOf(arg);
            layerGiven = true;
        } else if (!arg.empty() && arg[0] == '-') {
            throw NoriException("info: unknown option '{}'", arg);
        } else if (file.empty()) {
            file = arg;
        } else {
            throw NoriException("info: one image at a time ('{}' and '{}')", file, arg);
        }
    }
    if (file.empty())
        throw NoriException("info: no image file (see nori-imgtool --help)");
    LayeredImage image;
    if (toLower(std::filesystem::path(file).extension().string()) == ".exr") {
        image = LayeredImage::loadEXR(file);
    } else {
        if (layerGiven)
            throw NoriException("info: --layer needs an EXR file; {} is not one", file);
        ImageFile decoded = readImageFile(file);
        image = LayeredImage(Eigen::Vector2i(decoded.pixels.width(), decoded.pixels.height()));
        image.addLayer("", {"R", "G", "B"}, decoded.pixels);
    }
    std::vector<std::string> layers = image.layerNames();
    if (layerGiven) {
        try {
            image.layer(layer); // throws, naming the layers there are, when it is missing
        } catch (const NoriException &error) {
            throw NoriException("{}: {}", file, error.what());
        }
        layers = {layer};
    }
    std::vector<std::string> shown;
    for (const std::string &name : image.layerNames())
        shown.push_back(name.empty() ? "(beauty)" : name);
    fmt::print("file {}\nwidth {}\nheight {}\nlayers {}\n", file, image.size().x(),
               image.size().y(), fmt::join(shown, " "));
    for (const std::string &name : layers) {
        const std::string prefix = name.empty() ? "" : name + ".";
        const std::vector<std::string> channelNames = image.channelsOf(name);
        std::vector<const LayeredImage::Channel *> channels;
        channels.reserve(channelNames.size());
        for (const std::string &channel : channelNames)
            channels.push_back(&image.channels().at(prefix + channel));
        printLayerStatistics(prefix, channelNames, channels);
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
    if (command == "convert")
        return convertCommand({arguments.begin() + 1, arguments.end()});
    if (command == "info")
        return infoCommand({arguments.begin() + 1, arguments.end()});
    throw NoriException("unknown command '{}' (see nori-imgtool --help)", command);
}

} // namespace

int main(int argc, char **argv) {
    return runProgram([&] { return run(argc, argv); });
}
