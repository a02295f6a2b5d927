#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

namespace ddmr::tools {
namespace fs = std::filesystem;

namespace {
[[noreturn]] void fail(const fs::path& path, const char* what, int err) {
    throw std::runtime_error(std::string("cannot write ") + path.string() + ": " + what + ": " +
                             std::strerror(err));
}
}  // namespace

void write_file_atomic(const fs::path& path, std::string_view content) {
    fs::path tmp = path;
    tmp += ".tmp-" + std::to_string(::getpid());
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) fail(path, "open", errno);
    const char* p = content.data();
    std::size_t left = content.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            ::close(fd);
            ::unlink(tmp.c_str());
            fail(path, "write", err);
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        fail(path, "sync", err);
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        fail(path, "rename", err);
    }
}

AtomicFileWriter::AtomicFileWriter(fs::path path) : path_(std::move(path)) {
    tmp_ = path_;
    tmp_ += ".tmp-" + std::to_string(::getpid());
    file_ = std::fopen(tmp_.c_str(), "wb");
    if (file_ == nullptr) fail(path_, "open", errno);
}

AtomicFileWriter::~AtomicFileWriter() {
    if (file_ != nullptr) std::fclose(file_);
    if (!committed_) ::unlink(tmp_.c_str());
}

void AtomicFileWriter::write(std::string_view bytes) noexcept {
    if (error_ != 0 || file_ == nullptr || bytes.empty()) return;
    if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) error_ = errno != 0 ? errno : EIO;
}

void AtomicFileWriter::commit() {
    if (error_ != 0) fail(path_, "write", error_);
    if (std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) fail(path_, "sync", errno);
    const int rc = std::fclose(file_);
    file_ = nullptr;
    if (rc != 0) fail(path_, "close", errno);
    if (::rename(tmp_.c_str(), path_.c_str()) != 0) fail(path_, "rename", errno);
    committed_ = true;
}

void prepare_output_dir(const fs::path& dir) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
        throw std::runtime_error("output folder " + dir.string() + " exists and is not a folder");
    }
    fs::create_directories(dir, ec);
    if (ec) {
        throw std::runtime_error("cannot create output folder " + dir.string() + ": " + ec.message());
    }
    if (::access(dir.c_str(), W_OK) != 0) {
        throw std::runtime_error("output folder " + dir.string() + " is not writable: " +
                                 std::strerror(errno));
    }
}

void check_output_dir(const fs::path& dir) {
    std::error_code ec;
    if (dir.empty()) throw std::runtime_error("the output folder is an empty name");
    fs::path existing = dir;
    while (!fs::exists(existing, ec)) {
        const fs::path parent = existing.has_parent_path() ? existing.parent_path() : fs::path(".");
        if (parent == existing) break;
        existing = parent;
    }
    if (!fs::is_directory(existing, ec)) {
        throw std::runtime_error(existing == dir ? "output folder " + dir.string() + " exists and is not a folder"
                                                 : "output folder " + dir.string() + ": " + existing.string() +
                                                       " is not a folder");
    }
    if (::access(existing.c_str(), W_OK) != 0) {
        throw std::runtime_error("output folder " + dir.string() + ": " + existing.string() + " is not writable: " +
                                 std::strerror(errno));
    }
}

void check_output_file(const fs::path& file) {
    std::error_code ec;
    if (file.empty() || !file.has_filename()) throw std::runtime_error("'" + file.string() + "' names no file");
    if (fs::is_directory(file, ec)) throw std::runtime_error("a folder, not a file");
    const fs::path parent = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    if (!fs::is_directory(parent, ec)) {
        throw std::runtime_error("folder " + parent.string() + " does not exist");
    }
    if (::access(parent.c_str(), W_OK) != 0) {
        throw std::runtime_error("folder " + parent.string() + " is not writable: " + std::strerror(errno));
    }
}

}  // namespace ddmr::tools
