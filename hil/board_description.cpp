#include "hil/board_description.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace ddmr::hil {
namespace {

/// variants/standard (Uno) and variants/eightanaloginputs (Nano, Pro Mini;
/// A6/A7 there are ADC-only inputs without a port bit, not digital pins):
/// D0-D7 = PD0-PD7, D8-D13 = PB0-PB5, A0-A5 = D14-D19 = PC0-PC5.
std::vector<PortBit> standard_variant_pins() {
    std::vector<PortBit> p;
    for (uint8_t b = 0; b < 8; ++b) p.push_back({'D', b});
    for (uint8_t b = 0; b < 6; ++b) p.push_back({'B', b});
    for (uint8_t b = 0; b < 6; ++b) p.push_back({'C', b});
    return p;
}

/// variants/mega (pins_arduino.h's digital_pin_to_port/bit tables): D0..D53,
/// then A0..A15 = D54..D69 (PF0..PF7, PK0..PK7).
std::vector<PortBit> mega_variant_pins() {
    static constexpr const char* kPins =
        "E0E1E4E5G5E3H3H4H5H6B4B5B6B7J1J0H1H0D3D2D1D0A0A1A2A3A4A5A6A7C7C6C5C4C3C2C1C0D7G2G1G0L7L6L5L4L3L2L1L0B3B2"
        "B1B0F0F1F2F3F4F5F6F7K0K1K2K3K4K5K6K7";
    std::vector<PortBit> p;
    for (const char* c = kPins; *c != '\0'; c += 2) p.push_back({c[0], static_cast<uint8_t>(c[1] - '0')});
    return p;
}

BoardDescription make(BoardModel model, const char* key, const char* label, const char* fqbn, uint32_t clock_hz,
                      std::vector<const char*> analog_only) {
    BoardDescription d;
    d.model = model;
    d.key = key;
    d.label = label;
    d.fqbn = fqbn;
    d.mcu = &atmega328p_mcu();
    d.clock_hz = clock_hz;
    // The 8 MHz Pro Mini is the 3.3 V one (boards.txt: "3.3V, 8 MHz").
    d.supply_v = clock_hz == 8'000'000 ? 3.3 : 5.0;
    d.pins = standard_variant_pins();
    d.analog0 = 14;
    d.analog_only = std::move(analog_only);
    d.console_usart = 0;
    return d;
}

BoardDescription mega2560() {
    BoardDescription d;
    d.model = BoardModel::mega2560;
    d.key = "mega2560";
    d.label = "Arduino Mega 2560";
    d.fqbn = "arduino:avr:mega:cpu=atmega2560";
    d.mcu = &atmega2560_mcu();
    d.clock_hz = 16'000'000;
    d.supply_v = 5.0;
    d.pins = mega_variant_pins();
    d.analog0 = 54;
    d.console_usart = 0;  // Serial: USART0 on D0/D1 (PE0/PE1), the USB-serial chip's
    return d;
}

const std::vector<BoardDescription>& boards() {
    static const std::vector<BoardDescription> all = {
        make(BoardModel::uno, "uno", "Arduino Uno", "arduino:avr:uno", 16'000'000, {}),
        make(BoardModel::nano, "nano", "Arduino Nano (ATmega328P)", "arduino:avr:nano:cpu=atmega328", 16'000'000,
             {"A6", "A7"}),
        make(BoardModel::pro_mini_8mhz, "pro-mini-8mhz", "Arduino Pro Mini 3.3 V (ATmega328P, 8 MHz)",
             "arduino:avr:pro:cpu=8MHzatmega328", 8'000'000, {"A6", "A7"}),
        mega2560(),
    };
    return all;
}

}  // namespace

const BoardDescription& board_description(BoardModel model) {
    for (const BoardDescription& b : boards()) {
        if (b.model == model) return b;
    }
    return boards().front();
}

const std::vector<BoardModel>& board_models() {
    static const std::vector<BoardModel> models = [] {
        std::vector<BoardModel> m;
        for (const BoardDescription& b : boards()) m.push_back(b.model);
        return m;
    }();
    return models;
}

std::optional<BoardModel> parse_board_key(const std::string& key) {
    for (const BoardDescription& b : boards()) {
        if (key == b.key) return b.model;
    }
    return std::nullopt;
}

std::string board_key_list() {
    std::string s;
    const std::vector<BoardDescription>& all = boards();
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (i > 0) s += i + 1 == all.size() ? " or " : ", ";
        s += all[i].key;
    }
    return s;
}

std::optional<int> pin_number_of(const BoardDescription& board, PortBit at) {
    for (int n = 0; n < board.pin_count(); ++n) {
        const PortBit p = board.pins[static_cast<std::size_t>(n)];
        if (p.port == at.port && p.bit == at.bit) return n;
    }
    return std::nullopt;
}

char usart_irq_name(const UsartDesc& usart) { return static_cast<char>('0' + usart.index); }

std::string serial_port_name(int usart_index) {
    return usart_index == 0 ? std::string("Serial") : "Serial" + std::to_string(usart_index);
}

std::optional<int> parse_serial_port(const BoardDescription& board, const std::string& name) {
    for (const UsartDesc& u : board.mcu->usarts) {
        if (name == serial_port_name(u.index)) return u.index;
    }
    return std::nullopt;
}

std::string serial_port_list(const BoardDescription& board) {
    std::string s;
    const std::vector<UsartDesc>& all = board.mcu->usarts;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (i > 0) s += i + 1 == all.size() ? " or " : ", ";
        s += serial_port_name(all[i].index);
    }
    return s;
}

std::optional<PinInfo> board_pin(const BoardDescription& board, int number) {
    if (number < 0 || number >= board.pin_count()) return std::nullopt;
    const PortBit at = board.pins[static_cast<std::size_t>(number)];
    const McuDescription& mcu = *board.mcu;
    const PortRegisters* regs = mcu.port(at.port);
    if (regs == nullptr) return std::nullopt;
    PinInfo p;
    p.number = number;
    p.port = at.port;
    p.bit = at.bit;
    p.pin_register = regs->pin;
    p.ddr_register = regs->ddr;
    p.port_register = regs->port_register;
    p.oc = mcu.oc_at(at);
    p.ext_int = mcu.ext_int_at(at);
    if (const auto k = mcu.pcint_at(at)) {
        p.pcint_group = *k / 8;
        p.pcint_bit = *k % 8;
    }
    return p;
}

std::optional<int> parse_pin_name(const BoardDescription& board, const std::string& name) {
    if (name.empty()) return std::nullopt;
    std::string digits = name;
    int offset = 0;
    const auto first = static_cast<char>(std::toupper(static_cast<unsigned char>(name[0])));
    if (first == 'A') {
        digits = name.substr(1);
        offset = board.analog0;
    } else if (first == 'D') {
        digits = name.substr(1);
    }
    if (digits.empty() || digits.size() > 2) return std::nullopt;
    if (!std::all_of(digits.begin(), digits.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; })) {
        return std::nullopt;
    }
    const int n = std::stoi(digits) + offset;
    if (n >= board.pin_count()) return std::nullopt;
    return n;
}

std::string pin_label(const BoardDescription& board, int number) {
    if (number >= board.analog0) return fmt::format("A{}", number - board.analog0);
    return fmt::format("D{}", number);
}

std::string sketch_pin_name(const BoardDescription& board, int number) {
    if (number >= board.analog0) return pin_label(board, number);
    return std::to_string(number);
}

std::string pin_range(const BoardDescription& board) {
    return fmt::format("0..{}, A0..A{}", board.analog0 - 1, board.pin_count() - 1 - board.analog0);
}

std::string pwm_pin_list(const BoardDescription& board) {
    std::vector<std::string> pwm;
    for (int n = 0; n < board.pin_count(); ++n) {
        if (board_pin(board, n)->oc) pwm.push_back(sketch_pin_name(board, n));
    }
    std::string s;
    for (std::size_t i = 0; i < pwm.size(); ++i) {
        if (i > 0) s += i + 1 == pwm.size() ? " and " : ", ";
        s += pwm[i];
    }
    return s;
}

}  // namespace ddmr::hil
