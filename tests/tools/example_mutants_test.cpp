// The shipped examples catch the wiring mistakes they are written to catch:
// each mutant is the example with one thing changed, run as a user runs it.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "support/scenario_cli.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "the example no longer has: " << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

// Adafruit Motor Shield v1 (firmware/examples/afmotor_shield_v1): M1's A and
// B bits swapped (the 74HC595's Q2 and Q3 on the L293D's inputs) turn the
// right wheel backwards while the sketch says FORWARD.
TEST(ExampleMutants, AfmotorShieldWithOneMotorsABitsSwappedFailsItsScenario) {
    const fs::path example = source_dir() / "firmware/examples/afmotor_shield_v1";
    TempDir dir;
    const fs::path sketch_dir = dir / "afmotor_shield_v1";  // Arduino: the sketch in a folder of its name
    fs::create_directories(sketch_dir);
    fs::copy_file(example / "afmotor_shield_v1.ino", sketch_dir / "afmotor_shield_v1.ino");
    fs::copy_file(example / "scenario.yaml", sketch_dir / "scenario.yaml");
    std::ofstream(sketch_dir / "board.yaml")
        << replaced(read_text(example / "board.yaml"), "IN1: shield.Q2, IN2: shield.Q3", "IN1: shield.Q3, IN2: shield.Q2");
    const auto r = scenario(sh_quote((sketch_dir / "scenario.yaml").string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const auto result = result_of(dir / "out" / "afmotor_shield_v1");
    const std::string message = result.at("message");
    EXPECT_NE(message.find("expected right.wheel_rad_s in [2.65, 2.93], got -2.7"), std::string::npos) << message;
}

}  // namespace
}  // namespace ddmr::test
