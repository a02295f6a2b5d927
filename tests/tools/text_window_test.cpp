// Tests for tools/scenario/text_window: the bounded end of the serial text
// that wait-serial and expect-serial search.
#include <gtest/gtest.h>

#include <string>

#include "scenario/text_window.hpp"

namespace ddmr::tools::scenario {
namespace {

void append(TextWindow& w, const std::string& s) {
    for (const char c : s) w.push_back(c);
}

TEST(TextWindow, KeepsTheLastCapacityBytesWithTheirPositions) {
    TextWindow w(4);
    append(w, "abcdefghij");  // 10 bytes: the view is the last 4, "ghij", from position 6
    EXPECT_EQ(w.size(), 10U);
    EXPECT_EQ(w.view(), "ghij");
    EXPECT_EQ(w.view_begin(), 6U);
    EXPECT_EQ(w.find("hi", 0), 7U);     // a search from before the view starts at the view
    EXPECT_EQ(w.find("hi", 8), std::nullopt);
    EXPECT_EQ(w.find("cd", 0), std::nullopt);  // dropped
    EXPECT_EQ(w.find("fg", 0), std::nullopt);  // straddles the view's start
    EXPECT_EQ(w.find("", 10), 10U);
    EXPECT_EQ(w.find("", 11), std::nullopt);
    EXPECT_TRUE(w.ends_with("ij"));
    EXPECT_FALSE(w.ends_with("fghij"));  // longer than the view
}

TEST(TextWindow, ShortTextIsWhole) {
    TextWindow w(64);
    append(w, "0.6m\r\nEND\r\n");
    EXPECT_EQ(w.view(), "0.6m\r\nEND\r\n");
    EXPECT_EQ(w.view_begin(), 0U);
    EXPECT_EQ(w.find("END", 0), 6U);
    EXPECT_EQ(w.find("END", 7), std::nullopt);
}

TEST(TextWindow, MemoryStaysBelowTwiceTheCapacity) {
    TextWindow w(1000);
    for (int i = 0; i < 1'000'000; ++i) w.push_back(static_cast<char>('a' + i % 26));
    EXPECT_EQ(w.size(), 1'000'000U);
    EXPECT_EQ(w.view().size(), 1000U);
    EXPECT_EQ(w.view().back(), static_cast<char>('a' + 999'999 % 26));
    w.clear();
    EXPECT_TRUE(w.empty());
    EXPECT_EQ(w.view(), "");
}

TEST(TextWindow, ZeroCapacityIsRefused) { EXPECT_THROW(TextWindow(0), std::invalid_argument); }

}  // namespace
}  // namespace ddmr::tools::scenario
