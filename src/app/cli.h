// The programs' command lines, parsed by CLI11 (Debian's libcli11-dev): every program
// gets the same --help layout and the same form of errors, "Error: what (see PROGRAM
// --help)", and an exit status the caller chooses.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace nori {

/// Parses the command line into `app` and runs `body`, with runProgram's handling of
/// errors. --help prints the help on stdout and returns 0; a command-line error (an
/// unknown option, a missing value) prints "Error: ... (see NAME --help)" on stderr and
/// returns `errorStatus`, as does any exception `body` throws.
int runCommandLine(CLI::App &app, int argc, char **argv, const std::function<int()> &body,
                   int errorStatus = 1);

/// The application every program starts from: its name and one paragraph on what it
/// does, --help, and options listed in the order they are added.
void configureCommandLine(CLI::App &app);

/// Breaks the descriptions of the options of `app` and of its subcommands into lines
/// that fit the help's 100 columns (CLI11 leaves them as one line each).
void wrapDescriptions(CLI::App &app);

} // namespace nori
