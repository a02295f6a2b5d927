#include "hil/twi_slave.hpp"

#include "hil/simavr_io.hpp"

#include <avr_twi.h>
#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <fmt/format.h>

#include <cstring>
#include <stdexcept>

namespace ddmr::hil {
namespace {

/// 7-bit addresses 0000xxx and 1111xxx are reserved (section 22.3.3).
constexpr int kFirstAddress = 0x08;
constexpr int kLastAddress = 0x77;
/// Master transmitter status codes (Table 22-3) and TWSR's status bits.
constexpr uint32_t kSlaWAck = 0x18;
constexpr uint32_t kSlaWNack = 0x20;
constexpr uint32_t kDataAck = 0x28;
constexpr uint32_t kDataNack = 0x30;
constexpr unsigned kPrescalerBits = 0x07;
/// TWCR bit 7, TWINT (section 22.9.2).
constexpr uint8_t kTwint = 0x80;

/// One byte and its ACK on the bus: 9 SCL periods of 16 + 2 TWBR 4^TWPS CPU
/// cycles each (section 22.5.2: SCL = F_CPU / (16 + 2 TWBR 4^TWPS)).
avr_cycle_count_t byte_cycles(const avr_t* avr, const McuDescription& mcu) {
    const unsigned twps = avr->data[mcu.twsr] & kPrescalerBits & 0x03U;
    const avr_cycle_count_t twbr = avr->data[mcu.twbr];
    const avr_cycle_count_t period = 16U + 2U * twbr * (avr_cycle_count_t{1} << (2U * twps));
    return 9U * period;
}

/// simavr 1.6 completes a byte 9 us after the TWCR write that starts it,
/// whatever TWBR says ("cheats and uses one twi cycle == one usec",
/// avr_twi.c): 144 cycles at 16 MHz where a 100 kHz bus takes 1440. Right
/// after simavr's handler has registered that completion (a cycle timer
/// whose parameter is the TWI module, due later than now; a START's is due
/// now and is left alone), it is registered again at the byte's bus time.
void stretch_byte_to_bus_time(avr_t* avr, const McuDescription& mcu) {
    const std::vector<avr_io_t*> twis = simavr_io_modules(avr, "twi");
    const avr_io_t* twi = twis.empty() ? nullptr : twis.back();
    if (twi == nullptr) return;
    for (const avr_cycle_timer_slot_t* t = avr->cycle_timers.timer; t != nullptr; t = t->next) {
        if (t->param != twi || t->when <= avr->cycle) continue;
        avr_cycle_timer_register(avr, byte_cycles(avr, mcu), t->timer, t->param);  // replaces it
        return;
    }
}

/// After simavr's own TWCR write handler: a 1 written to TWINT clears it
/// (section 22.9.2: "TWINT is cleared by writing a logic one to it").
/// simavr 1.6 declares the TWI vector's flag "sticky" and leaves TWINT set,
/// so a master that polls TWINT runs on before its byte is sent. Stateless
/// (simavr 1.6 cannot unregister a write handler): installed once per core.
void clear_twint_on_write(avr_t* avr, avr_io_addr_t addr, uint8_t value, void* param) {
    if ((value & kTwint) != 0) avr->data[addr] = static_cast<uint8_t>(avr->data[addr] & ~kTwint);
    stretch_byte_to_bus_time(avr, *static_cast<const McuDescription*>(param));
}

/// Whether clear_twint_on_write already watches `twcr`: simavr shares a
/// register among its write handlers through a multiplexer slot.
bool twint_hook_installed(const avr_t* avr, uint16_t twcr) {
    const auto hook = reinterpret_cast<void*>(&clear_twint_on_write);
    const auto& io = avr->io[AVR_DATA_TO_IO(twcr)];
    if (reinterpret_cast<void*>(io.w.c) == hook) return true;
    for (int n = 0; n < avr->io_shared_io_count; ++n) {
        const auto& shared = avr->io_shared_io[n];
        for (int k = 0; k < shared.used && k < 4; ++k) {
            if (shared.io[k].c == hook && reinterpret_cast<intptr_t>(io.w.param) == n) return true;
        }
    }
    return false;
}

}  // namespace

TwiSlave::TwiSlave(AvrCore& core, int address) : core_(core), address_(address) {
    if (address < kFirstAddress || address > kLastAddress) {
        throw std::invalid_argument(
            fmt::format("TwiSlave: address 0x{:02x} is not a 7-bit device address (0x08..0x77)", address));
    }
    to_chip_ = avr_io_getirq(core_.raw(), static_cast<uint32_t>(AVR_IOCTL_TWI_GETIRQ(0)), TWI_IRQ_INPUT);
    from_chip_ = avr_io_getirq(core_.raw(), static_cast<uint32_t>(AVR_IOCTL_TWI_GETIRQ(0)), TWI_IRQ_OUTPUT);
    status_ = avr_io_getirq(core_.raw(), static_cast<uint32_t>(AVR_IOCTL_TWI_GETIRQ(0)), TWI_IRQ_STATUS);
    if (to_chip_ == nullptr || from_chip_ == nullptr || status_ == nullptr) {
        throw std::runtime_error(std::string("TwiSlave: simavr's ") + core_.mcu().label + " core has no TWI");
    }
    avr_irq_register_notify(from_chip_, &TwiSlave::on_message, this);
    avr_irq_register_notify(status_, &TwiSlave::on_status, this);
    if (!twint_hook_installed(core_.raw(), core_.mcu().twcr)) {
        avr_register_io_write(core_.raw(), core_.mcu().twcr, &clear_twint_on_write,
                              const_cast<McuDescription*>(&core_.mcu()));  // static: outlives the core
    }
}

TwiSlave::~TwiSlave() {
    avr_irq_unregister_notify(from_chip_, &TwiSlave::on_message, this);
    avr_irq_unregister_notify(status_, &TwiSlave::on_status, this);
}

void TwiSlave::on_status(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* self = static_cast<TwiSlave*>(param);
    if (!self->sla_w_sent_) return;
    self->sla_w_sent_ = false;
    if (value != kDataAck && value != kDataNack) return;
    // SLA+W reported with the data-byte codes: the datasheet's codes instead.
    uint8_t& twsr = self->core_.raw()->data[self->core_.mcu().twsr];
    twsr = static_cast<uint8_t>((twsr & kPrescalerBits) | (value == kDataAck ? kSlaWAck : kSlaWNack));
}

void TwiSlave::on_message(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    avr_twi_msg_irq_t m{};
    m.u.v = value;
    static_cast<TwiSlave*>(param)->handle(m.u.twi.msg, m.u.twi.addr, m.u.twi.data);
}

void TwiSlave::reply(uint8_t msg, uint8_t data) {
    const auto sla = static_cast<uint8_t>(address_ << 1);
    avr_raise_irq(to_chip_, avr_twi_irq_msg(msg, sla, data));
}

void TwiSlave::handle(uint8_t msg, uint8_t addr, uint8_t data) {
    if ((msg & TWI_COND_STOP) != 0 && selected_) {
        selected_ = false;  // the pointer stays
        if (on_idle_) on_idle_();
    }
    if ((msg & TWI_COND_START) != 0) {
        sla_w_sent_ = (addr & 1U) == 0;
        // addr is SLA+R/W: the 7-bit address, then R (1) or W (0).
        selected_ = (addr >> 1) == address_;
        if (!selected_) return;
        ++stats_.transactions;
        pointer_next_ = (addr & 1U) == 0;  // a write starts with the pointer
        reply(TWI_COND_ACK, 1);
        return;
    }
    if (!selected_) return;
    if ((msg & TWI_COND_WRITE) != 0) {
        ++stats_.bytes_written;
        reply(TWI_COND_ACK, 1);
        if (pointer_next_) {
            pointer_ = data;
            pointer_next_ = false;
            return;
        }
        const uint8_t index = pointer_++;
        regs_[index] = data;
        if (on_write_) on_write_(index, data);
        return;
    }
    if ((msg & TWI_COND_READ) != 0) {
        ++stats_.bytes_read;
        const uint8_t index = pointer_++;
        reply(TWI_COND_READ, regs_[index]);
        if (on_read_) on_read_(index);
    }
}

}  // namespace ddmr::hil
