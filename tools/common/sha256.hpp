#pragma once
// SHA-256 as lowercase hex (OpenSSL's EVP interface): of one file, or of a
// sequence of texts and files fed to a Sha256 in order (a cache key over a
// whole folder).
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace ddmr::tools {

/// An incremental SHA-256. Throws std::runtime_error if OpenSSL fails.
class Sha256 {
public:
    Sha256();
    ~Sha256();
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;

    void update(std::string_view bytes);
    /// The file's bytes; throws std::runtime_error naming it if it cannot be read.
    void update_file(const std::filesystem::path& path);
    /// The digest of everything fed so far, as lowercase hex (once).
    std::string hex();

private:
    struct Ctx;
    std::unique_ptr<Ctx> ctx_;
};

/// Throws std::runtime_error naming the file if it cannot be read.
std::string sha256_file_hex(const std::filesystem::path& path);

}  // namespace ddmr::tools
