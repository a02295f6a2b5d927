#pragma once
// A private folder under the system's temporary folder ($TMPDIR), made with
// mkdtemp (mode 0700, a name no other process gets): the Python API's
// staging folder, the fast-forward verification's second run.

#include <filesystem>
#include <string>

namespace ddmr::tools {

/// Creates "<tmp>/<prefix>-XXXXXX"; throws std::runtime_error naming it and why.
std::filesystem::path make_private_dir(const std::string& prefix);

/// make_private_dir() for a scope: removed, with what it holds, at its end.
class PrivateDir {
public:
    explicit PrivateDir(const std::string& prefix) : path_(make_private_dir(prefix)) {}
    ~PrivateDir();
    PrivateDir(const PrivateDir&) = delete;
    PrivateDir& operator=(const PrivateDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

}  // namespace ddmr::tools
