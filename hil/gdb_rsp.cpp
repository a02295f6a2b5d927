// The GDB remote serial protocol's pure pieces for avr-gdb: framing, hex,
// registers, address spaces (see gdb_rsp.hpp).
#include "hil/gdb_rsp.hpp"

namespace ddmr::hil::rsp {
namespace {

constexpr char kHexDigits[] = "0123456789abcdef";

int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

bool needs_escape(char c) { return c == '$' || c == '#' || c == '}' || c == '*'; }

constexpr char kEscape = '}';
constexpr uint8_t kEscapeXor = 0x20;

void append_le(std::string& out, uint32_t value, std::size_t bytes) {
    for (std::size_t i = 0; i < bytes; ++i) {
        const auto b = static_cast<uint8_t>(value >> (8 * i));
        out.push_back(kHexDigits[b >> 4]);
        out.push_back(kHexDigits[b & 0x0F]);
    }
}

uint32_t read_le(const std::vector<uint8_t>& bytes, std::size_t at, std::size_t count) {
    uint32_t v = 0;
    for (std::size_t i = 0; i < count; ++i) v |= static_cast<uint32_t>(bytes[at + i]) << (8 * i);
    return v;
}

}  // namespace

uint8_t checksum(std::string_view payload) {
    unsigned sum = 0;
    for (char c : payload) sum += static_cast<unsigned char>(c);
    return static_cast<uint8_t>(sum & 0xFFU);
}

std::string frame(std::string_view payload) {
    std::string body;
    body.reserve(payload.size() + 8);
    for (char c : payload) {
        if (needs_escape(c)) {
            body.push_back(kEscape);
            body.push_back(static_cast<char>(static_cast<uint8_t>(c) ^ kEscapeXor));
        } else {
            body.push_back(c);
        }
    }
    const uint8_t cs = checksum(body);
    std::string out = "$" + body + "#";
    out.push_back(kHexDigits[cs >> 4]);
    out.push_back(kHexDigits[cs & 0x0F]);
    return out;
}

std::string to_hex(const uint8_t* bytes, std::size_t count) {
    std::string out;
    out.reserve(2 * count);
    for (std::size_t i = 0; i < count; ++i) {
        out.push_back(kHexDigits[bytes[i] >> 4]);
        out.push_back(kHexDigits[bytes[i] & 0x0F]);
    }
    return out;
}

std::string to_hex(const std::vector<uint8_t>& bytes) { return to_hex(bytes.data(), bytes.size()); }

std::optional<std::vector<uint8_t>> from_hex(std::string_view hex) {
    if (hex.size() % 2 != 0) return std::nullopt;
    std::vector<uint8_t> out(hex.size() / 2);
    for (std::size_t i = 0; i < out.size(); ++i) {
        const int hi = hex_value(hex[2 * i]);
        const int lo = hex_value(hex[2 * i + 1]);
        if (hi < 0 || lo < 0) return std::nullopt;
        out[i] = static_cast<uint8_t>(hi << 4 | lo);
    }
    return out;
}

std::optional<uint64_t> parse_hex_number(std::string_view hex) {
    if (hex.empty() || hex.size() > 16) return std::nullopt;
    uint64_t v = 0;
    for (char c : hex) {
        const int d = hex_value(c);
        if (d < 0) return std::nullopt;
        v = v << 4 | static_cast<uint64_t>(d);
    }
    return v;
}

std::string unescape(std::string_view raw) {
    std::string out;
    out.reserve(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] == kEscape) {
            if (++i == raw.size()) break;
            out.push_back(static_cast<char>(static_cast<uint8_t>(raw[i]) ^ kEscapeXor));
        } else {
            out.push_back(raw[i]);
        }
    }
    return out;
}

std::optional<Event> PacketReader::feed(char byte) {
    constexpr char kInterruptByte = 0x03;
    if (byte == '$') {  // a packet starts (a '$' in a payload is always escaped)
        state_ = State::kPayload;
        raw_.clear();
        return std::nullopt;
    }
    switch (state_) {
        case State::kIdle:
            if (byte == '+') return Event{Event::Kind::kAck, {}};
            if (byte == '-') return Event{Event::Kind::kNak, {}};
            if (byte == kInterruptByte) return Event{Event::Kind::kInterrupt, {}};
            return std::nullopt;
        case State::kPayload:
            if (byte == '#') {
                state_ = State::kChecksumHigh;
            } else {
                raw_.push_back(byte);
            }
            return std::nullopt;
        case State::kChecksumHigh:
            checksum_high_ = hex_value(byte);
            state_ = State::kChecksumLow;
            return std::nullopt;
        case State::kChecksumLow: {
            state_ = State::kIdle;
            const int low = hex_value(byte);
            if (checksum_high_ < 0 || low < 0 || (checksum_high_ << 4 | low) != checksum(raw_)) {
                return Event{Event::Kind::kBadChecksum, {}};
            }
            return Event{Event::Kind::kPacket, unescape(raw_)};
        }
    }
    return std::nullopt;
}

std::size_t register_size(unsigned regno) {
    if (regno <= kRegSreg) return 1;
    if (regno == kRegSp) return 2;
    if (regno == kRegPc) return 4;
    return 0;
}

std::string encode_registers(const AvrRegisters& regs) {
    std::string out = to_hex(regs.r.data(), regs.r.size());
    append_le(out, regs.sreg, 1);
    append_le(out, regs.sp, 2);
    append_le(out, regs.pc, 4);
    return out;
}

bool decode_registers(std::string_view hex, AvrRegisters& regs) {
    const auto bytes = from_hex(hex);
    if (!bytes || bytes->size() != kRegisterPacketBytes) return false;
    for (std::size_t i = 0; i < regs.r.size(); ++i) regs.r[i] = (*bytes)[i];
    regs.sreg = (*bytes)[32];
    regs.sp = static_cast<uint16_t>(read_le(*bytes, 33, 2));
    regs.pc = read_le(*bytes, 35, 4);
    return true;
}

std::string encode_register(const AvrRegisters& regs, unsigned regno) {
    std::string out;
    if (regno < kRegSreg) {
        append_le(out, regs.r[regno], 1);
    } else if (regno == kRegSreg) {
        append_le(out, regs.sreg, 1);
    } else if (regno == kRegSp) {
        append_le(out, regs.sp, 2);
    } else if (regno == kRegPc) {
        append_le(out, regs.pc, 4);
    }
    return out;
}

bool decode_register(unsigned regno, std::string_view hex, AvrRegisters& regs) {
    const std::size_t size = register_size(regno);
    const auto bytes = from_hex(hex);
    if (size == 0 || !bytes || bytes->size() != size) return false;
    const uint32_t v = read_le(*bytes, 0, size);
    if (regno < kRegSreg) {
        regs.r[regno] = static_cast<uint8_t>(v);
    } else if (regno == kRegSreg) {
        regs.sreg = static_cast<uint8_t>(v);
    } else if (regno == kRegSp) {
        regs.sp = static_cast<uint16_t>(v);
    } else {
        regs.pc = v;
    }
    return true;
}

std::string stop_reply(int signal, const AvrRegisters& regs) {
    std::string out = "T";
    append_le(out, static_cast<uint32_t>(signal), 1);
    for (unsigned regno : {kRegSreg, kRegSp, kRegPc}) {
        append_le(out, regno, 1);
        out.push_back(':');
        out += encode_register(regs, regno);
        out.push_back(';');
    }
    return out;
}

std::optional<SpaceAddress> decode_address(uint64_t gdb_address) {
    if (gdb_address < kDataBase) return SpaceAddress{Space::kFlash, static_cast<uint32_t>(gdb_address)};
    if (gdb_address < kEepromBase) {
        return SpaceAddress{Space::kData, static_cast<uint32_t>(gdb_address - kDataBase)};
    }
    if (gdb_address < kEepromEnd) {
        return SpaceAddress{Space::kEeprom, static_cast<uint32_t>(gdb_address - kEepromBase)};
    }
    return std::nullopt;
}

std::optional<MemoryRange> parse_memory_range(std::string_view args) {
    const auto comma = args.find(',');
    if (comma == std::string_view::npos) return std::nullopt;
    const auto address = parse_hex_number(args.substr(0, comma));
    const auto length = parse_hex_number(args.substr(comma + 1));
    if (!address || !length) return std::nullopt;
    return MemoryRange{*address, *length};
}

std::optional<BreakpointRequest> parse_breakpoint(std::string_view args) {
    const auto c1 = args.find(',');
    if (c1 == std::string_view::npos) return std::nullopt;
    const auto c2 = args.find(',', c1 + 1);
    if (c2 == std::string_view::npos) return std::nullopt;
    // Conditions or commands after ';' (Z0,addr,kind;X...) are not supported.
    const auto end = args.find(';', c2 + 1);
    const auto type = parse_hex_number(args.substr(0, c1));
    const auto address = parse_hex_number(args.substr(c1 + 1, c2 - c1 - 1));
    const auto kind = parse_hex_number(args.substr(c2 + 1, end == std::string_view::npos ? end : end - c2 - 1));
    if (!type || !address || !kind || *type > 4) return std::nullopt;
    return BreakpointRequest{static_cast<unsigned>(*type), *address, *kind};
}

}  // namespace ddmr::hil::rsp
