// The programs' command lines, parsed by CLI11 (Debian's libcli11-dev): every program
// gets the same --help layout and the same form of errors, "Error: what (see PROGRAM
// --help)", and an exit status the caller chooses.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace nori {

/// What a program's main() does with its command line: makes the CLI11 application
/// `name`, described by `description`; lets `define` add its options and subcommands;
/// parses argv into them; runs `run` with the parsed application. --help prints the help
/// of the command it was asked for on stdout and returns 0; a command-line error (an
/// unknown option, a missing value) prints "Error: ... (see NAME --help)" on stderr and
/// returns `errorStatus`; an exception from `define` or `run` is reported as runProgram
/// reports it, with `errorStatus` too.
int runCommandLine(int argc, char **argv, const std::string &name, const std::string &description,
                   const std::function<void(CLI::App &)> &define,
                   const std::function<int(const CLI::App &)> &run, int errorStatus = 1);

} // namespace nori
