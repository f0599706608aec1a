// The tokenizer and parser of pbrt-v4 scene files (see pbrtparser.h). The rules are
// pbrt-v4's (src/pbrt/parser.cpp): a token is a quoted string, a bracket, a comment, or a
// run of characters up to white space, a quote or a bracket; each directive takes a fixed
// shape of positional arguments, then (for most) a parameter list.
#include <nori/common.h>
#include <nori/compression.h>
#include <nori/filesystem.h>
#include <nori/pbrtparser.h>
#include <nori/strutil.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <utility>

namespace nori::pbrt {

std::string Location::str() const {
    return fmt::format("{}:{}:{}", file, line, column);
}

namespace {

/// Deepest nesting of Include and Import.
constexpr int kMaxIncludeDepth = 32;

/// How a directive's positional arguments look (pbrt-v4's parse()).
enum class Shape {
    Bare,          ///< no arguments
    Numbers,       ///< a fixed count of numbers
    Matrix,        ///< [ 16 numbers ]
    Name,          ///< one quoted string
    Names,         ///< one or two quoted strings (MediumInterface)
    TypeAndParams, ///< a quoted plugin type, then parameters
    Texture,       ///< three quoted strings (name, type, class), then parameters
    Word,          ///< a bare word (ActiveTransform)
    Option,        ///< a quoted name and one value
    File,          ///< a quoted file name (Include, Import)
};

struct Signature {
    Shape shape;
    int numbers = 0;
};

const std::map<std::string, Signature> &signatures() {
    static const std::map<std::string, Signature> table = {
        {"Accelerator", {Shape::TypeAndParams}},
        {"ActiveTransform", {Shape::Word}},
        {"AreaLightSource", {Shape::TypeAndParams}},
        {"Attribute", {Shape::TypeAndParams}},
        {"AttributeBegin", {Shape::Bare}},
        {"AttributeEnd", {Shape::Bare}},
        {"Camera", {Shape::TypeAndParams}},
        {"ColorSpace", {Shape::Name}},
        {"ConcatTransform", {Shape::Matrix}},
        {"CoordSysTransform", {Shape::Name}},
        {"CoordinateSystem", {Shape::Name}},
        {"Film", {Shape::TypeAndParams}},
        {"Identity", {Shape::Bare}},
        {"Import", {Shape::File}},
        {"Include", {Shape::File}},
        {"Integrator", {Shape::TypeAndParams}},
        {"LightSource", {Shape::TypeAndParams}},
        {"LookAt", {Shape::Numbers, 9}},
        {"MakeNamedMaterial", {Shape::TypeAndParams}},
        {"MakeNamedMedium", {Shape::TypeAndParams}},
        {"Material", {Shape::TypeAndParams}},
        {"MediumInterface", {Shape::Names}},
        {"NamedMaterial", {Shape::Name}},
        {"ObjectBegin", {Shape::Name}},
        {"ObjectEnd", {Shape::Bare}},
        {"ObjectInstance", {Shape::Name}},
        {"Option", {Shape::Option}},
        {"PixelFilter", {Shape::TypeAndParams}},
        {"ReverseOrientation", {Shape::Bare}},
        {"Rotate", {Shape::Numbers, 4}},
        {"Sampler", {Shape::TypeAndParams}},
        {"Scale", {Shape::Numbers, 3}},
        {"Shape", {Shape::TypeAndParams}},
        {"Texture", {Shape::Texture}},
        {"Transform", {Shape::Matrix}},
        {"TransformBegin", {Shape::Bare}},
        {"TransformEnd", {Shape::Bare}},
        {"TransformTimes", {Shape::Numbers, 2}},
        {"Translate", {Shape::Numbers, 3}},
        {"WorldBegin", {Shape::Bare}},
        {"WorldEnd", {Shape::Bare}}, // pbrt-v3's; accepted and meaningless
    };
    return table;
}

/// The parameter types of pbrt-v4's ParameterDictionary, and the spellings of older files
/// it upgrades (point, vector, normal, color).
const std::map<std::string, std::string> &parameterTypes() {
    static const std::map<std::string, std::string> table = {
        {"integer", "integer"},   {"float", "float"},
        {"point2", "point2"},     {"vector2", "vector2"},
        {"point3", "point3"},     {"vector3", "vector3"},
        {"normal3", "normal3"},   {"normal", "normal3"},
        {"point", "point3"},      {"vector", "vector3"},
        {"rgb", "rgb"},           {"color", "rgb"},
        {"spectrum", "spectrum"}, {"blackbody", "blackbody"},
        {"string", "string"},     {"bool", "bool"},
        {"texture", "texture"}};
    return table;
}

struct Token {
    std::string text; ///< a string's content (unescaped), or the token as written
    bool quoted = false;
    Location location;
};

/// Splits one file's text into tokens, skipping white space and comments.
class Tokenizer {
public:
    Tokenizer(std::string text, std::string file, std::string folder)
        : m_text(std::move(text)), m_folder(std::move(folder)) {
        m_location.file = std::move(file);
        if (m_text.size() >= 2 && ((uint8_t(m_text[0]) == 0xfe && uint8_t(m_text[1]) == 0xff) ||
                                   (uint8_t(m_text[0]) == 0xff && uint8_t(m_text[1]) == 0xfe)))
            throw LocatedError(m_location.str(), "the file is UTF-16; save it as UTF-8 or ASCII");
    }

    const std::string &folder() const { return m_folder; }
    const std::string &file() const { return m_location.file; }

    std::optional<Token> next() {
        while (m_position < m_text.size()) {
            const Location start = m_location;
            const char c = get();
            if (c == ' ' || c == '\n' || c == '\t' || c == '\r')
                continue;
            if (c == '#') {
                while (m_position < m_text.size() && peek() != '\n' && peek() != '\r')
                    get();
                continue;
            }
            if (c == '[' || c == ']')
                return Token{std::string(1, c), false, start};
            if (c == '"')
                return quoted(start);
            std::string text(1, c);
            while (m_position < m_text.size()) {
                const char d = peek();
                if (d == ' ' || d == '\n' || d == '\t' || d == '\r' || d == '"' || d == '[' ||
                    d == ']')
                    break;
                text.push_back(get());
            }
            return Token{std::move(text), false, start};
        }
        return std::nullopt;
    }

private:
    char peek() const { return m_text[m_position]; }
    char get() {
        const char c = m_text[m_position++];
        if (c == '\n') {
            ++m_location.line;
            m_location.column = 1;
        } else {
            ++m_location.column;
        }
        return c;
    }

    Token quoted(const Location &start) {
        std::string text;
        while (true) {
            if (m_position >= m_text.size())
                throw LocatedError(start.str(), "a string is not closed before the file ends");
            char c = get();
            if (c == '"')
                break;
            if (c == '\n')
                throw LocatedError(start.str(), "a string is not closed on its line");
            if (c == '\\') {
                if (m_position >= m_text.size())
                    throw LocatedError(start.str(), "the file ends inside an escape");
                const char escaped = get();
                switch (escaped) {
                case 'b':
                    c = '\b';
                    break;
                case 'f':
                    c = '\f';
                    break;
                case 'n':
                    c = '\n';
                    break;
                case 'r':
                    c = '\r';
                    break;
                case 't':
                    c = '\t';
                    break;
                case '\\':
                    c = '\\';
                    break;
                case '\'':
                    c = '\'';
                    break;
                case '"':
                    c = '"';
                    break;
                default:
                    throw LocatedError(m_location.str(),
                                       fmt::format("unknown escape '\\{}' in a string", escaped));
                }
            }
            text.push_back(c);
        }
        return Token{std::move(text), true, start};
    }

    std::string m_text;
    std::string m_folder;
    size_t m_position = 0;
    Location m_location;
};

/// The file stack and the directive grammar.
class Parser {
public:
    Parser(const std::function<void(const Directive &)> &visit, bool allowFiles)
        : m_visit(visit), m_allowFiles(allowFiles) {}

    void pushFile(const std::string &path, const Location *includedFrom) {
        if (int(m_files.size()) >= kMaxIncludeDepth)
            throw LocatedError(
                includedFrom ? includedFrom->str() : path,
                fmt::format("Include and Import nest deeper than {} files", kMaxIncludeDepth));
        const std::string canonical = canonicalPathOrSame(path);
        for (const auto &open : m_files)
            if (canonicalPathOrSame(open.tokenizer->file()) == canonical)
                throw LocatedError(includedFrom ? includedFrom->str() : path,
                                   fmt::format("'{}' includes itself", path));
        std::string text;
        try {
            text = readBinaryFile(path, "pbrt-v4 scene file");
            if (isGzip(text))
                text = inflateBytes(text, CompressedFormat::Gzip, path, size_t(1) << 32);
        } catch (const NoriException &error) {
            if (includedFrom)
                throw LocatedError(includedFrom->str(), error.what());
            throw;
        }
        const std::string folder = std::filesystem::path(path).parent_path().string();
        m_files.push_back(
            {std::make_unique<Tokenizer>(std::move(text), path, folder.empty() ? "." : folder),
             false});
    }

    void pushText(std::string_view text, const std::string &name) {
        m_files.push_back({std::make_unique<Tokenizer>(std::string(text), name, "."), false});
    }

    void run() {
        while (true) {
            std::optional<Token> token = next(false);
            flushImportEnds(); // the files the lookahead finished end before this token
            if (!token)
                break;
            if (token->quoted || token->text == "[" || token->text == "]")
                fail(*token, fmt::format("expected a directive, found {}", describe(*token)));
            directive(*token);
        }
    }

private:
    struct OpenFile {
        std::unique_ptr<Tokenizer> tokenizer;
        bool imported; ///< ends with a synthetic AttributeEnd
    };

    [[noreturn]] static void fail(const Token &token, const std::string &message) {
        throw LocatedError(token.location.str(), message);
    }
    [[noreturn]] void failAtEnd(const std::string &message) const {
        throw LocatedError(m_lastLocation.str(), message);
    }

    static std::string describe(const Token &token) {
        return token.quoted ? fmt::format("the string \"{}\"", token.text)
                            : fmt::format("'{}'", token.text);
    }

    /// The next token of the innermost open file; at a file's end, the file that
    /// included it continues. With `required`, the end of everything is an error.
    std::optional<Token> next(bool required) {
        if (m_unget)
            return std::exchange(m_unget, std::nullopt);
        while (!m_files.empty()) {
            if (std::optional<Token> token = m_files.back().tokenizer->next()) {
                m_lastLocation = token->location;
                return token;
            }
            if (m_files.back().imported)
                m_importEnds.push_back(m_lastLocation);
            m_files.pop_back();
        }
        if (required)
            failAtEnd("the file ends in the middle of a directive");
        return std::nullopt;
    }

    void unget(Token token) { m_unget = std::move(token); }

    static double number(const Token &token) {
        if (token.quoted || token.text == "[" || token.text == "]")
            fail(token, fmt::format("expected a number, found {}", describe(token)));
        const char *begin = token.text.c_str();
        char *end = nullptr;
        errno = 0;
        const double value = std::strtod(begin, &end);
        if (end != begin + token.text.size() || token.text.empty())
            fail(token, fmt::format("'{}' is not a number", token.text));
        if (!std::isfinite(value) || errno == ERANGE)
            fail(token, fmt::format("'{}' is not a finite number", token.text));
        return value;
    }

    static double integer(const Token &token) {
        const double value = number(token);
        if (value != std::floor(value) || value > double(INT_MAX) || value < double(INT_MIN) ||
            token.text.find_first_of(".eExXpP") != std::string::npos)
            fail(token, fmt::format("'{}' is not an integer", token.text));
        return value;
    }

    std::string quotedString(const char *what) {
        Token token = *next(true);
        if (!token.quoted)
            fail(token, fmt::format("expected {} in quotes, found {}", what, describe(token)));
        return token.text;
    }

    void directive(const Token &keyword) {
        const auto &table = signatures();
        const auto it = table.find(keyword.text);
        if (it == table.end()) {
            std::vector<std::string> names;
            for (const auto &entry : table)
                names.push_back(entry.first);
            fail(keyword, fmt::format("unknown directive '{}'{}", keyword.text,
                                      didYouMean(keyword.text, names)));
        }
        Directive d;
        d.name = keyword.text;
        d.location = keyword.location;
        switch (it->second.shape) {
        case Shape::Bare:
            break;
        case Shape::Numbers:
            for (int i = 0; i < it->second.numbers; ++i)
                d.numbers.push_back(number(*next(true)));
            break;
        case Shape::Matrix: {
            const Token open = *next(true);
            if (open.text != "[" || open.quoted)
                fail(open,
                     fmt::format("{} takes [ 16 numbers ], found {}", d.name, describe(open)));
            for (int i = 0; i < 16; ++i)
                d.numbers.push_back(number(*next(true)));
            const Token close = *next(true);
            if (close.text != "]" || close.quoted)
                fail(close, fmt::format("{} takes exactly 16 numbers, found {} after them", d.name,
                                        describe(close)));
            break;
        }
        case Shape::Name:
            d.strings.push_back(quotedString("a name"));
            break;
        case Shape::Names: {
            d.strings.push_back(quotedString("a medium name"));
            if (std::optional<Token> second = next(false)) {
                if (second->quoted)
                    d.strings.push_back(second->text);
                else
                    unget(*second);
            }
            break;
        }
        case Shape::TypeAndParams:
            d.strings.push_back(quotedString("a type"));
            d.parameters = parameters();
            break;
        case Shape::Texture:
            d.strings.push_back(quotedString("the texture's name"));
            d.strings.push_back(quotedString("the texture's type (\"float\" or \"spectrum\")"));
            d.strings.push_back(quotedString("the texture's class"));
            d.parameters = parameters();
            break;
        case Shape::Word: {
            const Token word = *next(true);
            if (word.quoted ||
                (word.text != "All" && word.text != "StartTime" && word.text != "EndTime"))
                fail(word, fmt::format("ActiveTransform takes All, StartTime or EndTime, found {}",
                                       describe(word)));
            d.strings.push_back(word.text);
            break;
        }
        case Shape::Option: {
            d.strings.push_back(quotedString("an option name"));
            const Token value = *next(true);
            if (value.quoted || value.text == "true" || value.text == "false")
                d.strings.push_back(value.text);
            else
                d.numbers.push_back(number(value));
            break;
        }
        case Shape::File: {
            const Token file = *next(true);
            if (!file.quoted)
                fail(file, fmt::format("{} takes a file name in quotes, found {}", d.name,
                                       describe(file)));
            if (!m_allowFiles)
                fail(file, fmt::format("{} is not available here", d.name));
            std::string path = file.text;
            if (!std::filesystem::path(path).is_absolute())
                path = (std::filesystem::path(m_files.back().tokenizer->folder()) / path).string();
            if (d.name == "Import")
                emitSynthetic("AttributeBegin", d.location);
            pushFile(path, &file.location);
            m_files.back().imported = d.name == "Import";
            return; // the included file's directives follow
        }
        }
        m_visit(d);
    }

    /// The synthetic AttributeEnd of every imported file that has ended, in order. Deferred
    /// until the directive being read (whose lookahead found the end) has been visited.
    void flushImportEnds() {
        for (const Location &location : m_importEnds)
            emitSynthetic("AttributeEnd", location);
        m_importEnds.clear();
    }

    void emitSynthetic(const char *name, const Location &location) {
        Directive d;
        d.name = name;
        d.location = location;
        m_visit(d);
    }

    std::vector<Parameter> parameters() {
        std::vector<Parameter> list;
        while (std::optional<Token> token = next(false)) {
            if (!token->quoted) {
                unget(*token);
                break;
            }
            list.push_back(parameter(*token));
        }
        return list;
    }

    Parameter parameter(const Token &declaration) {
        Parameter p;
        p.location = declaration.location;
        // "type name", separated by spaces or tabs.
        const std::string &text = declaration.text;
        const auto isSpace = [](char c) { return c == ' ' || c == '\t'; };
        size_t i = 0;
        while (i < text.size() && isSpace(text[i]))
            ++i;
        size_t j = i;
        while (j < text.size() && !isSpace(text[j]))
            ++j;
        const std::string type = text.substr(i, j - i);
        while (j < text.size() && isSpace(text[j]))
            ++j;
        size_t k = j;
        while (k < text.size() && !isSpace(text[k]))
            ++k;
        p.name = text.substr(j, k - j);
        while (k < text.size() && isSpace(text[k]))
            ++k;
        if (type.empty() || p.name.empty() || k != text.size())
            fail(declaration,
                 fmt::format("\"{}\" is not a parameter declaration \"type name\"", text));
        const auto &types = parameterTypes();
        const auto known = types.find(type);
        if (known == types.end()) {
            std::vector<std::string> names;
            for (const auto &entry : types)
                names.push_back(entry.first);
            fail(declaration, fmt::format("unknown parameter type '{}'{} in \"{}\"", type,
                                          didYouMean(type, names), text));
        }
        p.type = known->second;

        std::vector<Token> values;
        const Token first = *next(true);
        if (first.text == "[" && !first.quoted) {
            while (true) {
                const Token value = *next(true);
                if (value.text == "]" && !value.quoted)
                    break;
                if (value.text == "[" && !value.quoted)
                    fail(value, fmt::format("a '[' inside the values of \"{}\"", text));
                values.push_back(value);
            }
        } else {
            values.push_back(first);
        }
        for (const Token &value : values)
            addValue(p, value);
        checkKind(p, declaration);
        return p;
    }

    static void addValue(Parameter &p, const Token &value) {
        const auto mixed = [&](const char *expected) {
            fail(value, fmt::format("\"{} {}\" expects {}, found {}", p.type, p.name, expected,
                                    describe(value)));
        };
        if (value.quoted) {
            if (p.type == "bool" && (value.text == "true" || value.text == "false")) {
                if (!p.numbers.empty() || !p.strings.empty())
                    mixed("one kind of value");
                p.bools.push_back(value.text == "true");
                return;
            }
            if (!p.numbers.empty() || !p.bools.empty())
                mixed("one kind of value");
            p.strings.push_back(value.text);
        } else if (value.text == "true" || value.text == "false") {
            if (!p.numbers.empty() || !p.strings.empty())
                mixed("one kind of value");
            p.bools.push_back(value.text == "true");
        } else {
            if (!p.strings.empty() || !p.bools.empty())
                mixed("one kind of value");
            p.numbers.push_back(p.type == "integer" ? integer(value) : number(value));
        }
    }

    /// Each type's kind of values and, for tuples, a whole number of them.
    static void checkKind(const Parameter &p, const Token &declaration) {
        const size_t count = p.numbers.size() + p.strings.size() + p.bools.size();
        const auto wrong = [&](const char *expected) {
            fail(declaration, fmt::format("\"{} {}\" expects {}", p.type, p.name, expected));
        };
        if (count == 0)
            wrong("at least one value");
        static const std::map<std::string, size_t> kTuple = {
            {"integer", 1}, {"float", 1},   {"point2", 2}, {"vector2", 2},  {"point3", 3},
            {"vector3", 3}, {"normal3", 3}, {"rgb", 3},    {"blackbody", 1}};
        if (const auto tuple = kTuple.find(p.type); tuple != kTuple.end()) {
            if (p.numbers.size() != count)
                wrong("numbers");
            if (count % tuple->second != 0)
                wrong(tuple->second == 2   ? "pairs of numbers"
                      : tuple->second == 3 ? "triples of numbers"
                                           : "numbers");
        } else if (p.type == "string" || p.type == "texture") {
            if (p.strings.size() != count)
                wrong("strings in quotes");
        } else if (p.type == "bool") {
            if (p.bools.size() != count)
                wrong("true or false");
        } else if (p.type == "spectrum") {
            // (λ, value) pairs, or one named spectrum or .spd file.
            if (p.strings.size() == count) {
                if (count != 1)
                    wrong("one spectrum name or file");
            } else if (p.numbers.size() != count || count % 2 != 0) {
                wrong("(wavelength, value) pairs or a spectrum's name");
            }
        }
    }

    const std::function<void(const Directive &)> &m_visit;
    bool m_allowFiles;
    std::vector<OpenFile> m_files;
    std::optional<Token> m_unget;
    Location m_lastLocation;
    std::vector<Location> m_importEnds;
};

} // namespace

void parseFile(const std::string &path, const std::function<void(const Directive &)> &visit) {
    Parser parser(visit, true);
    parser.pushFile(path, nullptr);
    parser.run();
}

void parseString(std::string_view text, const std::string &name,
                 const std::function<void(const Directive &)> &visit) {
    Parser parser(visit, false);
    parser.pushText(text, name);
    parser.run();
}

const std::vector<std::string> &directiveNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const auto &entry : signatures())
            out.push_back(entry.first);
        return out;
    }();
    return names;
}

} // namespace nori::pbrt
