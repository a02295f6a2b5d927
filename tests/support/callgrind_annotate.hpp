#pragma once
// Runs valgrind's callgrind_annotate (Debian package valgrind) on a callgrind
// profile and reads its report back, for the tests of callgrind.out.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "hil/cycle_time.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {

/// callgrind_annotate's report of `text`: the program total and each
/// "file:function" row's cost (self, or inclusive with --inclusive=yes).
struct CallgrindAnnotation {
    hil::Cycles total = 0;
    std::map<std::string, hil::Cycles> functions;  ///< by the name after the last ':' (the file dropped)
};

inline hil::Cycles callgrind_count(const std::string& s) {
    std::string digits;
    for (const char ch : s) {
        if (ch != ',') digits += ch;
    }
    return std::stoull(digits);
}

inline CallgrindAnnotation callgrind_annotate(const std::string& text, bool inclusive) {
    TempDir dir;
    const auto file = dir / "callgrind.out";
    std::ofstream(file) << text;
    // From the temporary folder: in a folder where the profile's source files
    // resolve (the source tree), callgrind_annotate 3.19 lists a function
    // under two file names with --inclusive=yes, and its rows add up twice.
    const ProcessResult r = run_command("cd " + sh_quote(dir.path().string()) +
                                        " && callgrind_annotate --auto=no --threshold=100" +
                                        (inclusive ? " --inclusive=yes " : " ") + sh_quote(file.string()));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("WARNING"), std::string::npos) << r.err;  // no line it could not read
    CallgrindAnnotation a;
    const std::regex total(R"(^\s*([0-9,]+)(?: \([0-9.]+%\))?\s+PROGRAM TOTALS)");
    const std::regex row(R"(^\s*([0-9,]+)(?: \([0-9.]+%\))?\s+(\S.*):([^:]+)$)");
    std::istringstream lines(r.out);
    for (std::string line; std::getline(lines, line);) {
        std::smatch m;
        if (std::regex_search(line, m, total)) {
            a.total = callgrind_count(m[1]);
        } else if (std::regex_match(line, m, row)) {
            a.functions[m[3]] += callgrind_count(m[1]);
        }
    }
    EXPECT_GT(a.total, 0u) << r.out;
    return a;
}

}  // namespace ddmr::test
