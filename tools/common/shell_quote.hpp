#pragma once
// A text quoted for a POSIX shell, for command lines ddmr-hil prints for a
// person to paste (compare's `sim` command) and the tests run.
#include <string>

namespace ddmr::tools {

/// `text` as is when it is made only of characters no shell treats
/// specially, else in single quotes (a ' inside as '\'').
inline std::string shell_quote(const std::string& text) {
    if (!text.empty() && text.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_./-=:,") ==
                             std::string::npos) {
        return text;
    }
    std::string q = "'";
    for (const char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace ddmr::tools
