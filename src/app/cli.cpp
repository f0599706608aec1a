#include "app/cli.h"
#include "app/program.h"
#include <nori/common.h>

#include <regex>

namespace nori {

namespace {

/// Width of the option column of the help, and of the whole help.
constexpr size_t kOptionColumn = 28, kHelpWidth = 100;

/// CLI11's message, in the words the rest of nori uses for the same mistakes.
std::string describe(const CLI::ParseError &error) {
    std::string message = error.what();
    // "The following arguments were not expected: --sppp x"
    static const std::regex kExtras("The following arguments? (were|was) not expected: (.*)");
    std::smatch match;
    if (std::regex_match(message, match, kExtras)) {
        const std::vector<std::string> extras = CLI::detail::split(match[2].str(), ' ');
        for (const std::string &extra : extras)
            if (extra.size() > 1 && extra[0] == '-')
                return fmt::format("unknown option '{}'", extra);
        return fmt::format("unexpected argument '{}'", extras.front());
    }
    return message;
}

/// The text broken into lines of at most `width` characters, at spaces.
std::string wrap(const std::string &text, size_t width) {
    std::string wrapped, line;
    for (const std::string &word : CLI::detail::split(text, ' ')) {
        if (!line.empty() && line.size() + 1 + word.size() > width) {
            wrapped += line + "\n";
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    return wrapped + line;
}

/// Breaks the descriptions of the options of `app` and of its subcommands into lines
/// that fit the help (CLI11 leaves each on one line).
void wrapDescriptions(CLI::App &app) {
    // A description laid out by hand (a table) is kept as it is.
    if (app.get_parent() == nullptr && app.get_description().find('\n') == std::string::npos)
        app.description(wrap(app.get_description(), kHelpWidth));
    for (CLI::Option *option : app.get_options())
        option->description(wrap(option->get_description(), kHelpWidth - kOptionColumn));
    for (CLI::App *sub : app.get_subcommands({})) {
        sub->description(wrap(sub->get_description(), kHelpWidth - kOptionColumn));
        wrapDescriptions(*sub);
    }
}

/// Help laid out alike in every program: the option column, no "REQUIRED" labels.
void configureCommandLine(CLI::App &app) {
    app.get_formatter()->column_width(kOptionColumn);
    app.get_formatter()->label("REQUIRED", "");
    app.option_defaults()->always_capture_default(false);
}

} // namespace

int runCommandLine(int argc, char **argv, const std::string &name, const std::string &description,
                   const std::function<void(CLI::App &)> &define,
                   const std::function<int(const CLI::App &)> &run, int errorStatus) {
    return runProgram(
        [&] {
            CLI::App app(description, name);
            configureCommandLine(app);
            define(app); // subcommands inherit the formatter set above
            wrapDescriptions(app);
            try {
                app.parse(argc, argv);
            } catch (const CLI::CallForHelp &) {
                // The help of the subcommand it was asked for (nori merge --help).
                const CLI::App *target = &app;
                while (!target->get_subcommands().empty())
                    target = target->get_subcommands().front();
                fmt::print("{}", target->help());
                return 0;
            } catch (const CLI::ParseError &error) {
                // A subcommand's own errors name the subcommand's help.
                std::string program = app.get_name();
                for (const CLI::App *sub : app.get_subcommands())
                    program += " " + sub->get_name();
                fmt::print(stderr, "Error: {} (see {} --help)\n", describe(error), program);
                return errorStatus;
            }
            return run(app);
        },
        errorStatus);
}

} // namespace nori
