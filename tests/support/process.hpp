#pragma once
// Runs a command line through /bin/sh and captures its exit code, stdout and
// stderr, for tests of the command-line front end.
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "support/temp_dir.hpp"

namespace ddmr::test {

struct ProcessResult {
    int exit_code = -1;
    std::string out;
    std::string err;
};

inline std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline ProcessResult run_command(const std::string& command_line) {
    TempDir capture;
    const std::string cmd = command_line + " >" + (capture / "out").string() + " 2>" +
                            (capture / "err").string() + " </dev/null";
    const int status = std::system(cmd.c_str());
    ProcessResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_text(capture / "out");
    r.err = read_text(capture / "err");
    return r;
}

/// Quotes a path for /bin/sh.
inline std::string sh_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) {
        if (c == '\'') q += "'\\''"; else q += c;
    }
    return q + "'";
}

}  // namespace ddmr::test
