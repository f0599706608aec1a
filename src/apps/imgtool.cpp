// nori-imgtool: operations on rendered images: `denoise` runs the built-in denoiser on a
// multi-layer EXR written by `nori --aovs ...`; `diff` compares a render with a reference;
// `compare` says whether two renders agree within their noise; `convert` changes an
// image's format; `info` prints its size, layers and statistics.
#include "app/cli.h"
#include "denoise/denoiser.h"
#include "testing/halfbuffers.h"
#include <nori/imagefile.h>
#include <nori/layeredimage.h>
#include <nori/strutil.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>

using namespace nori;

namespace {

/// The options of each command, as the command line gives them.
struct DenoiseOptions {
    std::string input, output;
    int threads = 0;
};
struct DiffOptions {
    std::vector<std::string> files;
    std::string layer, errorImage, metric = "relmse", crop;
    double tolerance = -1.0;
    float excludeAbove = kInfinity; ///< reference values above this leave their pixel out
    int excludeRim = 0;             ///< and the pixels this close to one (Chebyshev distance)
};
struct CompareOptions {
    std::vector<std::string> files, regions;
    int grid = 0, radius = HalfBufferErrors::kDefaultRadius;
    double threshold = 4.0;
};
struct ConvertOptions {
    std::vector<std::string> files;
    std::string layer, encoding = "srgb";
    float exposure = 0.0f;
};
struct InfoOptions {
    std::string file, layer;
};

int denoiseCommand(const DenoiseOptions &options) {
    const std::string &input = options.input, &output = options.output;
    DenoiserSettings settings;
    if (options.threads != 0) {
        settings.threads = options.threads;
        if (settings.threads <= 0)
            throw NoriException("denoise: --threads must be a positive integer");
    }
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

/// The pixels compared: those whose reference is at most `above` in every channel and no
/// closer than `rim` pixels (in x and y) to one that is not (a light and its rim, whose
/// noise is not the estimator's).
Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> keptPixels(const Bitmap &reference, float above,
                                                              int rim) {
    const Eigen::Index rows = reference.rows(), cols = reference.cols();
    Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> kept =
        Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(rows, cols, true);
    for (Eigen::Index y = 0; y < rows; ++y)
        for (Eigen::Index x = 0; x < cols; ++x) {
            if (!(reference(y, x).maxCoeff() > above))
                continue;
            // The square of side 2·rim + 1 about (x, y), clipped to the image.
            const Eigen::Index top = std::max<Eigen::Index>(0, y - rim),
                               bottom = std::min<Eigen::Index>(rows, y + rim + 1),
                               left = std::max<Eigen::Index>(0, x - rim),
                               right = std::min<Eigen::Index>(cols, x + rim + 1);
            kept.block(top, left, bottom - top, right - left).setConstant(false);
        }
    return kept;
}

/// The kept pixels of `image` in one row, in reading order.
Bitmap keptRow(const Bitmap &image,
               const Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> &kept) {
    Bitmap row(Eigen::Vector2i(static_cast<int>(kept.count()), 1));
    Eigen::Index next = 0;
    for (Eigen::Index y = 0; y < image.rows(); ++y)
        for (Eigen::Index x = 0; x < image.cols(); ++x)
            if (kept(y, x))
                row(0, next++) = image(y, x);
    return row;
}

/// The false-colour ramp black → red → yellow → white over t in [0, 1].
Color3f falseColor(float t) {
    t = std::clamp(t, 0.0f, 1.0f) * 3.0f;
    return Color3f(std::min(t, 1.0f), std::clamp(t - 1.0f, 0.0f, 1.0f),
                   std::clamp(t - 2.0f, 0.0f, 1.0f));
}

int diffCommand(const DiffOptions &options) {
    const std::vector<std::string> &files = options.files;
    const std::string &layer = options.layer, &errorImage = options.errorImage,
                      &metric = options.metric, &crop = options.crop;
    const double tolerance = options.tolerance;
    if (metric != "rmse" && metric != "relmse" && metric != "maxabs")
        throw NoriException("diff: --metric must be rmse, relmse or maxabs, got '{}'", metric);
    if (tolerance != -1.0 && (!(tolerance >= 0.0) || !std::isfinite(tolerance)))
        throw NoriException("diff: --tolerance must be a non-negative number");
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
    if (options.excludeRim < 0)
        throw NoriException("diff: --exclude-rim must be 0 or more, got {}", options.excludeRim);
    const auto kept = keptPixels(reference, options.excludeAbove, options.excludeRim);
    if (!kept.any())
        throw NoriException("diff: --exclude-above {} leaves no pixel to compare",
                            options.excludeAbove);

    double maxAbs = 0.0, peak = 1.0;
    size_t differing = 0;
    Eigen::ArrayXXf pixelError = Eigen::ArrayXXf::Zero(image.rows(), image.cols());
    for (Eigen::Index y = 0; y < image.rows(); ++y)
        for (Eigen::Index x = 0; x < image.cols(); ++x) {
            if (!kept(y, x))
                continue;
            const Color3f difference = (image(y, x) - reference(y, x)).abs();
            maxAbs = std::max(maxAbs, double(difference.maxCoeff()));
            peak = std::max(peak, double(reference(y, x).maxCoeff()));
            differing += (difference > 0.0f).any() || image(y, x).hasNaN() ? 1 : 0;
            pixelError(y, x) = difference.mean();
        }
    // The means over the kept pixels: the same functions, on the kept pixels in a row.
    const bool all = kept.all();
    const double mse = all ? meanSquaredError(image, reference)
                           : meanSquaredError(keptRow(image, kept), keptRow(reference, kept));
    const double relmse =
        all ? relativeMeanSquaredError(image, reference)
            : relativeMeanSquaredError(keptRow(image, kept), keptRow(reference, kept));
    const double psnr = 10.0 * std::log10(peak * peak / mse); // +inf when equal
    fmt::print("rmse {:.9g}\nrelmse {:.9g}\nmaxabs {:.9g}\npsnr {:.6g}\npixels {}\ndiffering {}\n",
               std::sqrt(mse), relmse, maxAbs, psnr, kept.count(), differing);
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

constexpr const char *kChannelNames[3] = {"R", "G", "B"};

/// One render of `compare`: its region estimates, or exact values for a reference
/// without half-buffers.
struct ComparedRender {
    std::string file;
    LayeredImage image;
    std::optional<HalfBufferErrors> errors;

    int radius;

    ComparedRender(const std::string &name, int correlationRadius)
        : file(name), image(LayeredImage::loadEXR(name)), radius(correlationRadius) {
        if (!image.hasLayer(""))
            throw NoriException("{}: has no beauty (R, G, B)", file);
        if (hasHalfBuffers(image)) {
            try {
                errors.emplace(image, radius);
            } catch (const NoriException &error) {
                throw NoriException("{}: {}", file, error.what());
            }
        }
    }

    std::array<RegionEstimate, 3> estimate(const ImageRegion &region) const {
        if (errors)
            return errors->estimate(region);
        // A reference taken as exact: its means with no standard error.
        const Bitmap beauty = image.layer("");
        const int width = region.width > 0 ? region.width : int(beauty.cols());
        const int height = region.width > 0 ? region.height : int(beauty.rows());
        std::array<RegionEstimate, 3> result;
        for (int c = 0; c < 3; ++c) {
            double sum = 0.0;
            for (int y = region.y; y < region.y + height; ++y)
                for (int x = region.x; x < region.x + width; ++x)
                    sum += beauty(y, x)[c];
            result[c].mean = sum / (double(width) * height);
        }
        return result;
    }

    std::string describe() const {
        if (!errors)
            return fmt::format("{}: no half-buffers, taken as exact (a reference)", file);
        return fmt::format("{}: pixels' noise correlated over {} pixels: κ = {:.3g}", file, radius,
                           errors->correlationFactor());
    }
};

int compareCommand(const CompareOptions &options) {
    if (options.files.size() != 2)
        throw NoriException("compare: expects two renders, A and B (got {})", options.files.size());
    if (!(options.threshold > 0.0) || !std::isfinite(options.threshold))
        throw NoriException("compare: --threshold must be a positive number of standard errors");
    if (options.grid < 0)
        throw NoriException("compare: --grid must be a positive number of regions per side");
    if (options.radius < 0)
        throw NoriException("compare: --correlation-radius must be at least 0 pixels");
    const ComparedRender a(options.files[0], options.radius), b(options.files[1], options.radius);
    const Eigen::Vector2i size = a.image.size();
    if (b.image.size() != size)
        throw NoriException("compare: {} is {}x{} but {} is {}x{}", a.file, size.x(), size.y(),
                            b.file, b.image.size().x(), b.image.size().y());
    if (!a.errors && !b.errors)
        throw NoriException("compare: neither {} nor {} has half-buffers, so neither has a "
                            "standard error: render at least one with --aovs variance",
                            a.file, b.file);

    std::vector<ImageRegion> regions{{"image", 0, 0, 0, 0}};
    for (const std::string &text : options.regions) {
        const size_t equals = text.find('=');
        const std::string name = equals == std::string::npos ? text : text.substr(0, equals);
        if (equals == std::string::npos || name.empty())
            throw NoriException("compare: --region expects NAME=X,Y,W,H, got '{}'", text);
        regions.push_back(parseImageRegion(name, text.substr(equals + 1), size));
    }
    if (options.grid > 0) {
        if (options.grid > std::min(size.x(), size.y()))
            throw NoriException("compare: --grid {} has more cells than the {}x{} image has "
                                "pixels on a side",
                                options.grid, size.x(), size.y());
        for (int j = 0; j < options.grid; ++j)
            for (int i = 0; i < options.grid; ++i) {
                const int x0 = i * size.x() / options.grid, x1 = (i + 1) * size.x() / options.grid;
                const int y0 = j * size.y() / options.grid, y1 = (j + 1) * size.y() / options.grid;
                regions.push_back({fmt::format("cell{},{}", i, j), x0, y0, x1 - x0, y1 - y0});
            }
    }

    fmt::print("A {}\nB {}\n", a.describe(), b.describe());
    AgreementSettings settings;
    settings.threshold = options.threshold;
    // Columns: the means, their difference relative to B's, the standard error of the
    // difference, z, and the smallest relative bias seen with 95 % power.
    fmt::print("{:<14} {:>2} {:>12} {:>12} {:>10} {:>11} {:>8} {:>10}\n", "region", "", "A", "B",
               "(A-B)/B", "std. error", "z", "detectable");
    size_t disagreements = 0;
    std::string worst;
    double worstZ = 0.0;
    for (const ImageRegion &region : regions) {
        const std::array<RegionEstimate, 3> ofA = a.estimate(region), ofB = b.estimate(region);
        for (int c = 0; c < 3; ++c) {
            const AgreementCell cell = compareEstimates(ofA[c], ofB[c], settings);
            const double sigma = std::hypot(ofA[c].standardError, ofB[c].standardError);
            fmt::print(
                "{:<14} {:>2} {:>12.6g} {:>12.6g} {:>+9.3f}% {:>11.3g} {:>+8.2f} {:>9.2f}%{}\n",
                region.name, kChannelNames[c], ofA[c].mean, ofB[c].mean, 100.0 * cell.difference,
                sigma, cell.z, 100.0 * cell.detectableBias, cell.agrees ? "" : "  DISAGREES");
            if (!cell.agrees)
                ++disagreements;
            if (std::abs(cell.z) > std::abs(worstZ)) {
                worstZ = cell.z;
                worst = fmt::format("{} {}", region.name, kChannelNames[c]);
            }
        }
    }
    if (disagreements > 0) {
        fmt::print("verdict: DISAGREE: {} of {} comparisons beyond {:g} standard errors (worst: "
                   "{}, z = {:+.2f})\n",
                   disagreements, 3 * regions.size(), options.threshold, worst, worstZ);
        return 1;
    }
    fmt::print("verdict: agree: every |z| <= {:g} ({} comparisons; largest: {}, z = {:+.2f})\n",
               options.threshold, 3 * regions.size(), worst.empty() ? "none" : worst, worstZ);
    return 0;
}

int convertCommand(const ConvertOptions &options) {
    const std::vector<std::string> &files = options.files;
    const std::string &layer = options.layer;
    const float exposure = options.exposure;
    if (!std::isfinite(exposure) || std::abs(exposure) > 100.0f)
        throw NoriException("convert: --exposure must be a number of stops in [-100, 100]");
    if (files.size() != 2)
        throw NoriException("convert: expects IN and OUT (got {} files)", files.size());
    const bool srgb = isSRGBEncoding(options.encoding, "convert");
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

int infoCommand(const InfoOptions &options, bool layerGiven) {
    const std::string &file = options.file, &layer = options.layer;
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

} // namespace

int main(int argc, char **argv) {
    DenoiseOptions denoiseOptions;
    DiffOptions diffOptions;
    CompareOptions compareOptions;
    ConvertOptions convertOptions;
    InfoOptions infoOptions;
    CLI::App *denoise = nullptr, *diff = nullptr, *compare = nullptr, *convert = nullptr,
             *info = nullptr;
    CLI::Option *infoLayer = nullptr;
    return runCommandLine(
        argc, argv, "nori-imgtool", "Operations on rendered images.",
        [&](CLI::App &app) {
            app.require_subcommand(1);
            denoise = app.add_subcommand(
                "denoise",
                "Denoises the beauty of IN.exr, a render with the layers albedo, normal, "
                "depth and variance (nori --denoise, or nori --aovs "
                "albedo,normal,depth,variance), and writes OUT.exr and OUT.png.");
            denoise->add_option("input", denoiseOptions.input, "the render")
                ->type_name("IN.exr")
                ->required();
            denoise
                ->add_option("-o,--output", denoiseOptions.output,
                             "OUT (default: IN_denoised beside IN); IN is left as it is")
                ->type_name("OUT");
            denoise
                ->add_option("-t,--threads", denoiseOptions.threads, "threads (default: all cores)")
                ->type_name("N");
            diff = app.add_subcommand(
                "diff",
                "Compares IMAGE with REFERENCE (EXR, PFM, HDR, PNG, JPEG; of one size) and "
                "prints one `key value` per line: rmse, relmse (Σ(a−b)²/(b²+0.01), per "
                "channel), maxabs, psnr (dB, the peak being REFERENCE's largest value or 1), "
                "pixels, differing (pixels not equal).");
            diff->add_option("files", diffOptions.files, "the render and the reference")
                ->type_name("IMAGE REFERENCE")
                ->expected(2)
                ->required();
            diff->add_option("--layer", diffOptions.layer,
                             "compare an AOV layer of two EXRs (default: the beauty)")
                ->type_name("NAME");
            diff->add_option(
                    "--crop", diffOptions.crop,
                    "compare only the W×H pixels from column X, row Y (a region of interest)")
                ->type_name("X,Y,W,H");
            diff->add_option("--exclude-above", diffOptions.excludeAbove,
                             "leave out the pixels whose reference exceeds V in a channel (a "
                             "light seen directly)")
                ->type_name("V");
            diff->add_option("--exclude-rim", diffOptions.excludeRim,
                             "with --exclude-above, also the pixels within R pixels of those "
                             "(default 0)")
                ->type_name("R");
            diff->add_option("--tolerance", diffOptions.tolerance,
                             "exit 1 when the metric exceeds T")
                ->type_name("T");
            diff->add_option("--metric", diffOptions.metric,
                             "the metric --tolerance bounds: rmse, relmse (default) or maxabs")
                ->type_name("M");
            diff->add_option(
                    "--out", diffOptions.errorImage,
                    "write the per-pixel absolute error in false colour (black, red, yellow, "
                    "white up to the largest error)")
                ->type_name("ERROR.png");
            compare = app.add_subcommand(
                "compare",
                "Says whether two renders of one scene agree within their noise: compares the "
                "mean of each channel over the whole image (and each --region, --grid cell) in "
                "standard errors, estimated from each render's half-buffers (render with "
                "--aovs variance; the pixels' correlation through the filter is measured and "
                "counted). A render without half-buffers is taken as an exact reference. "
                "Prints a table and a verdict; exits 0 when every |z| is within the threshold, "
                "1 when one is not (or on an error).");
            compare->add_option("files", compareOptions.files, "the two renders (EXR)")
                ->type_name("A.exr B.exr")
                ->expected(2)
                ->required();
            compare
                ->add_option("--region", compareOptions.regions,
                             "also compare the W×H pixels from column X, row Y; repeatable")
                ->type_name("NAME=X,Y,W,H");
            compare
                ->add_option("--grid", compareOptions.grid,
                             "also compare each cell of an N×N grid over the image")
                ->type_name("N");
            compare
                ->add_option("--threshold", compareOptions.threshold,
                             "standard errors a difference may reach and still agree (default "
                             "4: a correct pair disagrees on one comparison in 16,000)")
                ->type_name("Z");
            compare
                ->add_option("--correlation-radius", compareOptions.radius,
                             "how far apart two pixels' noise may be correlated, in pixels: "
                             "twice the filter's radius (default 4, for the Gaussian and "
                             "Mitchell filters of radius 2)")
                ->type_name("PIXELS");
            convert = app.add_subcommand(
                "convert", "Writes IN (EXR, PFM, HDR, PNG, JPEG) as OUT, in the format of OUT's "
                           "extension: .exr, .pfm, .hdr (linear floats) or .png (8 bits).");
            convert->add_option("files", convertOptions.files, "the image and the file to write")
                ->type_name("IN OUT")
                ->expected(2)
                ->required();
            convert
                ->add_option("--layer", convertOptions.layer,
                             "an AOV layer of an EXR (default: the beauty)")
                ->type_name("NAME");
            convert->add_option("--exposure", convertOptions.exposure, "scale the values by 2^EV")
                ->type_name("EV");
            convert
                ->add_option("--encoding", convertOptions.encoding,
                             "how 8-bit files (PNG, JPEG in; PNG out) encode values: srgb (the "
                             "default, as for display) or linear (data such as normal maps)")
                ->type_name("srgb|linear");
            info = app.add_subcommand(
                "info",
                "Prints one `key value` per line: file, width, height, layers (EXR; `(beauty)` "
                "is the R, G, B layer), then for each layer (or the one named) its statistics, "
                "keyed by the layer's name and a dot (none for the beauty): channels, min, max "
                "and mean (per channel, over finite values; 8-bit files: the stored values in "
                "[0, 1]), nan and inf (counts of values).");
            info->add_option("image", infoOptions.file, "the image")
                ->type_name("IMAGE")
                ->required();
            infoLayer = info->add_option("--layer", infoOptions.layer, "only this layer")
                            ->type_name("NAME");
        },
        [&](const CLI::App &) {
            if (denoise->parsed())
                return denoiseCommand(denoiseOptions);
            if (diff->parsed())
                return diffCommand(diffOptions);
            if (compare->parsed())
                return compareCommand(compareOptions);
            if (convert->parsed())
                return convertCommand(convertOptions);
            return infoCommand(infoOptions, infoLayer->count() > 0);
        });
}
