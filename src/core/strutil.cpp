#include <nori/common.h>
#include <nori/strutil.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>

namespace nori {

std::vector<std::string> tokenize(const std::string &text, const std::string &delimiters,
                                  bool includeEmpty) {
    std::vector<std::string> tokens;
    if (includeEmpty) {
        std::string::size_type start = 0;
        while (true) {
            const std::string::size_type end = text.find_first_of(delimiters, start);
            tokens.push_back(text.substr(start, end - start));
            if (end == std::string::npos)
                return tokens;
            start = end + 1;
        }
    }
    std::string::size_type start = text.find_first_not_of(delimiters);
    while (start != std::string::npos) {
        std::string::size_type end = text.find_first_of(delimiters, start);
        tokens.push_back(text.substr(start, end - start));
        start = text.find_first_not_of(delimiters, end);
    }
    return tokens;
}

float toFloat(const std::string &text, const std::string &what) {
    const char *begin = text.c_str();
    char *end = nullptr;
    errno = 0;
    float value = std::strtof(begin, &end);
    while (end && std::isspace(static_cast<unsigned char>(*end)))
        ++end;
    if (text.empty() || end == begin || *end != '\0' || errno == ERANGE)
        throw NoriException("could not parse {} '{}' as a floating point number", what, text);
    return value;
}

int toInt(const std::string &text, const std::string &what) {
    const char *begin = text.c_str();
    char *end = nullptr;
    errno = 0;
    long value = std::strtol(begin, &end, 10);
    while (end && std::isspace(static_cast<unsigned char>(*end)))
        ++end;
    if (text.empty() || end == begin || *end != '\0' || errno == ERANGE ||
        value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
        throw NoriException("could not parse {} '{}' as an integer", what, text);
    return static_cast<int>(value);
}

std::vector<float> toFloatList(const std::string &text, const std::string &what) {
    std::vector<float> values;
    for (const std::string &token : tokenize(text))
        values.push_back(toFloat(token, what));
    return values;
}

std::string trim(const std::string &text) {
    const size_t begin = text.find_first_not_of(" \t");
    if (begin == std::string::npos)
        return "";
    return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

std::string toLower(std::string text) {
    for (char &c : text)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

bool endsWith(const std::string &text, const std::string &suffix) {
    return text.size() >= suffix.size() &&
           text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

int editDistance(const std::string &first, const std::string &second) {
    const std::string a = toLower(first), b = toLower(second);
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
    for (size_t i = 0; i <= n; ++i)
        d[i][0] = static_cast<int>(i);
    for (size_t j = 0; j <= m; ++j)
        d[0][j] = static_cast<int>(j);
    for (size_t i = 1; i <= n; ++i) {
        for (size_t j = 1; j <= m; ++j) {
            int cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    }
    return d[n][m];
}

std::string closestMatch(const std::string &name, const std::vector<std::string> &candidates) {
    std::string best;
    int bestDistance = std::numeric_limits<int>::max();
    for (const std::string &candidate : candidates) {
        if (candidate == name)
            continue;
        int distance = editDistance(name, candidate);
        if (distance < bestDistance) {
            bestDistance = distance;
            best = candidate;
        }
    }
    const int length = static_cast<int>(std::max(name.size(), best.size()));
    if (best.empty() || bestDistance > 2 || 2 * bestDistance >= length)
        return "";
    return best;
}

std::string didYouMean(const std::string &name, const std::vector<std::string> &candidates) {
    std::string match = closestMatch(name, candidates);
    return match.empty() ? "" : fmt::format(" (did you mean '{}'?)", match);
}

std::string jsonString(const std::string &text) {
    std::string quoted = "\"";
    for (const char c : text) {
        switch (c) {
        case '"':
            quoted += "\\\"";
            break;
        case '\\':
            quoted += "\\\\";
            break;
        case '\n':
            quoted += "\\n";
            break;
        case '\t':
            quoted += "\\t";
            break;
        default:
            if (static_cast<unsigned char>(c) < 0x20)
                quoted += fmt::format("\\u{:04x}", static_cast<unsigned char>(c));
            else
                quoted += c;
        }
    }
    return quoted + '"';
}

} // namespace nori
