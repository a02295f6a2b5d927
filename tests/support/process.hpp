#pragma once
// Runs a command line through /bin/sh and captures its exit code, stdout and
// stderr, for tests of the command-line front end.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <sstream>
#include <string>

#include "common/shell_quote.hpp"
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

/// Every regular file below `dir`, by its relative path, with its bytes:
/// two output folders are byte-identical if their trees are equal.
inline std::map<std::string, std::string> file_tree(const std::filesystem::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) files[std::filesystem::relative(e.path(), dir).string()] = read_text(e.path());
    }
    return files;
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

/// A bad-input case of a subcommand: its arguments and the text the one-line
/// error must contain.
struct BadArgs {
    std::string args;
    std::string named;
};

/// Runs `command_prefix + args + out_option` for each case and checks what
/// every refusal must do: exit 2, one line on stderr naming the problem, and
/// nothing created at `out`.
inline void expect_refused(const std::string& command_prefix, const std::string& out_option,
                           const std::filesystem::path& out, std::initializer_list<BadArgs> cases) {
    for (const BadArgs& b : cases) {
        const ProcessResult r = run_command(command_prefix + b.args + out_option);
        EXPECT_EQ(r.exit_code, 2) << b.args;
        EXPECT_NE(r.err.find(b.named), std::string::npos) << b.args << ": " << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
        EXPECT_FALSE(std::filesystem::exists(out)) << b.args;
    }
}

/// Quotes a path for /bin/sh (the tool's own quoting).
inline std::string sh_quote(const std::string& s) { return tools::shell_quote(s); }

}  // namespace ddmr::test
