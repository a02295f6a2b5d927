#pragma once
// RunPlan: a `ddmr-hil run` checked before anything is written. Every
// option, the sketch contract and what they name in the ELF are validated
// here (throws std::invalid_argument / std::runtime_error with one line
// naming the bad value); run_firmware then builds its Session from the plan.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "firmware_run.hpp"
#include "hil/board_description.hpp"
#include "hil/eeprom_port.hpp"
#include "hil/elf_image.hpp"
#include "hil/firmware_variables.hpp"
#include "hil/loop_tracer.hpp"
#include "hil/robot_rig.hpp"
#include "hil/sketch_contract.hpp"
#include "hil/zero_calls.hpp"

namespace ddmr::tools {

struct RunPlan {
    std::optional<hil::SketchContract> contract;
    int test_case = 0;        ///< the contract's case (0: it takes none)
    bool has_start = false;   ///< the contract has a start text
    std::string start_text;
    hil::ElfImage elf;
    hil::RigConfig config;
    const hil::BoardDescription* board = nullptr;
    std::optional<hil::ElfSymbol> ready;  ///< the boot ends when it first returns
    std::string ready_symbol;
    std::vector<hil::TracedVariable> traced;  ///< firmware.csv's columns (the marker among them)
    std::optional<hil::TracedVariable> loop_marker;
    std::vector<hil::TracedVariable> trace_vars;  ///< --trace
    bool reports = false;             ///< the contract's report is parsed
    bool contract_completes = false;  ///< the contract's `complete` ends the run
    bool completes = false;           ///< something ends the run before --seconds (contract or --unity)
    std::optional<hil::ElfSymbol> loop_mark;  ///< with --profile
    std::string loop_mark_name;
    std::vector<FirmwareRunOptions::Send> sends;  ///< sorted by time
    std::optional<hil::EepromImage> preload;
    std::string sha256;
    hil::ZeroCallReport zero_calls;  ///< unguarded calls to address 0 in the ELF
};

/// The reference sketch's contract when `firmware` is the build's reference
/// ELF itself (what `run` and the Python API take when no contract is given).
std::optional<std::filesystem::path> reference_contract_for(const std::filesystem::path& firmware);

/// Checks `options` and what they name; nothing is written.
RunPlan plan_firmware_run(const FirmwareRunOptions& options);

/// "name[:type]" -> a traced variable; the type defaults by the symbol's size.
hil::TracedVariable parse_trace_spec(const std::string& spec, const hil::ElfImage& elf);

}  // namespace ddmr::tools
