#include "scenario_command.hpp"

#include "hil/board.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <thread>

#include "common/atomic_file.hpp"
#include "common/sketch_build.hpp"
#include "scenario/step_catalog.hpp"
#include "common/spawn.hpp"
#include "exit_codes.hpp"
#include "scenario/scenario_signals.hpp"
#include "hil/avr_core.hpp"
#include "hil/elf_image.hpp"
#include "scenario/scenario_runner.hpp"
#include "scenario/scenario_yaml.hpp"
#include "scenario/suite_results.hpp"

namespace ddmr::tools {
namespace {
namespace fs = std::filesystem;
namespace sc = scenario;
using nlohmann::json;

struct ScenarioCli {
    std::vector<std::string> files;
    std::string out_dir = "scenario-results";
    std::string junit;
    std::string firmware;
    std::vector<std::string> libraries;  ///< --libraries DIR (repeatable)
    unsigned jobs = 0;
    std::string shard;
    double wall_timeout_s = 600.0;
    bool worker = false;
    bool progress = false;
    bool list_steps = false;
    bool update_golden = false;
    bool no_fast_forward = false;
};

/// Loads a scenario and builds the sketch it names (cached) if it names one.
sc::Scenario load(const std::string& file, const ScenarioCli& cli);

sc::LoadOptions load_options(const ScenarioCli& cli) {
    sc::LoadOptions o;
    o.reference_firmware = DDMR_DEFAULT_FIRMWARE;
    if (!cli.firmware.empty()) o.firmware_override = fs::absolute(cli.firmware);
    return o;
}

sc::Scenario load(const std::string& file, const ScenarioCli& cli) {
    sc::Scenario s = sc::load_scenario(file, load_options(cli));
    if (cli.no_fast_forward) s.fast_forward = false;
    if (s.sketch) {
        SketchBuildOptions o;
        o.fqbn = hil::board_description(s.board.model).fqbn;
        o.libraries = s.libraries;
        for (const auto& dir : cli.libraries) o.libraries.emplace_back(dir);
        o.more_libraries_advice = "name its folder in the scenario's libraries: [DIR] (or pass --libraries DIR)";
        try {
            s.sketch_build = build_sketch(*s.sketch, o);
        } catch (const SketchBuildError& e) {
            throw SketchBuildError(fmt::format("{}: {}", file, e.what()));  // which scenario's sketch
        }
        s.firmware = s.sketch_build->elf;
        if (!cli.worker) std::fprintf(stderr, "%s\n", describe_libraries(*s.sketch_build).c_str());
    }
    sc::check_firmware_names(s);
    sc::check_signal_names(s);
    return s;
}

/// One scenario in this process (the worker a suite run spawns).
int run_worker(const ScenarioCli& cli) {
    if (cli.files.size() != 1) throw std::invalid_argument("--worker takes exactly one scenario file");
    const sc::Scenario s = load(cli.files[0], cli);
    const sc::ScenarioResult r = sc::run_scenario(s, cli.out_dir, cli.progress, cli.update_golden);
    return sc::exit_code(r.verdict);
}

/// The result a worker left in its folder (or why there is none).
sc::ScenarioResult read_result(const sc::Scenario& s, const fs::path& dir, int status, double wall_s) {
    if (fs::exists(dir / "result.json")) {
        sc::ScenarioResult r = sc::read_scenario_result(dir);
        r.wall_seconds = wall_s;
        return r;
    }
    sc::ScenarioResult r;
    r.name = s.name;
    r.file = s.file;
    r.wall_seconds = wall_s;
    r.verdict = sc::Verdict::kFirmware;
    std::string stderr_text;
    std::ifstream err(dir / "stderr.txt");
    std::getline(err, stderr_text);
    r.message = WIFSIGNALED(status)
                    ? fmt::format("the worker died with signal {} ({})", WTERMSIG(status), stderr_text)
                    : fmt::format("the worker exited with {} and no result: {}", WEXITSTATUS(status), stderr_text);
    return r;
}

std::string self_exe() {
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw std::runtime_error("cannot find this program's path (/proc/self/exe): " + ec.message());
    return p.string();
}

int run_suite(const ScenarioCli& cli) {
    if (cli.files.empty()) throw std::invalid_argument("give at least one scenario file (or --list-steps)");
    const unsigned jobs = cli.jobs > 0 ? cli.jobs : std::max(1U, std::thread::hardware_concurrency());
    // Everything is loaded and checked before anything runs or is written.
    std::vector<sc::Scenario> scenarios;
    std::set<std::string> names;
    for (const auto& f : cli.files) {
        scenarios.push_back(load(f, cli));
        if (!names.insert(scenarios.back().name).second) {
            throw std::invalid_argument(fmt::format("{}: scenario name '{}' is used twice (its output folder would be shared)",
                                                    f, scenarios.back().name));
        }
        const hil::ElfImage elf = hil::ElfImage::read(scenarios.back().firmware);
        const hil::BoardDescription& board = hil::board_description(scenarios.back().board.model);
        elf.require_mcu(*board.mcu, board.key);
        hil::AvrCore::check_loadable(elf, *board.mcu);
    }
    // --shard I/N keeps every N-th scenario of the suite's order, from the I-th.
    std::vector<std::string> suite_names;
    suite_names.reserve(scenarios.size());
    for (const auto& sc_ : scenarios) suite_names.push_back(sc_.name);
    std::optional<sc::Shard> shard;
    if (!cli.shard.empty()) {
        shard = sc::parse_shard(cli.shard);
        std::vector<sc::Scenario> mine;
        for (std::size_t k = 0; k < scenarios.size(); ++k) {
            if (shard->contains(k)) mine.push_back(std::move(scenarios[k]));
        }
        scenarios = std::move(mine);
    }
    // Every output path too: a --junit that cannot be written is found now,
    // not after the suite ran and its verdict was printed. Its folder must
    // exist, or be inside --out (made by the run).
    const fs::path out = cli.out_dir;
    std::optional<fs::path> junit_folder_to_make;
    if (!cli.junit.empty()) {
        try {
            const fs::path parent = fs::path(cli.junit).parent_path();
            const fs::path p = fs::weakly_canonical(parent.empty() ? fs::path(".") : parent);
            const fs::path o = fs::weakly_canonical(out);
            const auto rel = p.lexically_relative(o);
            const bool inside_out = !rel.empty() && *rel.begin() != "..";
            if (inside_out && !fs::is_directory(p)) {
                check_output_dir(p);
                junit_folder_to_make = p;
            } else {
                check_output_file(cli.junit);
            }
        } catch (const std::exception& e) {
            throw std::invalid_argument(fmt::format("--junit {}: {}", cli.junit, e.what()));
        }
    }
    prepare_output_dir(out);
    if (junit_folder_to_make) fs::create_directories(*junit_folder_to_make);
    // A scenario folder from an earlier run into this --out that this suite
    // would not rewrite (a scenario since renamed or removed) would read as
    // one of its results: removed.
    for (const auto& e : fs::directory_iterator(out)) {
        if (e.is_directory() && fs::exists(e.path() / "result.json") &&
            std::find(suite_names.begin(), suite_names.end(), e.path().filename().string()) == suite_names.end()) {
            fs::remove_all(e.path());
            std::fprintf(stderr, "ddmr-hil scenario: removed %s (an earlier run's scenario, not in this suite)\n",
                         e.path().string().c_str());
        }
    }
    const std::string exe = self_exe();

    struct Running {
        std::size_t index;
        std::chrono::steady_clock::time_point start;
        bool killed = false;
    };
    std::map<pid_t, Running> running;
    std::vector<std::optional<sc::ScenarioResult>> results(scenarios.size());
    std::size_t next = 0;
    const auto launch = [&](std::size_t i) {
        const sc::Scenario& s = scenarios[i];
        const fs::path dir = out / s.name;
        fs::remove_all(dir);  // an earlier run's files (a failure_window.vcd) are not this run's
        fs::create_directories(dir);
        std::vector<std::string> args = {exe, "scenario", "--worker", s.file.string(), "--out", dir.string()};
        if (!cli.firmware.empty()) args.insert(args.end(), {"--firmware", fs::absolute(cli.firmware).string()});
        for (const auto& lib : cli.libraries) args.insert(args.end(), {"--libraries", fs::absolute(lib).string()});
        if (cli.update_golden) args.emplace_back("--update-golden");
        if (cli.no_fast_forward) args.emplace_back("--no-fast-forward");
        if (cli.progress) {
            args.emplace_back("--progress");
            std::fprintf(stderr, "  start %s (%s)\n", s.name.c_str(), s.file.string().c_str());
        }
        pid_t pid = 0;
        const int rc = spawn_redirected(std::move(args), dir / "stdout.txt", dir / "stderr.txt", pid);
        if (rc != 0) throw std::runtime_error(fmt::format("cannot start a worker for {}: {}", s.file.string(), std::strerror(rc)));
        running[pid] = {i, std::chrono::steady_clock::now(), false};
    };
    const std::size_t workers = std::min<std::size_t>(jobs, scenarios.size());
    std::fprintf(stderr, "ddmr-hil scenario: %zu scenario%s on %zu worker%s, results in %s\n", scenarios.size(),
                 scenarios.size() == 1 ? "" : "s", workers, workers == 1 ? "" : "s", out.string().c_str());
    while (next < scenarios.size() || !running.empty()) {
        while (next < scenarios.size() && running.size() < jobs) launch(next++);
        int status = 0;
        const pid_t pid = waitpid(-1, &status, WNOHANG);
        if (pid < 0) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
        if (pid == 0) {
            // Nobody finished: enforce the wall-clock limit, then wait a little.
            const auto now = std::chrono::steady_clock::now();
            for (auto& [p, run] : running) {
                if (!run.killed && std::chrono::duration<double>(now - run.start).count() > cli.wall_timeout_s) {
                    kill(p, SIGKILL);
                    run.killed = true;
                }
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            continue;
        }
        const auto it = running.find(pid);
        if (it == running.end()) continue;
        const std::size_t i = it->second.index;
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - it->second.start).count();
        const bool killed = it->second.killed;
        running.erase(it);
        results[i] = read_result(scenarios[i], out / scenarios[i].name, status, wall);
        if (killed) {
            results[i]->verdict = sc::Verdict::kFirmware;
            results[i]->message = fmt::format("{}: wall-clock timeout after {} s (--wall-timeout): the worker was stopped",
                                              scenarios[i].file.string(), cli.wall_timeout_s);
        }
        const auto& r = *results[i];
        if (cli.progress) {
            // The worker's step-by-step progress, as it wrote it.
            std::ifstream steps(out / scenarios[i].name / "stderr.txt");
            for (std::string line; std::getline(steps, line);) {
                if (line.rfind("  [", 0) == 0) std::fprintf(stderr, "%s\n", line.c_str());
            }
        }
        std::fprintf(stderr, "  done %-28s %s (%.1f s wall)\n", r.name.c_str(), sc::to_string(r.verdict), wall);
    }

    if (shard) {
        write_file_atomic(out / "shard.json",
                          json{{"shard", shard->text()}, {"suite", suite_names}}.dump(2) + "\n");
    }
    // Verdicts in the order given, and the combined result.
    std::vector<sc::ScenarioResult> all;
    all.reserve(results.size());
    for (auto& r : results) all.push_back(*r);
    return sc::finish_suite(all, out, cli.junit);
}

}  // namespace

Subcommand register_scenario_command(CLI::App& app) {
    auto cli = std::make_shared<ScenarioCli>();
    CLI::App* sub = app.add_subcommand(
        "scenario",
        "Run scenario files (YAML, docs/scenarios.md): firmware regression tests in AVR time with the robot "
        "attached. Exit 0 all passed, 1 a check failed, 2 a scenario or input error, 3 a firmware crash or timeout.");
    sub->add_option("files", cli->files, "Scenario files")->check(CLI::ExistingFile);
    sub->add_flag("--list-steps", cli->list_steps, "Print every step kind with its forms and an example, and exit");
    sub->add_flag("--update-golden", cli->update_golden,
                  "Record what expect-eeprom (its bin/log file) and expect-pose (x_m, y_m, theta_rad in the scenario "
                  "file) steps see instead of checking it; written only when every other step passes");
    sub->add_flag("--no-fast-forward", cli->no_fast_forward,
                  "Execute every pass of the firmware's busy-wait loops instead of skipping them exactly, in "
                  "every scenario (as `fast-forward: false`; docs/fast-forward.md)");
    sub->add_option("--out", cli->out_dir, "Results folder: one sub-folder per scenario, results.json")
        ->capture_default_str();
    sub->add_option("--junit", cli->junit, "Also write JUnit XML here");
    sub->add_option("--firmware", cli->firmware, "Run every scenario on this ELF instead of the one it names");
    sub->add_option("--libraries", cli->libraries,
                    "A folder of Arduino libraries for the sketches scenarios build (repeatable; after the "
                    "sketch's src/ and the scenario's libraries:, before ~/Arduino/libraries; docs/firmware.md)")
        ->check(CLI::ExistingDirectory);
    sub->add_option("-j,--jobs", cli->jobs, "Scenarios run at once, each in its own process [default: all cores]")
        ->check(CLI::Range(1U, 256U));
    sub->add_option("--shard", cli->shard,
                    "Run only the I-th of N round-robin slices of the scenarios given (I = 1..N), e.g. one CI "
                    "matrix job each; `ddmr-hil merge` combines the shards' --out folders (docs/scaling.md)")
        ->option_text("I/N");
    sub->add_option("--wall-timeout", cli->wall_timeout_s,
                    "Wall-clock limit per scenario [s]: a worker still running then is stopped and the scenario "
                    "reported as a timeout (exit 3). Each scenario's own `timeout:` limits simulated time")
        ->check(CLI::Range(1.0, 1e6))
        ->capture_default_str();
    sub->add_flag("--progress", cli->progress, "Print each scenario as it starts, and its steps with their times as it ends");
    sub->add_flag("--worker", cli->worker, "Run one scenario in this process (used by the suite runner)")
        ->group("");  // hidden
    return {sub, [cli] {
        if (cli->list_steps) {
            std::fputs(std::string(sc::step_catalog_text()).c_str(), stdout);
            return kExitOk;
        }
        return cli->worker ? run_worker(*cli) : run_suite(*cli);
    }};
}

}  // namespace ddmr::tools
