#pragma once
// The datasheet's name of an I/O register at a data-space address, from the
// MCU description (hil/mcu.hpp): PIND, TCNT0, UCSR0A, OCR1AL, EIMSK...; an
// address the description does not name is "I/O 0x4e". For messages:
// fast-forward's refusals (hil/fast_forward.hpp), the machine states that
// differ (hil/machine_state.hpp).

#include <cstdint>
#include <string>

namespace ddmr::hil {

struct McuDescription;

/// The register's name, or "I/O 0xNN" (data-space address) if it has none.
std::string io_register_name(const McuDescription& mcu, uint16_t address);

}  // namespace ddmr::hil
