#include "common/visible_files.hpp"

#include <algorithm>

namespace ddmr::tools {
namespace fs = std::filesystem;

std::vector<fs::path> visible_files(const fs::path& dir) {
    std::vector<fs::path> files;
    for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
        if (it->path().filename().string().rfind('.', 0) == 0) {
            if (it->is_directory()) it.disable_recursion_pending();
            continue;
        }
        if (it->is_regular_file()) files.push_back(it->path().lexically_relative(dir));
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace ddmr::tools
