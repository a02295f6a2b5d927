// write_file_atomic / prepare_output_dir / check_output_file: all or nothing,
// and clear errors.
#include "common/atomic_file.hpp"

#include <gtest/gtest.h>

#include "support/process.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {
namespace {

TEST(AtomicFile, WritesTheWholeContentAndNoTempFile) {
    TempDir dir;
    tools::write_file_atomic(dir / "a.txt", "hello\n");
    EXPECT_EQ(read_text(dir / "a.txt"), "hello\n");
    tools::write_file_atomic(dir / "a.txt", "replaced");
    EXPECT_EQ(read_text(dir / "a.txt"), "replaced");
    int files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
        (void)e;
        ++files;
    }
    EXPECT_EQ(files, 1);
}

TEST(AtomicFile, FailureNamesThePathAndKeepsTheOldFile) {
    TempDir dir;
    tools::write_file_atomic(dir / "keep.txt", "old");
    try {
        tools::write_file_atomic(dir / "no-such-dir" / "x.txt", "new");
        FAIL() << "write into a missing folder succeeded";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("no-such-dir"), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_text(dir / "keep.txt"), "old");
}

TEST(AtomicFile, OutputDirThatIsAFileIsRefused) {
    TempDir dir;
    tools::write_file_atomic(dir / "file", "x");
    try {
        tools::prepare_output_dir(dir / "file");
        FAIL() << "a file was accepted as output folder";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("not a folder"), std::string::npos) << e.what();
    }
}

TEST(AtomicFile, OutputDirIsCreatedWithParents) {
    TempDir dir;
    tools::prepare_output_dir(dir / "a" / "b");
    EXPECT_TRUE(std::filesystem::is_directory(dir / "a" / "b"));
}

TEST(AtomicFile, OutputDirCheckCreatesNothing) {
    TempDir dir;
    tools::check_output_dir(dir / "a" / "b");  // its nearest existing part is writable
    EXPECT_FALSE(std::filesystem::exists(dir / "a"));
    tools::write_file_atomic(dir / "f", "x");
    try {
        tools::check_output_dir(dir / "f" / "sub");
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/f is not a folder"), std::string::npos) << e.what();
    }
    EXPECT_THROW(tools::check_output_dir(dir / "f"), std::runtime_error);
}

TEST(AtomicFile, OutputFileCheckNeedsAnExistingFolderAndCreatesNothing) {
    TempDir dir;
    EXPECT_NO_THROW(tools::check_output_file(dir / "run.vcd"));
    EXPECT_FALSE(std::filesystem::exists(dir / "run.vcd"));
    try {
        tools::check_output_file(dir / "missing" / "run.vcd");
        FAIL() << "a missing folder was accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
    EXPECT_THROW(tools::check_output_file(dir.path()), std::runtime_error);  // a folder, not a file
}

}  // namespace
}  // namespace ddmr::test
