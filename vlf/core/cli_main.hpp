// cli_main.hpp — the shared tail of the executables' main(): parse the command line, run,
// and turn every failure into one line on stderr with the documented exit code
// (0 success or --help, 2 bad input of any kind, 1 internal error). Header-only; included
// by the executables, which link CLI11.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "vlf/core/error.hpp"

namespace vlf {

template <class Run>
int cli_main(CLI::App& app, int argc, char** argv, const char* program, Run&& run) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        std::fputs(app.help().c_str(), stdout);
        return 0;
    } catch (const CLI::ParseError& e) {
        // CLI11 words an option given twice as "At Most 1 required but received 2".
        std::string what = e.what();
        const size_t at = what.find("At Most 1 required but received");
        if (at != std::string::npos) what = what.substr(0, at) + "given more than once";
        std::fprintf(stderr, "%s: %s\n", program, what.c_str());
        return 2;
    }
    try {
        return run();
    } catch (const Error& e) {
        std::fprintf(stderr, "%s: %s\n", program, e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: internal error: %s\n", program, e.what());
        return 1;
    }
}

}  // namespace vlf
