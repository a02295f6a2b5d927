#include "common/private_dir.hpp"

#include <stdlib.h>  // mkdtemp

#include <cerrno>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

namespace ddmr::tools {

std::filesystem::path make_private_dir(const std::string& prefix) {
    std::string tmpl = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (::mkdtemp(tmpl.data()) == nullptr) {
        throw std::runtime_error(fmt::format("cannot create a private folder {}: {}", tmpl,
                                             std::error_code(errno, std::generic_category()).message()));
    }
    return tmpl;
}

PrivateDir::~PrivateDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

}  // namespace ddmr::tools
