#pragma once
// TwiSlave: a device on the chip's I2C bus (TWI) at a 7-bit address, with a
// bank of 8-bit registers as common sensors have them (an MPU-6050, a
// compass, an EEPROM with one address byte):
//   - write: S, SLA+W, register pointer, data..., P: the first byte written
//     sets the pointer, each later byte is stored at the pointer, which then
//     increments;
//   - read:  S, SLA+R, data..., P: each byte is read from the pointer, which
//     then increments (the master sends ACK for more, NACK for the last);
//   - the pointer survives a STOP and a repeated START (the MPU-6050's
//     I2Cdev reads after a STOP: ../shared/SENSORS.md section 5); it wraps
//     from 0xFF to 0x00.
// The master is the firmware (the Wire library, or TWBR/TWCR/TWDR/TWSR by
// hand: ATmega328P datasheet section 22 "2-wire Serial Interface", 22.7
// "Using the TWI", Tables 22-3 and 22-4 status codes). A device at another
// address does not answer: the firmware sees NACK, TWSR 0x20 after SLA+W and
// 0x48 after SLA+R.
//
// Signals (simavr 1.6, avr_twi.{c,h}; messages avr_twi_msg_t {msg, addr, data}):
//   in   TWI_IRQ_OUTPUT of TWI '0': START (addr = SLA+R/W), WRITE (a data
//        byte), READ (a byte wanted; ACK set when the master will ACK it), STOP
//   out  TWI_IRQ_INPUT: ACK (data 1) to a START at this address and to each
//        byte written, READ carrying the byte asked for; all from inside the
//        master's message, as simavr requires.
//   in   TWI_IRQ_STATUS: each TWSR status simavr sets (see below)
// simavr 1.6 times each address or data byte as 9 us whatever TWBR says
// (about 10x a 100 kHz bus), and START at once. It also reports SLA+W with
// the data-byte codes (0x28 ACK, 0x30 NACK) at once when the firmware wrote
// TWDR before TWCR, as the datasheet's sequence does (avr_twi.c: the write
// latch flag is still set from the TWDR write): every TwiSlave puts the
// datasheet's 0x18 / 0x20 into TWSR before TWINT is raised (the code of a
// bus with no slave is still wrong without one). And simavr 1.6 leaves TWINT
// set when the firmware writes 1 to it (the vector's flag is "sticky"), so a
// master that polls TWINT, as the datasheet's examples do, would not wait
// for its byte: the first TwiSlave of a core adds a TWCR write handler that
// clears TWINT on a written 1 (section 22.9.2). It stays installed (simavr
// 1.6 cannot remove a write handler; it holds no pointer to the slave).
// Not thread-safe (like AvrCore). Construct after the AvrCore, destroy before.

#include <array>
#include <cstdint>
#include <functional>

#include "hil/avr_core.hpp"

struct avr_irq_t;

namespace ddmr::hil {

/// Bus traffic a TwiSlave saw (for tests and traces).
struct TwiSlaveStats {
    uint64_t transactions = 0;    ///< STARTs addressed to this device (repeated ones too)
    uint64_t bytes_written = 0;   ///< bytes the master wrote (the pointer byte too)
    uint64_t bytes_read = 0;      ///< bytes the master read
};

class TwiSlave {
public:
    /// (register, value): the master wrote `value` into `register`.
    using WriteListener = std::function<void(uint8_t, uint8_t)>;
    /// (register): the master read `register`.
    using ReadListener = std::function<void(uint8_t)>;
    /// The master ended a transaction with this device (STOP).
    using IdleListener = std::function<void()>;

    /// A device at 7-bit `address` (0x08..0x77: 0x00-0x07 and 0x78-0x7F are
    /// reserved, section 22.3.3); registers all 0. Throws
    /// std::invalid_argument naming the address otherwise.
    TwiSlave(AvrCore& core, int address);
    ~TwiSlave();
    TwiSlave(const TwiSlave&) = delete;
    TwiSlave& operator=(const TwiSlave&) = delete;

    [[nodiscard]] int address() const { return address_; }
    [[nodiscard]] uint8_t reg(uint8_t index) const { return regs_[index]; }
    void set_reg(uint8_t index, uint8_t value) { regs_[index] = value; }
    /// The register pointer (the next register read or written).
    [[nodiscard]] uint8_t pointer() const { return pointer_; }
    /// Called after each register the master writes (not the pointer byte),
    /// so a part can act on it (a reset bit). Must not throw.
    void set_write_listener(WriteListener listener) { on_write_ = std::move(listener); }
    /// Called after each register the master reads (a status that clears
    /// when read). Must not throw.
    void set_read_listener(ReadListener listener) { on_read_ = std::move(listener); }
    /// Called at the STOP that ends a transaction with this device: a
    /// sensor's pending sample may be published then. Must not throw.
    void set_idle_listener(IdleListener listener) { on_idle_ = std::move(listener); }
    /// Addressed since the last START and no STOP yet: a sensor updates its
    /// registers only while this is false (one burst, one sample).
    [[nodiscard]] bool in_transaction() const { return selected_; }
    [[nodiscard]] const TwiSlaveStats& stats() const { return stats_; }

private:
    static void on_message(avr_irq_t* irq, uint32_t value, void* param);
    static void on_status(avr_irq_t* irq, uint32_t value, void* param);
    void handle(uint8_t msg, uint8_t addr, uint8_t data);
    void reply(uint8_t msg, uint8_t data);

    AvrCore& core_;
    int address_ = 0;
    avr_irq_t* to_chip_ = nullptr;    ///< TWI_IRQ_INPUT
    avr_irq_t* from_chip_ = nullptr;  ///< TWI_IRQ_OUTPUT
    avr_irq_t* status_ = nullptr;     ///< TWI_IRQ_STATUS
    bool sla_w_sent_ = false;         ///< the next status is SLA+W's (any device)
    std::array<uint8_t, 256> regs_{};
    uint8_t pointer_ = 0;
    bool selected_ = false;       ///< addressed since the last START
    bool pointer_next_ = false;   ///< the next byte written sets the pointer
    WriteListener on_write_;
    ReadListener on_read_;
    IdleListener on_idle_;
    TwiSlaveStats stats_;
};

}  // namespace ddmr::hil
