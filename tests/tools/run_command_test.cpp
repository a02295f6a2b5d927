// `ddmr-hil run` end to end: the artifacts of a good run, determinism, and
// bad input refused with one line naming the problem, nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/sha256.hpp"
#include "support/callgrind_annotate.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"
#include "support/vcd_reader.hpp"

namespace ddmr::test {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

std::string cli() { return sh_quote(cli_path().string()); }

int line_count(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

/// `run --case 1 --vcd`, run once per test process and shared by the tests
/// that check its artifacts.
struct Case1Run {
    TempDir dir;
    std::filesystem::path out = dir / "run";
    std::filesystem::path vcd = dir / "run.vcd";
    ProcessResult result = run_command(cli() + " run --case 1 -q --out " + sh_quote(out.string()) + " --vcd " +
                                       sh_quote(vcd.string()));
};

const Case1Run& case1_run() {
    static const Case1Run run;
    return run;
}

// Case 1's outputs, byte for byte (issue 32: the engine's refactoring kept
// them). A change that alters them on purpose updates these hashes and says
// why in its commit.
TEST(RunCommand, Case1OutputsHaveTheCommittedHashes) {
    const auto& out = case1_run().out;
    ASSERT_EQ(case1_run().result.exit_code, 0) << case1_run().result.err;
    const std::map<std::string, std::string> want = {
        {"uart.txt", "803be92871378cdc2bdcc5e95abc18e15e4f0bf150c50724191407c9416cab0e"},
        {"eeprom.bin", "002eb0e1c733a6c2f0c87e51ac8e008189e2d31bb1de3576065a6b9b365fb249"},
        {"truth.csv", "ba5315ba843fba65876ddb831f2fca42565e88bc39efd410ac7ebbe347fbcd05"},
        {"firmware.csv", "6a5453f06c4db7b4b02c0c4f91e1d1cd8f892a5aaa70decdf440ec2c4f9d54ce"},
        {"eeprom_log.csv", "56ddb1dbf674bd2003034a5c076e111e46bd89e76bf6f1717ef0fd200e026d5e"},
    };
    for (const auto& [file, hash] : want) EXPECT_EQ(tools::sha256_file_hex(out / file), hash) << file;
}

TEST(RunCommand, Case1WritesUartEepromAndSummary) {
    const auto& out = case1_run().out;
    const auto& r = case1_run().result;
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string uart = read_text(out / "uart.txt");
    EXPECT_EQ(uart.rfind("0.6m\r\nEND\r\n", 0), 0u) << uart.substr(0, 40);
    // The last line is the erased pair at bytes 240/740: 255 / 250 = 1.020.
    EXPECT_EQ(uart.substr(uart.size() - 15), "1.020 , 1.020\r\n");
    EXPECT_EQ(read_text(out / "eeprom.bin").size(), 1024u);

    const json s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["exit_reason"], "report_complete");
    EXPECT_EQ(s["firmware"]["flash_bytes"], 9864);
    EXPECT_EQ(s["firmware"]["sha256"].get<std::string>().size(), 64u);
    EXPECT_EQ(s["firmware"]["path"], firmware_elf().string());
    EXPECT_GT(s["cycles_total"].get<uint64_t>(), 16'000'000ull * 17);  // 5 s boot + 12 s run
    EXPECT_NEAR(s["sim_seconds"].get<double>(), s["cycles_total"].get<double>() / 16e6, 1e-9);
    EXPECT_GT(s["wall_seconds"].get<double>(), 0.0);
    EXPECT_GT(s["mcycles_per_s"].get<double>(), 0.0);
    const json& rep = s["firmware_report"];
    // Closed loop: the wheels turned (about 7,500 and 5,700 edges).
    EXPECT_GT(rep["count1"].get<double>(), 5000);
    EXPECT_GT(rep["count2"].get<double>(), 4000);
    EXPECT_EQ(s["loop_iterations"], 1200);
    EXPECT_EQ(s["eeprom_log_samples"], 120);
    for (const char* ch : {"channel1", "channel2"}) {
        const json& e = s["encoder"][ch];
        EXPECT_GE(e["edges_injected"].get<int>(), e["isr_count"].get<int>() + e["lost_edges"].get<int>());
    }
    // The firmware's end pose is its Ex, Ey, Theta as it prints them (4 decimals).
    EXPECT_NEAR(s["end_pose_firmware"]["x_m"].get<double>(), rep["ex"].get<double>(), 5e-5);
    EXPECT_NEAR(s["end_pose_firmware"]["y_m"].get<double>(), rep["ey"].get<double>(), 5e-5);
    EXPECT_NEAR(s["end_pose_firmware"]["theta_rad"].get<double>(), rep["theta"].get<double>(), 5e-5);
    EXPECT_TRUE(s["end_pose_truth"].contains("x_m"));
    // 1 kHz of truth over ~19.6 s, one firmware row per iteration, 120 log rows.
    const auto lines = [](const std::string& t) { return std::count(t.begin(), t.end(), '\n'); };
    EXPECT_GT(lines(read_text(out / "truth.csv")), 19000);
    EXPECT_EQ(read_text(out / "truth.csv").rfind("t_s,x_m,y_m,theta_rad,v_m_s,omega_rad_s,ia1_A,ia2_A,"
                                                  "wheel1_rad_s,wheel2_rad_s,vbatt_V,edges1,edges2,duty1,"
                                                  "duty2,dir1,dir2\n", 0), 0u);
    // Issue 19, item 3: one row per loop iteration (an increase of t), 1200,
    // as loop_iterations says: the sketch zeroing t after its report is no
    // iteration and has no row. The EEPROM log's count is the same everywhere.
    const std::string fw = read_text(out / "firmware.csv");
    EXPECT_EQ(lines(fw), 1 + 1200);
    const std::string last_row = fw.substr(fw.rfind('\n', fw.size() - 2) + 1);
    EXPECT_EQ(last_row.rfind("1200,", 0), 0U) << last_row;
    EXPECT_NE(r.out.find(", 120 EEPROM log samples\n"), std::string::npos) << r.out;
    // isr.json: the INT0/INT1 vector entries are the encoder ISR counts.
    const json isr = json::parse(read_text(out / "isr.json"));
    std::map<std::string, uint64_t> entries;
    for (const auto& v : isr["vectors"]) entries[v["name"].get<std::string>()] = v["count"].get<uint64_t>();
    EXPECT_EQ(entries["INT0"], s["encoder"]["channel1"]["isr_count"].get<uint64_t>());
    EXPECT_EQ(entries["INT1"], s["encoder"]["channel2"]["isr_count"].get<uint64_t>());
    // Timer 0 overflows every 256 x 64 = 16,384 cycles from init() on.
    EXPECT_NEAR(static_cast<double>(entries["TIMER0_OVF"]), s["cycles_total"].get<double>() / 16384.0, 2.0);
    EXPECT_EQ(s["isr"]["torn_reads"]["Count1"]["visible"], 0);
    EXPECT_EQ(lines(read_text(out / "eeprom_log.csv")), 121);
    EXPECT_EQ(rep["addr"], 240);
    EXPECT_DOUBLE_EQ(rep["gx"].get<double>(), 0.6);
    EXPECT_DOUBLE_EQ(rep["t"].get<double>(), 12.0);
    for (const char* k : {"gy", "v", "w", "ex", "ey", "theta", "errx", "erry", "errxr"}) {
        EXPECT_TRUE(rep.contains(k)) << k;
    }
    EXPECT_EQ(rep["eeprom_pairs"].size(), 121u);
    EXPECT_EQ(r.out.find("report_complete") != std::string::npos, true) << r.out;
}

/// The value of a 1-bit VCD signal at `time` (the last change at or before it).
uint64_t value_at(const VcdVar& v, uint64_t time) {
    const auto after = std::upper_bound(v.changes.begin(), v.changes.end(), time,
                                        [](uint64_t t, const VcdChange& c) { return t < c.time; });
    return after == v.changes.begin() ? v.changes.front().value : std::prev(after)->value;
}

/// Serial frames on a line (idle high): at each falling edge, 8 data bits LSB
/// first sampled mid-bit, then a stop bit that must be high.
std::string decode_serial(const VcdVar& line, uint64_t bit_ns) {
    std::string bytes;
    uint64_t busy_until = 0;
    for (std::size_t i = 1; i < line.changes.size(); ++i) {
        const VcdChange& c = line.changes[i];
        if (c.value != 0 || line.changes[i - 1].value == 0 || c.time < busy_until) continue;
        unsigned byte = 0;
        for (unsigned b = 0; b < 8; ++b) {
            byte |= static_cast<unsigned>(value_at(line, c.time + bit_ns * (1 + b) + bit_ns / 2)) << b;
        }
        EXPECT_EQ(value_at(line, c.time + bit_ns * 9 + bit_ns / 2), 1u) << "no stop bit at " << c.time;
        bytes.push_back(static_cast<char>(byte));
        busy_until = c.time + bit_ns * 10;
    }
    return bytes;
}

TEST(RunCommand, Case1VcdHoldsPinsIsrsAndLoopMarker) {
    const Case1Run& run = case1_run();
    ASSERT_EQ(run.result.exit_code, 0) << run.result.err;
    const VcdFile vcd = parse_vcd(read_text(run.vcd));  // throws on a malformed file
    EXPECT_EQ(vcd.timescale, "1ns");
    EXPECT_TRUE(vcd.has_dumpvars);
    for (const char* name :
         {"uno.D0_RX", "uno.D1_TX", "uno.D2_right_OUT", "uno.D3_left_OUT", "uno.D10_right_PWM", "uno.D11_left_PWM",
          "uno.D12_right_DIR", "uno.D13_left_DIR", "isr.isr_INT0", "isr.isr_INT1", "isr.isr_TIMER0_OVF",
          "isr.isr_USART_UDRE", "firmware.loop_iteration"}) {
        EXPECT_TRUE(vcd.has(std::string("ddmr_hil.") + name)) << name;
    }
    EXPECT_TRUE(std::is_sorted(vcd.timestamps.begin(), vcd.timestamps.end()));
    const json s = json::parse(read_text(run.out / "summary.json"));
    // The dump ends at the run's last cycle: floor(cycles x 125 / 2) ns at 16 MHz.
    EXPECT_EQ(vcd.end_time, s["cycles_total"].get<uint64_t>() * 125 / 2);
    const auto var = [&](const std::string& name) -> const VcdVar& { return vcd.var("ddmr_hil." + name); };

    // Every injected encoder edge is one level change of the pin.
    EXPECT_EQ(edge_count(var("uno.D2_right_OUT")), s["encoder"]["channel1"]["edges_injected"].get<std::size_t>());
    EXPECT_EQ(edge_count(var("uno.D3_left_OUT")), s["encoder"]["channel2"]["edges_injected"].get<std::size_t>());
    // One high pulse per ISR entry, as isr.json counts them.
    const json isr = json::parse(read_text(run.out / "isr.json"));
    for (const auto& v : isr["vectors"]) {
        const std::string name = "isr.isr_" + v["name"].get<std::string>();
        ASSERT_TRUE(vcd.has("ddmr_hil." + name)) << name;
        EXPECT_EQ(edge_count(var(name), /*rising_only=*/true), v["count"].get<std::size_t>()) << name;
    }
    // The loop marker counts the iterations summary.json reports.
    const VcdVar& loop = var("firmware.loop_iteration");
    EXPECT_EQ(loop.changes.back().value, s["loop_iterations"].get<uint64_t>());
    EXPECT_EQ(loop.changes.size(), s["loop_iterations"].get<std::size_t>() + 1);  // +1 each, from 0

    // PWM on pin 10 while the loop runs: every pulse shorter than a period is
    // centred on the counter's BOTTOM (pulse centres 2.04 ms = 32,640 cycles
    // apart, give or take the 1 ns of rounding down) and lasts 2 x OCR x 64
    // cycles, a multiple of 128 cycles = 8,000 ns.
    const uint64_t loop_begin = loop.changes.at(1).time;
    const uint64_t loop_end = loop.changes.back().time;
    constexpr uint64_t kPeriodNs = 2'040'000, kStepNs = 8'000;
    const VcdVar& d10 = var("uno.D10_right_PWM");
    std::size_t pulses = 0, off_grid = 0;
    uint64_t first_centre_2x = 0, first_off_grid = 0;
    for (std::size_t i = 1; i + 1 < d10.changes.size(); ++i) {
        const uint64_t rise = d10.changes[i].time, fall = d10.changes[i + 1].time;
        if (d10.changes[i].value != 1 || rise < loop_begin || fall > loop_end || fall - rise >= kPeriodNs) continue;
        const uint64_t width = fall - rise;
        const uint64_t centre_2x = rise + fall;  // twice the centre, in ns
        if (pulses++ == 0) first_centre_2x = centre_2x;
        const uint64_t off = (centre_2x - first_centre_2x) % (2 * kPeriodNs);
        if (std::min(width % kStepNs, kStepNs - width % kStepNs) > 1 || std::min(off, 2 * kPeriodNs - off) > 2) {
            if (off_grid++ == 0) first_off_grid = rise;
        }
    }
    EXPECT_GT(pulses, 4000u);  // ~490 per simulated second over 12 s
    EXPECT_EQ(off_grid, 0u) << "first pulse off the PWM grid rises at " << first_off_grid << " ns";

    // The TX line decodes (start, 8 data bits, stop at 1664 cycles = 104 us a
    // bit) back to what the firmware sent; RX carries the case byte.
    const std::string uart = read_text(run.out / "uart.txt");
    const std::string tx = decode_serial(var("uno.D1_TX"), 104'000);
    ASSERT_GE(tx.size(), 64u);
    EXPECT_EQ(tx.substr(0, 64), uart.substr(0, 64));
    EXPECT_EQ(tx.size(), uart.size());
    const auto mismatch = std::mismatch(tx.begin(), tx.end(), uart.begin(), uart.end());
    EXPECT_TRUE(mismatch.first == tx.end()) << "TX differs from uart.txt at byte " << (mismatch.first - tx.begin());
    EXPECT_EQ(decode_serial(var("uno.D0_RX"), 104'000), "1");
}

TEST(RunCommand, SameInputsGiveByteIdenticalArtifacts) {
    TempDir dir;
    for (const char* name : {"a", "b"}) {
        const auto r = run_command(cli() + " run --case 2 -q --out " + sh_quote((dir / name).string()) +
                                   " --vcd " + sh_quote((dir / name).string() + ".vcd"));
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    EXPECT_EQ(read_text(dir / "a" / "uart.txt"), read_text(dir / "b" / "uart.txt"));
    const std::string vcd = read_text(dir / "a.vcd");
    EXPECT_GT(vcd.size(), 100'000u);
    EXPECT_TRUE(vcd == read_text(dir / "b.vcd")) << "the VCDs of two identical runs differ";
    for (const char* f : {"eeprom.bin", "truth.csv", "firmware.csv", "eeprom_log.csv"}) {
        EXPECT_EQ(read_text(dir / "a" / f), read_text(dir / "b" / f)) << f;
    }
    json a = json::parse(read_text(dir / "a" / "summary.json"));
    json b = json::parse(read_text(dir / "b" / "summary.json"));
    // Only the host's wall-clock figures (and the VCD's path) may differ between two runs.
    for (json* j : {&a, &b}) {
        j->erase("wall_seconds");
        j->erase("mcycles_per_s");
        j->erase("vcd");
    }
    EXPECT_EQ(a, b);
}

TEST(RunCommand, TimeLimitIsAFirmwareFailureWithArtifactsKept) {
    TempDir dir;
    const auto out = dir / "short";
    const auto vcd = dir / "short.vcd";
    const auto r = run_command(cli() + " run --seconds 5.5 -q --out " + sh_quote(out.string()) + " --vcd " +
                               sh_quote(vcd.string()));
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("timeout after 5.5 simulated s"), std::string::npos) << r.err;
    const json s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["exit_reason"], "timeout");
    EXPECT_EQ(read_text(out / "uart.txt"), "0.6m\r\n");
    // The VCD is kept too, and ends at the time limit.
    const VcdFile f = parse_vcd(read_text(vcd));
    EXPECT_EQ(f.end_time, s["cycles_total"].get<uint64_t>() * 125 / 2);
    EXPECT_EQ(decode_serial(f.var("ddmr_hil.uno.D1_TX"), 104'000), "0.6m\r\n");
}

TEST(RunCommand, ProfileMeasuresEveryIteration) {
    TempDir dir;
    const auto out = dir / "prof";
    const auto vcd = dir / "prof.vcd";
    const auto r = run_command(cli() + " profile --case 2 -q --top 3 --out " + sh_quote(out.string()) + " --vcd " +
                               sh_quote(vcd.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json s = json::parse(read_text(out / "summary.json"));
    // Case 2: 800 delay(9) calls; the first opens the first iteration.
    EXPECT_EQ(s["loop_profile"]["iterations"], 799);
    // The same count on stdout, said as what it is (issue 19, item 3): all of
    // the run's 800 loop iterations but the first.
    EXPECT_EQ(s["loop_iterations"], 800);
    EXPECT_NE(r.out.find("loop profile: 799 iterations measured (all but the first, which has no start)"),
              std::string::npos)
        << r.out;
    // In cycles first; case 2 writes no EEPROM, so one group only.
    EXPECT_NE(r.out.find("   799 without an EEPROM write  compute mean "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" cycles ("), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("with an EEPROM write"), std::string::npos) << r.out;
    EXPECT_EQ(s["loop_profile"]["all"]["period"]["count"], 799);
    EXPECT_GE(s["loop_profile"]["all"]["wait"]["min_us"].get<double>(), 9000.0);
    EXPECT_EQ(s["loop_profile"]["with_eeprom_write"]["period"]["count"], 0);  // case 2 logs nothing
    const std::string table = read_text(out / "loop_profile.csv");
    EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 800);  // header + 799 rows
    // With the profiler the VCD's loop marker is exact: +1 at each iteration's
    // end, the cycle loop_profile.csv gives (start of the next row).
    const VcdFile f = parse_vcd(read_text(vcd));
    const VcdVar& loop = f.var("ddmr_hil.firmware.loop_iteration");
    ASSERT_EQ(loop.changes.size(), 800u);  // initial 0, then 1..799
    EXPECT_EQ(loop.changes.back().value, 799u);
    std::istringstream rows(table);
    std::string line;
    std::getline(rows, line);  // header
    std::getline(rows, line);  // iteration 1
    std::getline(rows, line);  // iteration 2 starts where iteration 1 ended
    const uint64_t second_start = std::stoull(line.substr(line.find(',') + 1));
    EXPECT_EQ(loop.changes[1].time, second_start * 125 / 2);

    // The function profile: both scopes, sorted by self cycles; the control
    // loop holds the same 799 iterations.
    const json p = json::parse(read_text(out / "profile.json"));
    for (const char* scope : {"whole_run", "control_loop"}) {
        const json& sc = p["scopes"][scope];
        const auto& fs = sc["functions"];
        ASSERT_GT(fs.size(), 20u) << scope;
        uint64_t self_sum = 0;
        for (std::size_t i = 0; i < fs.size(); ++i) {
            self_sum += fs[i]["self_cycles"].get<uint64_t>();
            if (i > 0) {
                EXPECT_GE(fs[i - 1]["self_cycles"].get<uint64_t>(), fs[i]["self_cycles"].get<uint64_t>());
            }
        }
        EXPECT_EQ(self_sum, sc["cycles"].get<uint64_t>()) << scope;
        const auto mul = std::find_if(fs.begin(), fs.end(), [](const json& fn) { return fn["name"] == "__mulsf3"; });
        ASSERT_NE(mul, fs.end()) << scope;
        EXPECT_GT((*mul)["calls"].get<uint64_t>(), 0u);
    }
    EXPECT_EQ(p["scopes"]["control_loop"]["iterations"], 799);
    EXPECT_EQ(p["scopes"]["whole_run"]["cycles"], s["cycles_total"]);
    EXPECT_EQ(p["stack"]["overflows"], 0);
    const std::string text = read_text(out / "profile.txt");
    // The call graph: loop() is inlined into main (LTO), which calls delay()
    // once per iteration; every micros() call in the loop is delay()'s.
    const json& cl = p["scopes"]["control_loop"];
    const auto edge = [&](const std::string& caller, const std::string& callee) {
        for (const json& e : cl["call_graph"]) {
            if (e["caller"] == caller && e["callee"] == callee) return e;
        }
        return json();
    };
    EXPECT_EQ(edge("main", "delay")["calls"], 799);
    const auto micros = std::find_if(cl["functions"].begin(), cl["functions"].end(),
                                     [](const json& fn) { return fn["name"] == "micros"; });
    ASSERT_NE(micros, cl["functions"].end());
    EXPECT_EQ(edge("delay", "micros")["calls"], (*micros)["calls"]);
    // Source lines from the stabs: the sketch's lines are there; libgcc's and
    // libm's float code has none and is said so; lines and the rest add up.
    const json& sl = cl["source_lines"];
    EXPECT_EQ(sl["line_cycles"].get<uint64_t>() + sl["no_line_info_cycles"].get<uint64_t>(),
              cl["cycles"].get<uint64_t>());
    EXPECT_TRUE(std::any_of(sl["lines"].begin(), sl["lines"].end(), [](const json& l) {
        return l["file"].get<std::string>().find("ddmr_tracking.ino") != std::string::npos;
    }));
    EXPECT_TRUE(std::any_of(sl["no_line_info"].begin(), sl["no_line_info"].end(),
                            [](const json& u) { return u["function"] == "__mulsf3_pse"; }));
    EXPECT_NE(text.find("Call graph (gprof style)"), std::string::npos);
    // callgrind.out: the control loop, and callgrind_annotate's total is its cycles.
    EXPECT_EQ(p["callgrind"]["scope"], "control_loop");
    EXPECT_EQ(callgrind_annotate(read_text(out / "callgrind.out"), false).total, cl["cycles"].get<uint64_t>());
    EXPECT_NE(text.find("Whole run"), std::string::npos);
    EXPECT_NE(text.find("Control loop"), std::string::npos);
    // --top 3: three ranked rows per scope on stdout.
    EXPECT_NE(r.out.find("Top 3 by self cycles. Whole run"), std::string::npos) << r.out;
    // The compute scope: the loop without delay()'s wait, self cycles only;
    // its total is loop_profile.csv's compute but for a few interrupts taken
    // in the same step as delay()'s CALL or RET (hil/function_profiler.hpp).
    const json& cp = p["scopes"]["compute"];
    EXPECT_EQ(cp["iterations"], 799);
    EXPECT_FALSE(cp.contains("call_graph"));
    EXPECT_FALSE(cp["functions"][0].contains("inclusive_cycles"));
    uint64_t compute_self = 0;
    for (const json& fn : cp["functions"]) {
        compute_self += fn["self_cycles"].get<uint64_t>();
        EXPECT_NE(fn["name"], "delay");  // the wait, never compute
        EXPECT_NE(fn["name"], "micros");
    }
    EXPECT_EQ(compute_self, cp["cycles"].get<uint64_t>());
    uint64_t loop_compute = 0;
    {
        std::istringstream csv(read_text(out / "loop_profile.csv"));
        std::string row;
        std::getline(csv, row);  // iteration,start_cycle,compute_cycles,...
        while (std::getline(csv, row)) {
            const std::size_t a = row.find(',', row.find(',') + 1) + 1;
            loop_compute += std::stoull(row.substr(a, row.find(',', a) - a));
        }
    }
    const double apart = std::abs(static_cast<double>(loop_compute) - cp["cycles"].get<double>());
    EXPECT_LT(apart, 1000.0) << loop_compute << " vs " << cp["cycles"];  // a few ISRs of ~100 cycles
    EXPECT_NE(r.out.find("Top 3 by self cycles. Compute"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Top 3 source lines by self cycles. Compute"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\n   3  "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("\n   4  "), std::string::npos) << r.out;
}

TEST(RunCommand, TraceOfExEyMatchesFirmwareCsv) {
    TempDir dir;
    const auto out = dir / "trace";
    const auto r = run_command(cli() + " run --case 2 -q --trace Ex,Ey,Count1:uint32 --out " + sh_quote(out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // Both are sampled at the same confirmed iteration boundaries: row for row
    // the same cycle, Ex and Ey.
    std::istringstream trace(read_text(out / "trace.csv"));
    std::istringstream fw(read_text(out / "firmware.csv"));
    std::string t_line, f_line;
    std::getline(trace, t_line);
    std::getline(fw, f_line);
    EXPECT_EQ(t_line, "iteration,cycle,t_avr_s,Ex,Ey,Count1");
    int rows = 0;
    while (std::getline(trace, t_line) && std::getline(fw, f_line)) {
        // firmware.csv: iteration,cycle,t_avr_s,Ex,Ey,...; trace.csv: the same first five columns.
        const auto prefix = [](const std::string& line, int fields) {
            std::size_t pos = 0;
            for (int i = 0; i < fields; ++i) pos = line.find(',', pos) + 1;
            return line.substr(0, pos);
        };
        ASSERT_EQ(prefix(t_line, 5), prefix(f_line, 5)) << "row " << rows;
        ++rows;
    }
    EXPECT_GE(rows, 800);
}

TEST(RunCommand, TraceOfAnUnknownOrMisTypedVariableIsRefused) {
    TempDir dir;
    auto r = run_command(cli() + " run -q --trace Nope --out " + sh_quote((dir / "a").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("'Nope'"), std::string::npos) << r.err;
    r = run_command(cli() + " run -q --trace Count1:int16 --out " + sh_quote((dir / "b").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("Count1"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "a"));
    EXPECT_FALSE(std::filesystem::exists(dir / "b"));
}

TEST(RunCommand, HelpListsTheOptions) {
    const auto r = run_command(cli() + " run --help");
    EXPECT_EQ(r.exit_code, 0);
    for (const char* opt : {"--firmware", "--case", "--seconds", "--out", "--eeprom"}) {
        EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
    }
}

struct BadInput {
    const char* name;
    std::string args;      ///< after `ddmr-hil run`, before --out
    const char* expected;  ///< a fragment of the one-line error
};

// Names the case in test output instead of dumping the struct's bytes.
void PrintTo(const BadInput& b, std::ostream* os) { *os << b.name; }

class RunCommandBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(RunCommandBadInput, OneLineNonZeroExitNothingWritten) {
    TempDir dir;
    std::ofstream(dir / "not-elf.elf") << "this is not an ELF file\n";
    const auto& p = GetParam();
    std::string args = p.args;
    const std::string tmp = "@TMP@";
    if (auto pos = args.find(tmp); pos != std::string::npos) args.replace(pos, tmp.size(), dir.path().string());
    const auto out = dir / "out";
    const auto r = run_command(cli() + " run " + args + " -q --out " + sh_quote(out.string()));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(p.expected), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << "bad input created the output folder";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, RunCommandBadInput,
    ::testing::Values(
        BadInput{"MissingElf", "--firmware @TMP@/missing.elf", "missing.elf: no such file"},
        BadInput{"NotAnElf", "--firmware @TMP@/not-elf.elf", "not an ELF file"},
        BadInput{"OtherMcu", "--firmware " + (test_firmware_dir() / "other_mcu_atmega2560.elf").string(),
                 "avr6"},
        BadInput{"HostElf", "--firmware /bin/true", "not AVR"},
        BadInput{"Case3", "--case 3", "--case"},
        BadInput{"NegativeSeconds", "--seconds -1", "--seconds"},
        BadInput{"ZeroSeconds", "--seconds 0", "--seconds"},
        BadInput{"NotANumber", "--seconds abc", "--seconds"},
        BadInput{"MissingEeprom", "--eeprom @TMP@/none.bin", "none.bin"},
        BadInput{"ShortEeprom", "--eeprom @TMP@/not-elf.elf", "bytes, the ATmega328P has 1024"},
        BadInput{"UnknownReadySymbol", "--ready-symbol nosuch", "has no function 'nosuch' (--ready-symbol)"},
        BadInput{"VcdFolderMissing", "--vcd @TMP@/nodir/run.vcd", "--vcd"},
        BadInput{"VcdIsAFolder", "--vcd @TMP@", "--vcd"},
        BadInput{"TopZero", "--profile --top 0", "--top"},
        BadInput{"TopNotANumber", "--profile --top many", "--top"},
        BadInput{"ContractEepromLogPastTheChip",
                 "--firmware " + (test_firmware_dir() / "echo_fixture.elf").string() + " --contract " +
                     (source_dir() / "tests/firmware/contract_eeprom_4k.yaml").string(),
                 "no room for a sample in the ATmega328P's 1024-byte EEPROM"}),
    [](const ::testing::TestParamInfo<BadInput>& p) { return std::string(p.param.name); });


// --- A firmware without the reference sketch's protocol (no sketch contract) ---

TEST(RunCommand, AnyFirmwareRunsItsSecondsAndEndsWithTimeLimit) {
    // echo_fixture upper-cases what it receives: the --send bytes at 10 ms,
    // then '\x41' (A) and a CR at 0.1 s, come back in uart.txt.
    TempDir dir;
    const auto out = dir / "echo";
    const auto r = run_command(cli() + " run -q --firmware " + sh_quote((test_firmware_dir() / "echo_fixture.elf").string()) +
                               " --seconds 0.25 --send 'go\\n@10ms' --send 'b\\x41\\r@0.1s' --out " +
                               sh_quote(out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("no sketch contract"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("time_limit after 0.250 simulated s"), std::string::npos) << r.out;
    EXPECT_EQ(read_text(out / "uart.txt"), "GO\nBA\r");
    const json s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["exit_reason"], "time_limit");
    EXPECT_EQ(s["protocol"], "none");
    // 0.25 s at 16 MHz, and the instruction in progress then (at most 4 cycles).
    EXPECT_GE(s["cycles_total"].get<uint64_t>(), 4'000'000u);
    EXPECT_LT(s["cycles_total"].get<uint64_t>(), 4'000'005u);
    EXPECT_TRUE(s["firmware_report"].is_null());
    for (const char* f : {"truth.csv", "eeprom.bin", "isr.json", "isr.md"}) EXPECT_TRUE(fs::exists(out / f)) << f;
    // What needs the reference sketch's globals and EEPROM layout is not made up.
    EXPECT_FALSE(fs::exists(out / "firmware.csv"));
    EXPECT_FALSE(fs::exists(out / "eeprom_log.csv"));
}

TEST(RunCommand, AnyFirmwareIsProfiledFromResetWithTheGivenLoopMark) {
    TempDir dir;
    const auto r = run_command(cli() + " run -q --firmware " + sh_quote((test_firmware_dir() / "loop_fixture.elf").string()) +
                               " --seconds 0.01 --profile --loop-mark mark --out " + sh_quote((dir / "loop").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json s = json::parse(read_text(dir / "loop" / "summary.json"));
    // loop_fixture's iteration is 18 cycles (tests/firmware/loop_fixture.c): 160,000 cycles hold ~8,888.
    EXPECT_GT(s["loop_profile"]["iterations"].get<uint64_t>(), 8000u);
}

// Issue 32: --loop-mark takes C++ names. The reference sketch (C++, built
// by arduino-builder) has the core's serialEventRun() (_Z14serialEventRunv),
// which main calls after each loop(). Its loop() polls Serial.available()
// (a few cycles an iteration) until the case byte has come, then runs the
// whole case in one call (8 s for case 2, then its report), then polls
// again while the report drains from the UART's buffer.
TEST(RunCommand, ProfileTakesTheDemangledNameOfACxxFunction) {
    TempDir dir;
    const auto out = dir / "prof";
    const auto r = run_command(cli() + " profile --case 2 -q --top 1 --loop-mark serialEventRun --out " +
                               sh_quote(out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["loop_profile"]["mark"], "serialEventRun");
    const json& period = s["loop_profile"]["all"]["period"];
    EXPECT_GT(s["loop_profile"]["iterations"].get<uint64_t>(), 100u);
    EXPECT_EQ(period["count"], s["loop_profile"]["iterations"]);
    // The longest iteration is the case's loop() call, the others are polls.
    EXPECT_GT(period["max_us"].get<double>(), 8.0e6);
    EXPECT_LT(period["max_us"].get<double>(), 8.5e6);
    EXPECT_LT(period["p99_us"].get<double>(), 100.0);
}

// tests/firmware/cpp_fixture.cpp: no loop() or delay(); main's loop calls
// MyClass::step(), tick(int), tick(long) and serialEventRun() once each
// and twice() twice; 51 cycles an iteration.
TEST(RunCommand, ProfileNamesAMarkThatWorksAndRefusesAnOverloadedName) {
    TempDir dir;
    const std::string fw = " --firmware " + sh_quote((test_firmware_dir() / "cpp_fixture.elf").string());
    const std::string elf = (test_firmware_dir() / "cpp_fixture.elf").string();
    auto r = run_command(cli() + " profile -q --seconds 0.001 --loop-mark MyClass::step" + fw + " --out " +
                         sh_quote((dir / "step").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json s = json::parse(read_text(dir / "step" / "summary.json"));
    EXPECT_EQ(s["loop_profile"]["mark"], "MyClass::step");
    EXPECT_GT(s["loop_profile"]["iterations"].get<uint64_t>(), 100u);  // 16,000 cycles
    const std::string try_these = "; try one that main's loop calls from one place: serialEventRun, MyClass::step, "
                                  "tick(int), tick(long)\n";
    const struct {
        const char* args;
        std::string message;
    } refused[] = {
        {"", ": neither loop() nor delay() is a function in the ELF (LTO inlined them): pass --loop-mark FUNCTION, "
             "a function each loop iteration calls once" + try_these},
        {" --loop-mark tick",
         ": --loop-mark 'tick' names 2 functions: tick(int), tick(long); give one of these names\n"},
        {" --loop-mark nosuch", ": --loop-mark 'nosuch' is no function in the ELF" + try_these},
    };
    for (const auto& c : refused) {
        r = run_command(cli() + " profile -q --seconds 0.001" + c.args + fw + " --out " +
                        sh_quote((dir / "no").string()));
        EXPECT_EQ(r.exit_code, 2) << c.args;
        EXPECT_EQ(r.err, "ddmr-hil profile: error: firmware " + elf + c.message) << c.args;
        EXPECT_FALSE(fs::exists(dir / "no")) << c.args;
    }
}

TEST(RunCommand, AnyFirmwareRefusesTheReferenceOptionsAndBadSends) {
    TempDir dir;
    const std::string fw = " --firmware " + sh_quote((test_firmware_dir() / "echo_fixture.elf").string());
    auto r = run_command(cli() + " run -q --case 2 --seconds 0.1" + fw + " --out " + sh_quote((dir / "a").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--case / --ready-symbol need a sketch contract"), std::string::npos) << r.err;
    r = run_command(cli() + " run -q --seconds 0.1 --send 'x@2'" + fw + " --out " + sh_quote((dir / "b").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--send 'x@2': TIME '2' must be a non-negative number with a unit"), std::string::npos) << r.err;
    r = run_command(cli() + " run -q --seconds 0.1 --send 'x\\q@1s'" + fw + " --out " + sh_quote((dir / "c").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("unknown escape"), std::string::npos) << r.err;
    r = run_command(cli() + " profile -q --seconds 0.1" + fw + " --out " + sh_quote((dir / "d").string()));
    EXPECT_EQ(r.exit_code, 2);
    // echo_fixture's loop calls nothing: no mark to suggest, and it says why.
    EXPECT_NE(r.err.find("neither loop() nor delay() is a function in the ELF (LTO inlined them): pass --loop-mark "
                         "FUNCTION, a function each loop iteration calls once; main's loop calls no function that "
                         "could be the mark"),
              std::string::npos)
        << r.err;
    for (const char* d : {"a", "b", "c", "d"}) EXPECT_FALSE(fs::exists(dir / d)) << d;
}

TEST(RunCommand, AnyFirmwareGetsARaceReport) {
    // race_fixture (tests/firmware/race_fixture.c): a torn read of `ticks`, a
    // torn write of `setpoint`, a stale read of the non-volatile `flag`;
    // the fixed build has none of them.
    TempDir dir;
    const auto run = [&](const char* variant) {
        const auto out = dir / variant;
        const auto r = run_command(cli() + " run -q --seconds 0.15 --firmware " +
                                   sh_quote((test_firmware_dir() / (std::string("race_fixture_") + variant + ".elf")).string()) +
                                   " --out " + sh_quote(out.string()));
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return json::parse(read_text(out / "isr.json"))["races"];
    };
    const json racy = run("racy");
    ASSERT_EQ(racy["torn"].size(), 2u) << racy.dump(2);
    std::map<std::string, json> torn;
    for (const auto& t : racy["torn"]) torn[t["variable"]] = t;
    EXPECT_EQ(torn["ticks"]["access"], "read");
    EXPECT_EQ(torn["ticks"]["status"], "observed");
    EXPECT_EQ(torn["ticks"]["function"], "main");
    EXPECT_EQ(torn["ticks"]["size"], 4);
    EXPECT_EQ(torn["ticks"]["split_by"], json::array({"TIMER0_OVF"}));
    EXPECT_TRUE(torn["ticks"]["source"].is_null());  // built without -g
    EXPECT_EQ(torn["setpoint"]["access"], "write");
    EXPECT_EQ(torn["setpoint"]["status"], "observed");
    ASSERT_EQ(racy["stale"].size(), 1u);
    EXPECT_EQ(racy["stale"][0]["variable"], "flag");
    EXPECT_GT(racy["stale"][0]["writes_missed"].get<uint64_t>(), 100u);
    const json fixed = run("fixed");
    EXPECT_EQ(fixed["torn"].size(), 0u) << fixed.dump(2);
    EXPECT_EQ(fixed["stale"].size(), 0u);
    EXPECT_EQ(fixed["torn_observed"], 0);
    const std::string md = read_text(dir / "racy" / "isr.md");
    EXPECT_NE(md.find("| `ticks` | 4 | read | `main` |"), std::string::npos) << md;
    EXPECT_NE(md.find("Declare the variable `volatile`"), std::string::npos) << md;
}

TEST(RunCommand, AnyFirmwareThroughItsSketchContract) {
    // contract_fixture.c with contract_fixture.yaml: start on "ready" with the
    // case digit, complete two lines after "DONE", pose read at "DONE" (the
    // firmware zeroes px after), firmware.csv per `t` step, EEPROM log at
    // 100.. / 300.., one byte per sample, 100 counts per metre, no unwrap.
    TempDir dir;
    const auto lines = [](const std::string& t) { return std::count(t.begin(), t.end(), '\n'); };
    const std::string fw = " --firmware " + sh_quote((test_firmware_dir() / "contract_fixture.elf").string());
    const std::string contract =
        " --contract " + sh_quote((fs::path(DDMR_TEST_SOURCE_DIR) / "tests/firmware/contract_fixture.yaml").string());
    const auto out = dir / "with";
    auto r = run_command(cli() + " run -q --seconds 2 --case 4" + fw + contract + " --out " + sh_quote(out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_text(out / "uart.txt"), "ready\r\nDONE\r\n400,50\r\nbye\r\n");  // case 4: 50 x 0.008 m
    const json s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["exit_reason"], "report_complete");
    EXPECT_EQ(s["protocol"], "contract");
    EXPECT_EQ(s["case"], 4);
    EXPECT_TRUE(s["firmware_report"].is_null());  // not the ddmr-tracking format ...
    EXPECT_EQ(s["report_fields"]["px_mm"], 400.0);  // ... but named fields, from the line "400,50"
    EXPECT_EQ(s["report_fields"]["py_mm"], 50.0);
    EXPECT_TRUE(s["report_fields"]["missing"].is_null());
    EXPECT_NEAR(s["end_pose_firmware"]["x_m"].get<double>(), 0.4, 1e-5);
    EXPECT_NEAR(s["end_pose_firmware"]["y_m"].get<double>(), 0.05, 1e-5);
    EXPECT_NEAR(s["end_pose_firmware"]["theta_rad"].get<double>(), 0.5, 1e-5);
    EXPECT_EQ(s["loop_iterations"], 50);
    EXPECT_EQ(lines(read_text(out / "firmware.csv")), 51);  // header + 50 iterations
    EXPECT_EQ(read_text(out / "firmware.csv").substr(0, 34), "iteration,cycle,t_avr_s,px,py,th,t");
    // Sample k = px, py after iteration 10k + 10: int(0.08 (k + 1) * 100), int(0.01 (k + 1) * 100) in float.
    const std::string log = read_text(out / "eeprom_log.csv");
    EXPECT_EQ(lines(log), 6);
    EXPECT_NE(log.find("\n0,"), std::string::npos);
    EXPECT_NE(log.find(",0.080000,0.010000\n"), std::string::npos) << log;
    // profile takes the contract's loop.function as its loop mark: 50 iterations of step().
    r = run_command(cli() + " profile -q --seconds 2" + fw + contract + " --out " + sh_quote((dir / "prof").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json p = json::parse(read_text(dir / "prof" / "summary.json"));
    EXPECT_EQ(p["loop_profile"]["mark"], "step");
    EXPECT_EQ(p["loop_profile"]["iterations"], 49);  // the completed ones: from one step() to the next
    // The same firmware without its contract: a time-limited run, nothing made up.
    const auto bare = dir / "bare";
    r = run_command(cli() + " run -q --seconds 0.05" + fw + " --out " + sh_quote(bare.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json b = json::parse(read_text(bare / "summary.json"));
    EXPECT_EQ(b["exit_reason"], "time_limit");
    EXPECT_EQ(read_text(bare / "uart.txt"), "ready\r\n");  // nobody sent the case digit
    EXPECT_FALSE(fs::exists(bare / "firmware.csv"));
    // A contract whose completion never comes: a timeout that names it (exit 3).
    std::ofstream(dir / "never.yaml") << "start: {send: \"3\", after-text: ready}\ncomplete: {text: NEVER}\n";
    r = run_command(cli() + " run -q --seconds 0.2" + fw + " --contract " + sh_quote((dir / "never.yaml").string()) +
                    " --out " + sh_quote((dir / "never").string()));
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("'NEVER' never came"), std::string::npos) << r.err;
    // A bad contract is refused before anything is written.
    std::ofstream(dir / "bad.yaml") << "pose: {x: px, y: py, theta: nosuch}\n";
    r = run_command(cli() + " run -q --seconds 0.2" + fw + " --contract " + sh_quote((dir / "bad.yaml").string()) +
                    " --out " + sh_quote((dir / "bad").string()));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("nosuch"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad"));
}

TEST(RunCommand, BaudPutsTheHostsAdapterOnTheLine) {
    // echo_fixture listens and answers at 9600 baud: an adapter at 9600
    // reads its answer; one at 57600 sends garbage and reads garbage, with
    // framing errors, as on the bench.
    TempDir dir;
    const std::string fw = " --firmware " + sh_quote((test_firmware_dir() / "echo_fixture.elf").string());
    const auto run = [&](const char* baud) {
        const auto out = dir / baud;
        const auto r = run_command(cli() + " run -q --seconds 0.2 --send 'hello\\n@10ms' --baud " + baud + fw +
                                   " --out " + sh_quote(out.string()));
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return std::make_pair(read_text(out / "uart.txt"), json::parse(read_text(out / "summary.json"))["uart"]);
    };
    const auto [good, good_uart] = run("9600");
    EXPECT_EQ(good, "HELLO\n");
    EXPECT_EQ(good_uart["adapter_baud"], 9600);
    EXPECT_EQ(good_uart["framing_errors"], 0);
    const auto [bad, bad_uart] = run("57600");
    EXPECT_NE(bad, "HELLO\n");
    EXPECT_GT(bad_uart["framing_errors"].get<uint64_t>(), 0u);
    const auto r = run_command(cli() + " run -q --baud 0" + fw + " --out " + sh_quote((dir / "zero").string()));
    EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace ddmr::test

namespace ddmr::test {
namespace {

TEST(RunCommand, BoardNameAndSerialPortPutTheAdapterOnAMegasSerial1) {
    // serial1_mega_fixture echoes upper-cased on Serial1 at 19200 baud and
    // prints "usart0" on Serial: with --serial-port Serial1 the host's adapter
    // (at 19200) talks to USART1, and the thesis robot's wiring sits on the Mega.
    TempDir dir;
    const auto out = dir / "bt";
    const auto r = run_command(cli() + " run -q --board-name mega2560 --serial-port Serial1 --baud 19200 --firmware " +
                               sh_quote((test_firmware_dir() / "serial1_mega_fixture.elf").string()) +
                               " --seconds 0.05 --send 'fwd\\n@5ms' --out " + sh_quote(out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_text(out / "uart.txt"), "FWD\n");
    const json s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["uart"]["port"], "Serial1");
    EXPECT_EQ(s["uart"]["framing_errors"], 0);
    EXPECT_EQ(s["uart"]["cycles_per_byte"], 8320);  // (103 + 1) x 8 x 10 bits
    EXPECT_EQ(s["board"]["name"], "mega2560");
    EXPECT_EQ(s["board"]["file"], "built-in default board on the mega2560");
}

TEST(RunCommand, ABoardNameOrSerialPortThatDoesNotFitIsRefused) {
    TempDir dir;
    const std::string mega_fw = " --firmware " + sh_quote((test_firmware_dir() / "serial1_mega_fixture.elf").string());
    // The Uno has one USART.
    auto r = run_command(cli() + " run -q --seconds 0.01 --serial-port Serial1 --firmware " +
                         sh_quote((test_firmware_dir() / "echo_fixture.elf").string()) + " --out " +
                         sh_quote((dir / "a").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--serial-port Serial1: the Arduino Uno (ATmega328P) has Serial"), std::string::npos) << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    // The board file says mega2560, --board-name says uno.
    r = run_command(cli() + " run -q --seconds 0.01 --board-name uno --board " +
                    sh_quote((source_dir() / "firmware/examples/mega_l298n_int45/board.yaml").string()) + mega_fw +
                    " --out " + sh_quote((dir / "b").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--board-name uno: the board file"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("is for the Arduino Mega 2560 (board: mega2560)"), std::string::npos) << r.err;
    // A Mega ELF on the default Uno.
    r = run_command(cli() + " run -q --seconds 0.01" + mega_fw + " --out " + sh_quote((dir / "c").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("avr6"), std::string::npos) << r.err;
    r = run_command(cli() + " run -q --seconds 0.01 --board-name leonardo" + mega_fw + " --out " +
                    sh_quote((dir / "d").string()));
    EXPECT_EQ(r.exit_code, 2);
    for (const char* d : {"a", "b", "c", "d"}) EXPECT_FALSE(fs::exists(dir / d)) << d;
}

TEST(RunCommand, AWorldFilePutsTheRobotAtItsStart) {
    TempDir dir;
    std::ofstream(dir / "w.yaml") << "start: {x_m: 0.5, y_m: -0.25, heading_deg: 90}\n"
                                     "walls:\n  - {from_m: [2, -1], to_m: [2, 1]}\n";
    // 10 ms of a firmware that never drives the motors.
    const auto r = run_command(cli() + " run -q --seconds 0.01 --firmware " +
                               sh_quote((test_firmware_dir() / "echo_fixture.elf").string()) + " --world " +
                               sh_quote((dir / "w.yaml").string()) + " --out " + sh_quote((dir / "out").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json s = json::parse(read_text(dir / "out" / "summary.json"));
    EXPECT_EQ(s["world"], (dir / "w.yaml").string());
    EXPECT_EQ(s["end_pose_truth"]["x_m"], 0.5);
    EXPECT_EQ(s["end_pose_truth"]["y_m"], -0.25);
    EXPECT_DOUBLE_EQ(s["end_pose_truth"]["theta_rad"].get<double>(), 3.14159265358979323846 / 2);
}

// drive_fixture drives both wheels forward at full drive from reset: a wall
// 0.3 m ahead stops the body with its front edge (0.09 m ahead of the axle)
// at the wall; summary.json and truth.csv report the contact.
TEST(RunCommand, AWallStopsTheRobotAndTheContactIsReported) {
    TempDir dir;
    std::ofstream(dir / "w.yaml") << "walls:\n  - {from_m: [0.3, -1], to_m: [0.3, 1]}\n";
    const auto r = run_command(cli() + " run -q --seconds 1.5 --firmware " +
                               sh_quote((test_firmware_dir() / "drive_fixture.elf").string()) + " --world " +
                               sh_quote((dir / "w.yaml").string()) + " --out " + sh_quote((dir / "out").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json s = json::parse(read_text(dir / "out" / "summary.json"));
    EXPECT_EQ(s["contacts"]["count"], 1);
    EXPECT_EQ(s["contacts"]["in_contact_at_end"], true);
    const json& e = s["contacts"]["events"][0];
    EXPECT_DOUBLE_EQ(e["x_m"].get<double>(), 0.3);
    EXPECT_GT(e["speed_m_s"].get<double>(), 0.4);  // it met the wall at speed (top speed ~0.6 m/s)
    EXPECT_GT(e["t_s"].get<double>(), 0.2);        // 0.21 m from rest
    EXPECT_LT(e["t_s"].get<double>(), 0.8);
    EXPECT_LT(s["end_pose_truth"]["x_m"].get<double>(), 0.3 - 0.09 + 1e-9);
    EXPECT_GT(s["end_pose_truth"]["x_m"].get<double>(), 0.3 - 0.09 - 0.002);  // a corner may touch first
    const std::string truth = read_text(dir / "out" / "truth.csv");
    const std::string header = truth.substr(0, truth.find('\n'));
    EXPECT_NE(header.find(",wall_distance_m,contact,contacts"), std::string::npos) << header;
    const std::string last = truth.substr(truth.rfind('\n', truth.size() - 2) + 1);
    EXPECT_EQ(last.substr(last.size() - 5), ",1,1\n") << last;  // touching, one contact
}

}  // namespace
}  // namespace ddmr::test
