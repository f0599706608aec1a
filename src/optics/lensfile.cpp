#include <nori/common.h>
#include <nori/filesystem.h>
#include <nori/lensfile.h>
#include <nori/strutil.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace nori {

namespace {

/// Parses one number of a row; `column` names it in the error.
double parseColumn(const std::string &token, const char *column, const std::string &where) {
    char *end = nullptr;
    errno = 0;
    const double value = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(value))
        throw NoriException("{}: the {} '{}' is not a finite number", where, column, token);
    return value;
}

} // namespace

std::vector<LensInterfaceRow> parseLensPrescription(const std::string &text,
                                                    const std::string &fileName) {
    std::vector<LensInterfaceRow> rows;
    std::istringstream lines(text);
    std::string line;
    int lineNumber = 0;
    while (std::getline(lines, line)) {
        ++lineNumber;
        const std::string where = fmt::format("{}:{}", fileName, lineNumber);
        const std::vector<std::string> tokens = tokenize(line.substr(0, line.find('#')), " \t\r");
        if (tokens.empty())
            continue;
        if (tokens.size() != 4)
            throw NoriException("{}: a lens row holds 4 numbers (curvature radius, thickness, "
                                "index of refraction, aperture diameter; in mm), got {}: '{}'",
                                where, tokens.size(), line);
        LensInterfaceRow row;
        row.curvatureRadius = parseColumn(tokens[0], "curvature radius", where);
        row.thickness = parseColumn(tokens[1], "thickness", where);
        row.eta = parseColumn(tokens[2], "index of refraction", where);
        row.apertureDiameter = parseColumn(tokens[3], "aperture diameter", where);
        row.line = lineNumber;
        if (!(row.apertureDiameter > 0.0))
            throw NoriException("{}: the aperture diameter must be positive, got {} mm", where,
                                tokens[3]);
        if (row.thickness < 0.0)
            throw NoriException("{}: the thickness must not be negative, got {} mm", where,
                                tokens[1]);
        if (row.eta == 0.0)
            row.eta = 1.0; // pbrt's files write air as 0
        if (row.eta < 1.0)
            throw NoriException("{}: the index of refraction must be 0 (air) or at least 1, got {}",
                                where, tokens[2]);
        if (row.curvatureRadius != 0.0 &&
            std::abs(row.curvatureRadius) < 0.5 * row.apertureDiameter)
            throw NoriException("{}: a sphere of radius {} mm cannot hold an aperture of "
                                "diameter {} mm",
                                where, tokens[0], tokens[3]);
        const double etaBefore = rows.empty() ? 1.0 : rows.back().eta;
        if (row.curvatureRadius == 0.0 && row.eta != etaBefore)
            throw NoriException("{}: an aperture stop (radius 0) lies between two media of "
                                "indices {} and {}; it does not refract, so both must be the "
                                "same (write a flat glass surface as a very large radius)",
                                where, etaBefore, row.eta);
        rows.push_back(row);
    }
    if (rows.empty())
        throw NoriException("{}: the lens file holds no rows (curvature radius, thickness, index "
                            "of refraction, aperture diameter)",
                            fileName);
    bool refracts = false;
    for (const LensInterfaceRow &row : rows)
        refracts = refracts || row.curvatureRadius != 0.0;
    if (!refracts)
        throw NoriException("{}: the lens has no refracting surface (every radius is 0)", fileName);
    return rows;
}

std::vector<LensInterfaceRow> readLensFile(const std::string &path) {
    return parseLensPrescription(readTextFile(path, "lens file"), path);
}

} // namespace nori
