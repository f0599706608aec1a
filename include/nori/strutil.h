// String helpers used where text from outside (XML, OBJ, command line) is read.
#pragma once

#include <string>
#include <vector>

namespace nori {

/// Splits on any of the delimiter characters, dropping empty tokens unless includeEmpty.
std::vector<std::string> tokenize(const std::string &text,
                                  const std::string &delimiters = ", \t\r\n",
                                  bool includeEmpty = false);
/// Parses the whole string as a float / int; throws NoriException naming `what` otherwise.
float toFloat(const std::string &text, const std::string &what = "number");
int toInt(const std::string &text, const std::string &what = "integer");
/// Parses a list of floats separated by commas and/or white space.
std::vector<float> toFloatList(const std::string &text, const std::string &what = "value");
std::string toLower(std::string text);
/// The text without its leading and trailing spaces and tabs.
std::string trim(const std::string &text);
bool endsWith(const std::string &text, const std::string &suffix);

/// Edit distance with adjacent transpositions (optimal string alignment), case-insensitive.
int editDistance(const std::string &a, const std::string &b);
/// The candidate closest to `name` if it is a plausible typo of it (at most two edits,
/// and fewer than half the characters changed), else an empty string.
std::string closestMatch(const std::string &name, const std::vector<std::string> &candidates);
/// " (did you mean 'x'?)" or "" — for appending to error messages.
std::string didYouMean(const std::string &name, const std::vector<std::string> &candidates);

/// `text` as a JSON string literal, quotes included (RFC 8259 §7: ", \ and control
/// characters escaped; UTF-8 passes through).
std::string jsonString(const std::string &text);

} // namespace nori
