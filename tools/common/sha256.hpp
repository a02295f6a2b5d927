#pragma once
// SHA-256 of a file, as lowercase hex (OpenSSL's EVP interface).
#include <filesystem>
#include <string>

namespace ddmr::tools {

/// Throws std::runtime_error naming the file if it cannot be read.
std::string sha256_file_hex(const std::filesystem::path& path);

}  // namespace ddmr::tools
