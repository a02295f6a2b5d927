#include "sweep_results.hpp"

#include <fmt/format.h>

#include <fstream>
#include <iterator>
#include <stdexcept>

#include "common/atomic_file.hpp"

namespace ddmr::tools {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string run_file(std::size_t k, const char* ext) { return fmt::format("run-{:04d}.{}", k + 1, ext); }

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    if (!in) throw std::runtime_error(p.string() + ": missing (is this the --out folder of `sweep --shard`?)");
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

json read_json(const fs::path& p) {
    try {
        return json::parse(read_file(p));
    } catch (const json::exception& e) {
        throw std::runtime_error(p.string() + ": malformed JSON: " + e.what());
    }
}

}  // namespace

bool stopped_early(const SweepRunRecord& r) { return r.summary.value("status", "") != "ok"; }

void write_sweep_folder(const fs::path& dir, const json& header, const std::vector<SweepRunRecord>& records) {
    json sweep = header;
    json& studies = sweep.at("studies");
    for (std::size_t s = 0; s < studies.size(); ++s) {
        std::string csv = kSweepCsvHeader;
        json& runs = studies[s]["runs"];
        for (const SweepRunRecord& r : records) {
            if (r.study != s) continue;
            runs.push_back(r.summary);
            csv += r.csv_rows;
        }
        write_file_atomic(dir / (studies[s].at("id").get<std::string>() + ".csv"), csv);
    }
    write_file_atomic(dir / "sweep.json", sweep.dump(2) + "\n");
}

void write_sweep_shard(const fs::path& dir, const SweepShard& s, const std::vector<const SweepRunRecord*>& records) {
    for (std::size_t k = 0; k < records.size(); ++k) {
        if (records[k] == nullptr) continue;
        write_file_atomic(dir / run_file(k, "json"), records[k]->summary.dump(2) + "\n");
        write_file_atomic(dir / run_file(k, "csv"), kSweepCsvHeader + records[k]->csv_rows);
    }
    // Last: a folder with a shard.json is complete.
    const json shard = {{"shard", s.shard.text()}, {"sweep", s.header}, {"run_study", s.run_study}};
    write_file_atomic(dir / "shard.json", shard.dump(2) + "\n");
}

bool is_sweep_shard(const fs::path& dir) {
    std::ifstream in(dir / "shard.json");
    if (!in) return false;
    const json j = json::parse(in, nullptr, /*allow_exceptions=*/false);
    return j.is_object() && j.contains("sweep");
}

SweepShard read_sweep_shard(const fs::path& dir) {
    const fs::path p = dir / "shard.json";
    const json j = read_json(p);
    try {
        SweepShard s;
        s.shard = scenario::parse_shard(j.at("shard").get<std::string>());
        s.header = j.at("sweep");
        s.run_study = j.at("run_study").get<std::vector<std::size_t>>();
        if (!s.header.at("studies").is_array()) throw std::runtime_error("\"studies\" is not a list");
        for (const std::size_t study : s.run_study) {
            if (study >= s.header["studies"].size()) throw std::runtime_error("run_study names no study");
        }
        return s;
    } catch (const std::exception& e) {
        throw std::runtime_error(p.string() + ": not a sweep shard: " + e.what());
    }
}

SweepRunRecord read_sweep_run(const fs::path& dir, std::size_t k, std::size_t study) {
    SweepRunRecord r;
    r.study = study;
    r.summary = read_json(dir / run_file(k, "json"));
    const fs::path csv_path = dir / run_file(k, "csv");
    std::string csv = read_file(csv_path);
    const std::string_view header = kSweepCsvHeader;
    if (csv.compare(0, header.size(), header) != 0) {
        throw std::runtime_error(csv_path.string() + ": does not start with the sweep CSV header");
    }
    r.csv_rows = csv.substr(header.size());
    return r;
}

}  // namespace ddmr::tools
