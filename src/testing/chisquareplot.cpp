// The picture of a χ² test: observed | expected | difference histograms with labels.
#include <nori/chisquare.h>

#include <array>
#include <cctype>
#include <map>

namespace nori {

std::string parameterSetOf(const NoriObject &plugin) {
    const std::string text = plugin.toString();
    const size_t open = text.find('['), close = text.rfind(']');
    if (open == std::string::npos || close == std::string::npos || close <= open)
        return "";
    return text.substr(open + 1, close - open - 1);
}

std::string chiSquarePictureName(const std::string &plugin, const std::string &parameters,
                                 const std::string &condition) {
    // Letters, digits and "=._-" are kept; every other run of characters (brackets, spaces)
    // becomes one ',', none at the start or end or after '=': "albedo=0.5,0.5,0.5", where
    // a '-' is only ever a minus sign or a condition's own.
    auto clean = [](const std::string &text) {
        std::string out;
        bool separate = false;
        for (char c : text) {
            if (std::isalnum(static_cast<unsigned char>(c)) || c == '=' || c == '.' || c == '-' ||
                c == '_') {
                if (separate && !out.empty() && out.back() != '=')
                    out += ',';
                separate = false;
                out += c;
            } else {
                separate = true;
            }
        }
        return out.substr(0, 100);
    };
    std::string name = clean(plugin);
    for (const std::string &part : {parameters, condition})
        if (!clean(part).empty())
            name += "_" + clean(part);
    return name;
}

namespace {

/// A 5x7 bitmap font for labels: each glyph is 7 rows of 5 bits (bit 4 = left column).
const std::map<char, std::array<uint8_t, 7>> &glyphs() {
    static const std::map<char, std::array<uint8_t, 7>> font = {
        {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
        {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
        {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
        {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
        {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
        {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
        {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
        {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
        {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
        {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
        {'A', {0x0E, 0x11, 0x11, 0x11, 0x1F, 0x11, 0x11}},
        {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
        {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
        {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
        {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
        {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
        {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
        {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
        {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
        {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
        {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
        {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
        {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
        {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
        {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
        {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
        {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}},
        {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
        {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
        {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
        {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
        {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
        {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
        {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
        {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}},
        {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
        {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
        {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
        {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
        {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
        {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
        {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}},
        {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
        {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
        {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
        {'<', {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02}},
        {'>', {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08}},
        {'^', {0x04, 0x0A, 0x11, 0x00, 0x00, 0x00, 0x00}},
        {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
        {'[', {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}},
        {']', {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}},
        {'|', {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
        {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
        {' ', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}}};
    return font;
}

constexpr int kTextScale = 2;
constexpr int kCharWidth = 6 * kTextScale; ///< 5 columns and a gap
constexpr int kLineHeight = 10 * kTextScale;

/// Writes text (upper-cased; unknown characters as spaces) with its top-left at (x, y).
void drawText(Bitmap &image, int x, int y, const std::string &text, const Color3f &color) {
    for (size_t i = 0; i < text.size(); ++i) {
        auto it =
            glyphs().find(static_cast<char>(std::toupper(static_cast<unsigned char>(text[i]))));
        if (it == glyphs().end())
            continue;
        for (int row = 0; row < 7; ++row)
            for (int column = 0; column < 5; ++column) {
                if (!(it->second[row] & (0x10 >> column)))
                    continue;
                for (int sy = 0; sy < kTextScale; ++sy)
                    for (int sx = 0; sx < kTextScale; ++sx) {
                        const int px =
                            x + static_cast<int>(i) * kCharWidth + column * kTextScale + sx;
                        const int py = y + row * kTextScale + sy;
                        if (px >= 0 && py >= 0 && px < image.width() && py < image.height())
                            image(py, px) = color;
                    }
            }
    }
}

/// A perceptually ordered ramp (dark blue → teal → yellow), in sRGB.
Color3f sequentialColor(double t) {
    static const Color3f kStops[] = {
        {0.05f, 0.03f, 0.25f}, {0.15f, 0.35f, 0.55f}, {0.15f, 0.65f, 0.50f}, {0.98f, 0.90f, 0.15f}};
    t = std::clamp(t, 0.0, 1.0) * 3.0;
    const int i = std::min(static_cast<int>(t), 2);
    const float f = static_cast<float>(t - i);
    return kStops[i] * (1.0f - f) + kStops[i + 1] * f;
}

/// Blue for negative, white for zero, red for positive t in [-1, 1], in sRGB.
Color3f divergingColor(double t) {
    t = std::clamp(t, -1.0, 1.0);
    const float f = static_cast<float>(std::abs(t));
    const Color3f end = t < 0 ? Color3f(0.15f, 0.35f, 0.85f) : Color3f(0.85f, 0.15f, 0.15f);
    return Color3f(1.0f) * (1.0f - f) + end * f;
}

} // namespace

Bitmap renderChiSquareReport(const ChiSquareReport &report, const std::string &title) {
    // The sphere's histogram is shown with φ across and cos θ down (+1 at the top); a
    // planar one with x across and y up.
    const bool sphere = report.yBins == 2 * report.xBins;
    const int columns = sphere ? report.yBins : report.xBins;
    const int rows = sphere ? report.xBins : report.yBins;
    const int cell = std::max(2, 320 / columns);
    const int panelWidth = cell * columns, panelHeight = cell * rows;
    const int margin = 16;
    const std::string verdict = report.result.message;
    // Wrap the verdict to the width of the picture.
    const int width = 3 * panelWidth + 4 * margin;
    const size_t charsPerLine = static_cast<size_t>((width - 2 * margin) / kCharWidth);
    std::vector<std::string> lines;
    for (size_t start = 0; start < verdict.size(); start += charsPerLine)
        lines.push_back(verdict.substr(start, charsPerLine));
    const int height = margin + kLineHeight * 2 + panelHeight + margin +
                       kLineHeight * static_cast<int>(lines.size() + 1) + margin;

    Bitmap image(Eigen::Vector2i(width, height));
    image.setConstant(Color3f(1.0f));
    const Color3f black(0.0f);
    drawText(image, margin, margin, title, black);

    double maxCount = 0.0, maxDifference = 0.0;
    for (size_t i = 0; i < report.observed.size(); ++i) {
        maxCount = std::max({maxCount, report.observed[i], report.expected[i]});
        maxDifference = std::max(maxDifference, std::abs(report.observed[i] - report.expected[i]));
    }
    const std::string panelTitles[3] = {
        "observed", "expected", fmt::format("obs - exp (+-{:.0f})", std::max(maxDifference, 1.0))};
    const int panelTop = margin + 2 * kLineHeight;
    for (int panel = 0; panel < 3; ++panel) {
        const int left = margin + panel * (panelWidth + margin);
        drawText(image, left, margin + kLineHeight, panelTitles[panel], black);
        for (int row = 0; row < rows; ++row)
            for (int column = 0; column < columns; ++column) {
                // Histogram bin shown at (row, column).
                const int bx = sphere ? report.xBins - 1 - row : column;
                const int by = sphere ? column : report.yBins - 1 - row;
                const size_t bin = static_cast<size_t>(by) * report.xBins + bx;
                const double observed = report.observed[bin], expected = report.expected[bin];
                Color3f color =
                    panel == 0 ? sequentialColor(maxCount > 0 ? observed / maxCount : 0.0)
                    : panel == 1
                        ? sequentialColor(maxCount > 0 ? expected / maxCount : 0.0)
                        : divergingColor(maxDifference > 0 ? (observed - expected) / maxDifference
                                                           : 0.0);
                color = color.toLinearRGB(); // the PNG writer applies the sRGB curve
                for (int y = 0; y < cell; ++y)
                    for (int x = 0; x < cell; ++x)
                        image(panelTop + row * cell + y, left + column * cell + x) = color;
            }
    }
    const int textTop = panelTop + panelHeight + margin;
    drawText(image, margin, textTop,
             sphere ? "axes: phi across, cos theta down from +1" : "axes: x across, y up",
             Color3f(0.3f));
    for (size_t i = 0; i < lines.size(); ++i)
        drawText(image, margin, textTop + kLineHeight * static_cast<int>(i + 1), lines[i],
                 report.result.passed ? Color3f(0.0f, 0.3f, 0.0f) : Color3f(0.6f, 0.0f, 0.0f));
    return image;
}

} // namespace nori
