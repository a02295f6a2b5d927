#pragma once
// MachineState: a robot's whole observable state at one instant between two
// instructions, as two runs of one firmware are compared (the fast-forward
// verification, tools/fast_forward_verify.hpp): the cycle, the PC, the data
// space (r0-r31, the I/O registers, SRAM), the EEPROM and the plant's state.
//
// Registers simavr keeps elsewhere are read as the firmware would read them:
// SREG from the core's flags, TCNTn as a read of it returns (simavr computes
// the count when it is read; the byte in the data space is the last read's).
// Capturing changes nothing in the run.
//
// compare_machine_states() names each difference as a person debugging the
// firmware would look for it: "r24", "SREG", "TCNT0", "SRAM 0x01a4
// (loop_count+1)", "EEPROM 0x010", "plant x_m".

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hil/cycle_time.hpp"
#include "hil/plant_coupler.hpp"

struct avr_t;

namespace ddmr::hil {

class RobotRig;
class DataObjects;
struct McuDescription;

struct MachineState {
    Cycles cycle = 0;
    uint32_t pc = 0;            ///< flash byte address of the next instruction
    std::vector<uint8_t> data;  ///< data space 0..RAMEND
    std::vector<uint8_t> eeprom;
    TruthSample plant;  ///< the plant's state and input (truth.csv's columns)
};

/// SREG as the firmware would read it: simavr 1.6 keeps it split into
/// sreg[0..7] (one flag per byte) and updates data[SREG] only on reads.
uint8_t sreg_of(const avr_t* avr);

/// The rig's state now (between two instructions).
MachineState capture_machine_state(RobotRig& rig);

/// One difference: what differs, its value in each state (as text).
struct StateDifference {
    std::string what;
    std::string a, b;
};

struct StateComparison {
    std::vector<StateDifference> shown;  ///< the first `max_shown`, in the order cycle, PC, data, EEPROM, plant
    std::size_t total = 0;               ///< every byte and value that differs
    [[nodiscard]] bool equal() const { return total == 0; }
};

/// The differences between `a` and `b` (states of the same MCU). `objects`
/// (may be null) names SRAM bytes by the firmware's variables.
StateComparison compare_machine_states(const MachineState& a, const MachineState& b, const McuDescription& mcu,
                                       const DataObjects* objects, std::size_t max_shown = 16);

/// The name of data-space byte `address`: "r24", an I/O register
/// (hil/io_register_name.hpp), "SRAM 0x01a4" with its variable if known.
std::string data_byte_name(uint16_t address, const McuDescription& mcu, const DataObjects* objects);

}  // namespace ddmr::hil
