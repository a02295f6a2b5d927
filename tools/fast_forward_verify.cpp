#include "fast_forward_verify.hpp"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <thread>
#include <utility>

#include <fmt/format.h>

#include "common/atomic_file.hpp"
#include "common/private_dir.hpp"
#include "firmware_run_plan.hpp"
#include "hil/data_objects.hpp"
#include "lockstep.hpp"

namespace ddmr::tools {
namespace {

namespace fs = std::filesystem;
using hil::MachineState;

/// The same run, writing into `dir`, quiet; a VCD (if any) into `dir` too
/// (its recorder watches pins, which fast-forward takes into account), or none.
FirmwareRunOptions copy_into(const FirmwareRunOptions& o, const fs::path& dir, bool keep_vcd) {
    FirmwareRunOptions c = o;
    c.out_dir = dir;
    c.progress = false;
    c.notices = false;
    if (c.vcd) c.vcd = keep_vcd ? std::optional<fs::path>(dir / "run.vcd") : std::nullopt;
    return c;
}

/// Runs `a` on this thread and `b` on another; rethrows the first error.
template <typename T>
std::pair<T, T> on_two_threads(const std::function<T()>& a, const std::function<T()>& b) {
    T rb{};
    std::exception_ptr error_b;
    std::thread thread([&] {
        try {
            rb = b();
        } catch (...) {
            error_b = std::current_exception();
        }
    });
    T ra{};
    try {
        ra = a();
    } catch (...) {
        thread.join();
        throw;
    }
    thread.join();
    if (error_b) std::rethrow_exception(error_b);
    return {std::move(ra), std::move(rb)};
}

MachineState capture(FirmwareRun& run) { return hil::capture_machine_state(run.session().rig()); }

/// The run to its end, meeting `lockstep` at each checkpoint and at its end.
hil::SessionStop run_meeting(FirmwareRun& run, Lockstep& lockstep, Lockstep::Side side) {
    try {
        const hil::SessionStop stop = run.run_to_end([&] { lockstep.checkpoint(side, capture(run)); });
        lockstep.ended(side, capture(run));
        return stop;
    } catch (...) {
        lockstep.ended(side, std::nullopt);
        throw;
    }
}

/// Both runs from reset to their first stop at or after cycle `at` (or to
/// their ends, if sooner), stopping every 10 ms on the way as the lockstep
/// runs did (a stop bounds fast-forward's jumps).
std::pair<MachineState, MachineState> probe(const FirmwareRunOptions& options_a, const FirmwareRunOptions& options_b,
                                            hil::Cycles at, const fs::path& dir) {
    const auto state_at = [at](const FirmwareRunOptions& o) {
        FirmwareRun run(o);
        std::optional<MachineState> s;
        run.session().at(at, [&] {
            s = capture(run);
            run.session().end_run();
        });
        run.run_to_end([] {});
        return s ? *s : capture(run);
    };
    const FirmwareRunOptions a = copy_into(options_a, dir / "a", true);
    const FirmwareRunOptions b = copy_into(options_b, dir / "b", true);
    return on_two_threads<MachineState>([&] { return state_at(a); }, [&] { return state_at(b); });
}

/// Bisects (last equal, first differing stop) by repeating the runs.
void narrow(const FirmwareRunOptions& options_a, const FirmwareRunOptions& options_b, const hil::McuDescription& mcu,
            const hil::DataObjects& objects, FastForwardDifference& d) {
    hil::Cycles lo = d.last_equal_cycle;
    hil::Cycles hi = std::min(d.with_ff.cycle, d.without_ff.cycle);
    const PrivateDir dir("ddmr-hil-verify");
    int probes = 0;
    while (hi - lo > 1) {
        const hil::Cycles mid = lo + (hi - lo) / 2;
        auto [a, b] = probe(options_a, options_b, mid, dir.path());
        hil::StateComparison c = hil::compare_machine_states(a, b, mcu, &objects);
        ++probes;
        if (options_a.progress) {
            std::fprintf(stderr, "ddmr-hil run: verify: repeat %d: at cycle %llu they are %s\n", probes,
                         static_cast<unsigned long long>(a.cycle), c.equal() ? "equal" : "different");
        }
        if (c.equal()) {
            if (a.cycle >= hi) break;  // the stop fell on the differing one's: nothing between
            lo = a.cycle;
        } else {
            hi = mid;
            d.with_ff = std::move(a);
            d.without_ff = std::move(b);
            d.comparison = std::move(c);
        }
    }
    d.last_equal_cycle = lo;
    d.narrowed = true;
}

std::string function_at(const hil::ElfImage& elf, uint32_t pc) {
    const auto f = elf.function_at(pc);
    return f ? elf.function_name(*f) : std::string();
}

FastForwardDifference difference_of(const LockstepDivergence& d) {
    FastForwardDifference out;
    out.last_equal_cycle = d.last_equal_cycle;
    out.with_ff = d.a;
    out.without_ff = d.b;
    out.comparison = d.comparison;
    return out;
}

}  // namespace

VerifiedRun run_in_lockstep_with(const FirmwareRunOptions& options, const FirmwareRunOptions& other) {
    if (options.gdb_port || other.gdb_port) throw std::invalid_argument("--verify-fast-forward cannot serve avr-gdb (--gdb): a debugged run has no fast-forward");
    if (options.unity || other.unity) throw std::invalid_argument("--verify-fast-forward cannot be used with --unity: stdout would carry both runs' output");
    FirmwareRun a(options);
    const PrivateDir shadow_dir("ddmr-hil-verify");
    const FirmwareRunOptions options_b = copy_into(other, shadow_dir.path(), false);
    FirmwareRun b(options_b);
    const hil::McuDescription& mcu = a.session().core().mcu();
    const hil::DataObjects objects(a.session().elf(), mcu);
    Lockstep lockstep(mcu, &objects);
    const auto [stop_a, stop_b] = on_two_threads<hil::SessionStop>(
        [&] { return run_meeting(a, lockstep, Lockstep::kA); },
        [&] { return run_meeting(b, lockstep, Lockstep::kB); });
    static_cast<void>(stop_b);
    VerifiedRun out;
    out.verification.checkpoints_equal = lockstep.checkpoints_equal();
    out.verification.checked_to_cycle = lockstep.last_equal_cycle();
    if (const auto d = lockstep.divergence()) {
        FastForwardDifference diff = difference_of(*d);
        const bool in_boot = a.plan().ready && d->last_equal_cycle == 0;
        if (!in_boot) narrow(options, other, mcu, objects, diff);
        diff.function_with_ff = function_at(a.session().elf(), diff.with_ff.pc);
        diff.function_without_ff = function_at(a.session().elf(), diff.without_ff.pc);
        out.verification.difference = std::move(diff);
    }
    out.result = a.finish(stop_a);
    write_file_atomic(options.out_dir / "fast_forward_verify.json",
                      verification_json(out.verification, out.result.clock_hz).dump(2) + "\n");
    return out;
}

VerifiedRun run_verifying_fast_forward(const FirmwareRunOptions& options) {
    if (!options.fast_forward) {
        throw std::invalid_argument("--verify-fast-forward compares a run with fast-forward: drop --no-fast-forward");
    }
    FirmwareRunOptions without = options;
    without.fast_forward = false;
    return run_in_lockstep_with(options, without);
}

nlohmann::json verification_json(const FastForwardVerification& v, uint32_t clock_hz) {
    using nlohmann::json;
    json j;
    j["equal"] = !v.difference.has_value();
    j["checkpoint_period_s"] = 0.01;
    j["checkpoints_equal"] = v.checkpoints_equal;
    j["checked_to_cycle"] = v.checked_to_cycle;
    j["checked_to_s"] = hil::cycles_to_s(v.checked_to_cycle, clock_hz);
    if (!v.difference) {
        j["first_difference"] = nullptr;
        return j;
    }
    const FastForwardDifference& d = *v.difference;
    const auto side = [](const MachineState& s, const std::string& function) {
        return json{{"cycle", s.cycle}, {"pc", fmt::format("0x{:04x}", s.pc)}, {"function", function}};
    };
    json differences = json::array();
    for (const hil::StateDifference& s : d.comparison.shown) {
        differences.push_back({{"what", s.what}, {"with_fast_forward", s.a}, {"without_fast_forward", s.b}});
    }
    j["first_difference"] = {
        {"cycle", d.with_ff.cycle},
        {"t_s", hil::cycles_to_s(d.with_ff.cycle, clock_hz)},
        {"last_equal_cycle", d.last_equal_cycle},
        {"narrowed", d.narrowed},
        {"with_fast_forward", side(d.with_ff, d.function_with_ff)},
        {"without_fast_forward", side(d.without_ff, d.function_without_ff)},
        {"differences_total", d.comparison.total},
        {"differences", differences},
    };
    return j;
}

std::string verification_line(const FastForwardVerification& v, uint32_t clock_hz) {
    if (!v.difference) {
        return fmt::format("fast-forward verified: the runs with and without it were equal at {} checkpoints, up to "
                           "cycle {} (t = {:.6f} s)",
                           v.checkpoints_equal, v.checked_to_cycle, hil::cycles_to_s(v.checked_to_cycle, clock_hz));
    }
    const FastForwardDifference& d = *v.difference;
    const auto pc = [](const MachineState& s, const std::string& f) {
        return f.empty() ? fmt::format("0x{:04x}", s.pc) : fmt::format("0x{:04x} ({})", s.pc, f);
    };
    std::string shown;
    for (std::size_t i = 0; i < d.comparison.shown.size() && i < 4; ++i) {
        const hil::StateDifference& s = d.comparison.shown[i];
        shown += fmt::format("{}{} {} / {}", i == 0 ? "" : ", ", s.what, s.a, s.b);
    }
    const std::size_t more = d.comparison.total - std::min<std::size_t>(d.comparison.total, 4);
    return fmt::format("fast-forward verification failed: the runs {} at cycle {} (t = {:.6f} s; equal at cycle {}), "
                       "PC {} with fast-forward, {} without: {}{} (with / without; fast_forward_verify.json)",
                       d.narrowed ? "first differ" : "differ at the boot's end,", d.with_ff.cycle,
                       hil::cycles_to_s(d.with_ff.cycle, clock_hz), d.last_equal_cycle, pc(d.with_ff, d.function_with_ff),
                       pc(d.without_ff, d.function_without_ff), shown,
                       more > 0 ? fmt::format(", and {} more", more) : std::string());
}

}  // namespace ddmr::tools
