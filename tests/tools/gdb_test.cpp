// `ddmr-hil run --gdb PORT` end to end with Debian's avr-gdb in batch mode:
// a breakpoint in the encoder ISR while the robot moves, Count1 read twice,
// detach, and the run finishes normally; a busy port is refused with nothing
// written; gdb's kill ends the run with exit code 3 and the artifacts kept.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/types.h>

#include <chrono>
#include <memory>
#include <optional>
#include <regex>
#include <thread>

#include <nlohmann/json.hpp>

#include "support/loopback_tcp.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

using nlohmann::json;

std::string cli() { return sh_quote(cli_path().string()); }

/// `ddmr-hil <args>` started in the background; its pid and, once it has
/// ended, its exit code land in files. Ended (SIGTERM, by pid) if the test
/// leaves it running.
class BackgroundRun {
public:
    explicit BackgroundRun(const std::string& args) {
        const std::string script = "{ " + cli() + " " + args + " >" + sh_quote((dir_ / "out").string()) + " 2>" +
                                   sh_quote((dir_ / "err").string()) + " </dev/null & echo $! >" +
                                   sh_quote((dir_ / "pid").string()) + "; wait $!; echo $? >" +
                                   sh_quote((dir_ / "rc.tmp").string()) + "; mv " +
                                   sh_quote((dir_ / "rc.tmp").string()) + " " + sh_quote((dir_ / "rc").string()) +
                                   "; } >/dev/null 2>&1 &";
        started_ = std::system(script.c_str()) == 0;
    }
    ~BackgroundRun() {
        if (!exit_code(std::chrono::milliseconds(0))) {
            const std::string pid = read_text(dir_ / "pid");
            if (!pid.empty()) ::kill(static_cast<pid_t>(std::stol(pid)), SIGTERM);
            exit_code(std::chrono::seconds(10));
        }
    }
    BackgroundRun(const BackgroundRun&) = delete;
    BackgroundRun& operator=(const BackgroundRun&) = delete;

    bool started() const { return started_; }
    /// The exit code, once the process has ended within `limit`.
    std::optional<int> exit_code(std::chrono::milliseconds limit) {
        const auto deadline = std::chrono::steady_clock::now() + limit;
        for (;;) {
            const std::string rc = read_text(dir_ / "rc");
            if (!rc.empty()) return std::stoi(rc);
            if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
    std::string out() const { return read_text(dir_ / "out"); }
    std::string err() const { return read_text(dir_ / "err"); }

private:
    TempDir dir_;
    bool started_ = false;
};

/// avr-gdb in batch mode on the reference firmware, one -ex per command.
ProcessResult avr_gdb(uint16_t port, std::initializer_list<std::string> commands) {
    std::string line = "timeout 120 avr-gdb -batch -nx -ex " +
                       sh_quote("target remote 127.0.0.1:" + std::to_string(port));
    for (const auto& c : commands) line += " -ex " + sh_quote(c);
    return run_command(line + " " + sh_quote(firmware_elf().string()));
}

/// The values of gdb's "$N = value" lines, in order.
std::vector<long long> printed_values(const std::string& gdb_output) {
    std::vector<long long> values;
    const std::regex value_line(R"(\$\d+ = (-?\d+))");
    for (auto it = std::sregex_iterator(gdb_output.begin(), gdb_output.end(), value_line);
         it != std::sregex_iterator(); ++it) {
        values.push_back(std::stoll((*it)[1].str()));
    }
    return values;
}

constexpr auto kListenLimit = std::chrono::seconds(30);
constexpr auto kRunLimit = std::chrono::seconds(180);

class GdbOption : public ::testing::Test {
protected:
    /// Starts `ddmr-hil run --gdb` on a free port and waits until it listens.
    void start_run(const std::filesystem::path& out) {
        port_ = free_loopback_port();
        ASSERT_NE(port_, 0);
        run_ = std::make_unique<BackgroundRun>("run -q --gdb " + std::to_string(port_) + " --out " +
                                               sh_quote(out.string()));
        ASSERT_TRUE(run_->started());
        ASSERT_TRUE(wait_for_listener(port_, kListenLimit)) << run_->err();
    }

    TempDir dir_;
    uint16_t port_ = 0;
    std::unique_ptr<BackgroundRun> run_;
};

TEST_F(GdbOption, BreaksInEncoder1WhileTheRobotMovesAndTheRunFinishes) {
    const auto out = dir_ / "run";
    ASSERT_NO_FATAL_FAILURE(start_run(out));
    const uint16_t port = port_;
    BackgroundRun& run = *run_;
    // Bound to 127.0.0.1 only: no 0.0.0.0 (00000000) or IPv6 listener on the port.
    EXPECT_EQ(listening_addresses(port), std::vector<std::string>{kProcLoopback});
    EXPECT_NE(run.err().find("waiting for avr-gdb on 127.0.0.1:" + std::to_string(port) + " (loopback only)"),
              std::string::npos)
        << run.err();

    // Count1 has no type in the LTO build's debug info: read it as the sketch
    // declares it (unsigned long). encoder1() is `Count1++;` and runs once per
    // edge on pin 2, so two consecutive hits see consecutive values.
    const ProcessResult gdb = avr_gdb(port, {"break encoder1", "continue", "print (unsigned long)Count1",
                                             "continue", "print (unsigned long)Count1", "detach"});
    EXPECT_EQ(gdb.exit_code, 0) << gdb.out << gdb.err;
    EXPECT_NE(gdb.out.find("Breakpoint 1, encoder1 ()"), std::string::npos) << gdb.out;
    const auto values = printed_values(gdb.out);
    ASSERT_EQ(values.size(), 2u) << gdb.out;
    EXPECT_EQ(values[1], values[0] + 1) << gdb.out;
    EXPECT_NE(gdb.out.find("detached"), std::string::npos) << gdb.out;

    const auto rc = run.exit_code(kRunLimit);
    ASSERT_TRUE(rc.has_value()) << "the run did not end after gdb detached";
    EXPECT_EQ(*rc, 0) << run.err();
    const json s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["exit_reason"], "report_complete");
    // The robot drove its whole case after the debugging session.
    EXPECT_GT(s["firmware_report"]["count1"].get<double>(), 5000);
    EXPECT_EQ(s["loop_iterations"], 1200);
}

// Issue 19, item 8: the shipped tools/ddmr.gdbinit. A source-line
// breakpoint works (its line tables read up front: without them avr-gdb says
// "No source file named ddmr_tracking.ino"), it stops in main() because loop()
// is inlined, and its commands read the untyped globals.
TEST_F(GdbOption, TheShippedGdbinitBreaksOnASourceLineAndReadsThePose) {
    const auto out = dir_ / "run";
    ASSERT_NO_FATAL_FAILURE(start_run(out));
    std::string line = "timeout 120 avr-gdb -batch -nx -x " +
                       sh_quote((source_dir() / "tools/ddmr.gdbinit").string());
    for (const std::string& c : {"hil " + std::to_string(port_), std::string("break ddmr_tracking.ino:182"),
                                std::string("continue"), std::string("pose"), std::string("counts"),
                                std::string("where"), std::string("detach")}) {
        line += " -ex " + sh_quote(c);
    }
    const ProcessResult gdb = run_command(line + " " + sh_quote(firmware_elf().string()));
    EXPECT_EQ(gdb.exit_code, 0) << gdb.out << gdb.err;
    EXPECT_NE(gdb.out.find("Breakpoint 1, main () at "), std::string::npos) << gdb.out << gdb.err;
    EXPECT_NE(gdb.out.find("ddmr_tracking.ino:182"), std::string::npos) << gdb.out;
    EXPECT_NE(gdb.out.find("Ex 0.0000 m  Ey 0.0000 m  Theta "), std::string::npos) << gdb.out;
    EXPECT_NE(gdb.out.find("Count1 "), std::string::npos) << gdb.out;
    EXPECT_NE(gdb.out.find("main + "), std::string::npos) << gdb.out;  // where: inside main, loop() inlined
    const auto rc = run_->exit_code(kRunLimit);
    ASSERT_TRUE(rc.has_value());
    EXPECT_EQ(*rc, 0) << run_->err();
}

TEST_F(GdbOption, ABusyPortIsRefusedAndKillEndsTheRunWithExit3) {
    const auto first_out = dir_ / "first";
    ASSERT_NO_FATAL_FAILURE(start_run(first_out));
    const uint16_t port = port_;
    BackgroundRun& first = *run_;

    // A second run on the same port: exit 2, one line naming the port, nothing written.
    const auto second_out = dir_ / "second";
    expect_refused(cli() + " run -q ", " --out " + sh_quote(second_out.string()), second_out,
                   {{"--gdb " + std::to_string(port), "port " + std::to_string(port) + " on 127.0.0.1"}});

    // gdb's kill before the first instruction ends the first run: exit 3, a
    // distinct exit reason, the artifacts written.
    const ProcessResult gdb = avr_gdb(port, {"kill"});
    EXPECT_NE(gdb.out.find("killed"), std::string::npos) << gdb.out << gdb.err;
    const auto rc = first.exit_code(kRunLimit);
    ASSERT_TRUE(rc.has_value());
    EXPECT_EQ(*rc, 3);
    EXPECT_NE(first.err().find("killed by the debugger at cycle 0"), std::string::npos) << first.err();
    const json s = json::parse(read_text(first_out / "summary.json"));
    EXPECT_EQ(s["exit_reason"], "killed_by_debugger");
    EXPECT_EQ(s["cycles_total"], 0);
    EXPECT_TRUE(std::filesystem::exists(first_out / "truth.csv"));
}

TEST_F(GdbOption, HelpSaysWhatListensWhereAndThatItIsSlower) {
    for (const char* sub : {"run", "profile"}) {
        const ProcessResult r = run_command(cli() + " " + sub + " --help");
        ASSERT_EQ(r.exit_code, 0);
        const auto at = r.out.find("--gdb PORT");
        ASSERT_NE(at, std::string::npos) << sub << ": " << r.out;
        const std::string text = r.out.substr(at, r.out.find("\n  -", at + 1) - at);
        EXPECT_NE(text.find("127.0.0.1:PORT"), std::string::npos) << text;
        EXPECT_NE(text.find("loopback only"), std::string::npos) << text;
        EXPECT_NE(text.find("slower"), std::string::npos) << text;
    }
}

TEST_F(GdbOption, PortOutOfRangeIsRefused) {
    const auto out = dir_ / "run";
    expect_refused(cli() + " run -q ", " --out " + sh_quote(out.string()), out,
                   {{"--gdb 0", "--gdb: Value 0 not in range 1 to 65535"},
                    {"--gdb 65536", "--gdb: Value 65536 not in range"},
                    {"--gdb http", "--gdb: Value http"}});
}

}  // namespace
}  // namespace ddmr::test
