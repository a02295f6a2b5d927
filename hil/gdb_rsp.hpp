#pragma once
// The GDB remote serial protocol as avr-gdb (Debian's gdb-avr 12.1) speaks it
// to an ATmega328P, without sockets: packet framing, hex, the register
// layout and the address spaces. GdbServer (gdb_server.hpp) puts these on a
// loopback TCP socket; the pieces here are pure functions and a byte-at-a-time
// reader, so they are tested on their own.
//
// Framing (GDB manual, "Overview" of the remote protocol):
//   $<payload>#<cs>   cs = sum of the payload's bytes mod 256, two hex digits;
//   '$' '#' '}' '*' inside a payload are sent as '}' followed by the byte XOR 0x20;
//   '+' / '-' acknowledge a packet; a lone 0x03 byte is an interrupt (Ctrl-C).
// Run-length encoding ('*') is only allowed in replies: this side never sends
// it and, as gdb never sends it, takes an incoming '*' literally.
//
// avr-gdb's target description (gdb/avr-tdep.c):
//   registers r0..r31 (numbers 0..31, 1 byte), SREG (32, 1 byte),
//   SP (33, 2 bytes little-endian), PC (34, 4 bytes little-endian, a flash
//   *byte* address): the 'g' packet holds 39 bytes, 78 hex digits.
//   Addresses: below 0x800000 flash (byte address), 0x800000 + a the data
//   space (registers, I/O, SRAM), 0x810000 + a the EEPROM.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ddmr::hil::rsp {

/// Modulo-256 sum of the bytes of `payload`, as sent (escapes included).
uint8_t checksum(std::string_view payload);

/// "$" + escaped payload + "#" + checksum, ready to send.
std::string frame(std::string_view payload);

/// Lower-case hex of `bytes`, two digits per byte.
std::string to_hex(const uint8_t* bytes, std::size_t count);
std::string to_hex(const std::vector<uint8_t>& bytes);
/// Bytes of an even-length hex string; nullopt if it is not one.
std::optional<std::vector<uint8_t>> from_hex(std::string_view hex);
/// An unsigned hex number ("1a2b"); nullopt if empty, not hex or over 64 bits.
std::optional<uint64_t> parse_hex_number(std::string_view hex);

/// What a byte from gdb completed.
struct Event {
    enum class Kind {
        kPacket,       ///< a packet with a good checksum: `payload` holds it, unescaped
        kBadChecksum,  ///< a packet whose checksum did not match: answer '-'
        kInterrupt,    ///< 0x03 outside a packet: gdb's Ctrl-C
        kAck,          ///< '+'
        kNak,          ///< '-': resend the last packet
    };
    Kind kind = Kind::kPacket;
    std::string payload;
};

/// Reassembles gdb's byte stream into events. Bytes outside a packet other
/// than '$', '+', '-' and 0x03 are ignored; a '$' inside a packet restarts it.
class PacketReader {
public:
    std::optional<Event> feed(char byte);

private:
    enum class State { kIdle, kPayload, kChecksumHigh, kChecksumLow };
    State state_ = State::kIdle;
    std::string raw_;          ///< payload as received (escapes kept)
    int checksum_high_ = 0;    ///< the checksum's first digit; -1 if not hex
};

/// Removes '}' escapes (the byte after '}' is XOR 0x20). A trailing lone '}'
/// is dropped.
std::string unescape(std::string_view raw);

// --- avr-gdb's AVR target -------------------------------------------------

inline constexpr unsigned kRegisterCount = 35;  ///< r0..r31, SREG, SP, PC
inline constexpr unsigned kRegSreg = 32;
inline constexpr unsigned kRegSp = 33;
inline constexpr unsigned kRegPc = 34;
inline constexpr std::size_t kRegisterPacketBytes = 32 + 1 + 2 + 4;  ///< 'g': 39 bytes

/// The CPU state gdb sees.
struct AvrRegisters {
    std::array<uint8_t, 32> r{};  ///< r0..r31
    uint8_t sreg = 0;
    uint16_t sp = 0;      ///< data-space address
    uint32_t pc = 0;      ///< flash byte address
};

/// Size in bytes of register `regno` in avr-gdb's layout; 0 if it has none.
std::size_t register_size(unsigned regno);
/// The 'g' reply: 39 bytes as hex, in register-number order.
std::string encode_registers(const AvrRegisters& regs);
/// A 'G' payload (78 hex digits) into `regs`; false (regs untouched) if malformed.
bool decode_registers(std::string_view hex, AvrRegisters& regs);
/// The 'p' reply for one register; empty if `regno` is not a register.
std::string encode_register(const AvrRegisters& regs, unsigned regno);
/// A 'P' value (little-endian hex of the register's size) into `regs`.
bool decode_register(unsigned regno, std::string_view hex, AvrRegisters& regs);

/// The stop reply "T<signal>" with SREG, SP and PC expedited (gdb then needs
/// no 'g' to show where the target stopped).
std::string stop_reply(int signal, const AvrRegisters& regs);

/// POSIX signal numbers gdb uses in stop replies.
inline constexpr int kSigInt = 2;   ///< stopped by the user's Ctrl-C
inline constexpr int kSigTrap = 5;  ///< breakpoint, step, or the stop before the first instruction

enum class Space { kFlash, kData, kEeprom };
struct SpaceAddress {
    Space space = Space::kFlash;
    uint32_t offset = 0;  ///< byte offset within the space
};
inline constexpr uint64_t kDataBase = 0x800000;    ///< avr-gdb's data-space offset
inline constexpr uint64_t kEepromBase = 0x810000;  ///< avr-gdb's EEPROM offset
inline constexpr uint64_t kEepromEnd = 0x820000;   ///< fuses and lock bits follow: not served

/// The space and offset of one of avr-gdb's addresses; nullopt past the EEPROM.
std::optional<SpaceAddress> decode_address(uint64_t gdb_address);

/// "addr,length" (the arguments of m, M and X before any ':').
struct MemoryRange {
    uint64_t address = 0;
    uint64_t length = 0;
};
std::optional<MemoryRange> parse_memory_range(std::string_view args);

/// "type,addr,kind" (the arguments of Z and z).
struct BreakpointRequest {
    unsigned type = 0;  ///< 0 software, 1 hardware, 2 write, 3 read, 4 access watchpoint
    uint64_t address = 0;
    uint64_t kind = 0;  ///< breakpoint length in bytes (2 on AVR)
};
std::optional<BreakpointRequest> parse_breakpoint(std::string_view args);

}  // namespace ddmr::hil::rsp
