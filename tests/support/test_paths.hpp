#pragma once
// Paths the tests need, baked in by CMake (tests/CMakeLists.txt).
#include <filesystem>

namespace ddmr::test {

inline std::filesystem::path source_dir() { return DDMR_TEST_SOURCE_DIR; }
inline std::filesystem::path shared_dir() { return DDMR_TEST_SHARED_DIR; }
inline std::filesystem::path firmware_elf() { return DDMR_TEST_FIRMWARE_ELF; }
inline std::filesystem::path cli_path() { return DDMR_TEST_CLI; }
inline std::filesystem::path test_firmware_dir() { return DDMR_TEST_FIRMWARE_DIR; }

}  // namespace ddmr::test
