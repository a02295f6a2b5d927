#pragma once
// Calls and jumps to flash address 0 in a firmware ELF, found before it runs.
//
// Address 0 is the reset vector: a CALL or JMP there restarts the firmware
// without a reset (the chip's registers keep their values). The usual cause is
// a weak reference the link left unresolved: Debian's Arduino core declares
// `operator new` weak (its <new>), so a sketch that includes it never pulls
// new.o from the core's archive, and `new` links to `call 0`. An unresolved
// weak symbol leaves no relocation in the linked ELF, so which symbol a call
// was meant for is not recorded; the ELF's unresolved weak symbols are named
// as the candidates.
//
// Code is decoded from each sized symbol in .text (functions and libgcc's
// assembly routines), never the PROGMEM data between them. Not reported:
//   - __bad_interrupt's `jmp 0` (avr-libc's handler of an unused vector): a
//     label without a size in gcrt1.S, so never decoded;
//   - a call the code tests first, as the core's serialEventRun tests the weak
//     serialEvent: a conditional branch past the call, within kGuardWindow
//     instructions before it, right after a test of a zero-loaded register
//     pair (the weak symbol's address, `ldi r24, lo8(gs(f)); ldi r25,
//     hi8(gs(f))`, is 0 once linked).
//
//   ElfImage => ZeroCallReport => one warning line per call

#include <cstdint>
#include <string>
#include <vector>

#include "hil/elf_image.hpp"

namespace ddmr::hil {

/// A CALL, JMP, RCALL or RJMP to address 0 that nothing guards.
struct ZeroCall {
    uint32_t pc = 0;          ///< flash byte address of the instruction
    std::string instruction;  ///< "call", "jmp", "rcall" or "rjmp"
    std::string function;     ///< the (demangled) function it is in, or empty
};

struct ZeroCallReport {
    std::vector<ZeroCall> calls;                ///< by address
    std::vector<std::string> unresolved_weak;   ///< demangled names, sorted
};

/// Instructions before a call to 0 searched for the test that guards it.
inline constexpr std::size_t kGuardWindow = 16;

/// The unguarded calls and jumps to 0 in `elf`'s code, and its unresolved
/// weak symbols (undefined, or weak with value 0 outside the toolchain's own
/// `__` names).
ZeroCallReport find_zero_calls(const ElfImage& elf);

/// One line per call, without a prefix: "`call 0` at 0x0a3c in setup():
/// ...restarts the firmware... (the unresolved weak symbol operator
/// new(unsigned int) ...)".
std::vector<std::string> describe_zero_calls(const ZeroCallReport& report);

}  // namespace ddmr::hil
