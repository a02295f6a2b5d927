// VcdRecorder: rig events => VcdWriter signals (see vcd_recorder.hpp).
#include "hil/vcd_recorder.hpp"

#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_interrupts.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "hil/atmega328p.hpp"
#include "hil/isr_monitor.hpp"

namespace ddmr::hil {
namespace {

constexpr char kUartName = '0';
/// The Uno's serial pins (PD0 = RXD, PD1 = TXD).
constexpr int kRxPin = 0;
constexpr int kTxPin = 1;
/// 8N1: start bit, 8 data bits, stop bit.
constexpr unsigned kDataBits = 8;
constexpr unsigned kFrameBits = 1 + kDataBits + 1;

bool port_bit(const AvrCore& core, const PinLocation& pin) {
    return ((static_cast<unsigned>(core.data(pin.port_register)) >> pin.bit) & 1U) != 0;
}

std::string pin_name(int pin, const std::string& function) { return "D" + std::to_string(pin) + "_" + function; }

}  // namespace

VcdRecorder::VcdRecorder(RobotRig& rig, const ElfImage& elf, VcdWriter& writer, const LoopProfiler* profiler)
    : rig_(rig), core_(rig.core()), writer_(writer), profiler_(profiler) {
    if (writer_.signal_count() != 0) throw std::logic_error("VcdRecorder: the VcdWriter already has signals");
    const BoardWiring& board = rig_.config().board;
    const Cycles now = core_.cycle();
    lag_cycles_ = 2 * rig_.coupler().config().step_cycles;

    // Pins in Uno pin order; each entry declares its signal.
    struct PinSignal {
        int pin;
        std::string name;
        bool initial;
        VcdWriter::SignalId* id;
    };
    std::vector<PinSignal> pins = {{kRxPin, pin_name(kRxPin, "RX"), true, &rx_.signal},
                                   {kTxPin, pin_name(kTxPin, "TX"), true, &tx_.signal}};
    for (std::size_t m = 0; m < 2; ++m) {
        const std::string n = std::to_string(m + 1);
        const MotorWiring& w = board.motor[m];
        const EncoderWiring& e = board.encoder[m];
        direction_pin_[m] = *uno_pin_location(w.direction_pin);
        direction_level_[m] = port_bit(core_, direction_pin_[m]);
        enable_level_[m] = rig_.driver().drive(m).enable_level_at(now);
        pins.push_back({e.pin, pin_name(e.pin, "encoder" + n), rig_.robot().encoder_level(m), &encoder_[m]});
        pins.push_back({w.enable_pin, pin_name(w.enable_pin, "enable" + n), enable_level_[m], &enable_[m]});
        pins.push_back({w.direction_pin, pin_name(w.direction_pin, "direction" + n), direction_level_[m],
                        &direction_[m]});
    }
    std::stable_sort(pins.begin(), pins.end(), [](const PinSignal& a, const PinSignal& b) { return a.pin < b.pin; });
    for (const PinSignal& p : pins) *p.id = writer_.add_wire("uno", p.name, p.initial);

    avr_t* avr = core_.raw();
    isr_.reserve(atmega328p::kVectorCount);
    for (int v = 1; v < atmega328p::kVectorCount; ++v) {
        const std::string handler = vector_handler_name(core_, elf, v);
        if (handler == kNoHandler || handler == "?") continue;
        avr_irq_t* irqs = avr_get_interrupt_irq(avr, static_cast<uint8_t>(v));
        if (irqs == nullptr) throw std::runtime_error("VcdRecorder: simavr has no IRQs for vector " + std::to_string(v));
        IsrHook h;
        h.self = this;
        h.running = irqs + AVR_INT_IRQ_RUNNING;
        h.signal = writer_.add_wire("isr", std::string("isr_") + atmega328p::vector::kNames[static_cast<std::size_t>(v)],
                                    false);
        isr_.push_back(h);
    }
    loop_ = writer_.add_vector("firmware", "loop_iteration", 32, 0);

    writer_.add_comment("ddmr-hil HIL run; time in ns of AVR time (cycle x 1e9 / " +
                        std::to_string(core_.clock_hz()) + " Hz, rounded down)");
    writer_.add_comment("uno.*_RX/_TX: synthesised 8N1 serial frames, idle high; *_encoder*: injected Hall edges");
    writer_.add_comment(std::string("uno.*_enable*: phase-correct PWM enable waveform as the plant is driven (") +
                        (rig_.coupler().config().mode == plant::DriveMode::switched ? "switched" : "averaged") +
                        " mode); *_direction*: PORT bit at its write");
    writer_.add_comment("isr.isr_*: 1 from the vector's entry to the end of its RETI");
    writer_.add_comment(profiler_ != nullptr
                            ? "firmware.loop_iteration: exact, +1 at each return of the loop mark (LoopProfiler)"
                            : "firmware.loop_iteration: +1 at the coupling boundary where the sketch's t was first "
                              "seen changed (LoopTracer; resolution " +
                                  std::to_string(rig_.coupler().config().step_cycles) + " cycles)");

    // Hooks. The rig's parts report through their listeners; simavr IRQs for the rest.
    for (IsrHook& h : isr_) avr_irq_register_notify(h.running, &VcdRecorder::on_isr, &h);
    avr_irq_t* uart = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(kUartName), 0);
    if (uart == nullptr) throw std::runtime_error("VcdRecorder: simavr USART0 has no IRQs");
    tx_irq_ = uart + UART_IRQ_OUTPUT;
    rx_irq_ = uart + UART_IRQ_INPUT;
    avr_irq_register_notify(tx_irq_, &VcdRecorder::on_tx, this);
    avr_irq_register_notify(rx_irq_, &VcdRecorder::on_rx, this);
    for (const PinLocation& p : direction_pin_) {
        avr_irq_t* irq = avr_iomem_getirq(avr, p.port_register, nullptr, AVR_IOMEM_IRQ_ALL);
        if (irq == nullptr) throw std::runtime_error("VcdRecorder: simavr gave no IRQ for register " +
                                                     std::to_string(p.port_register));
        if (std::find(port_irqs_.begin(), port_irqs_.end(), irq) != port_irqs_.end()) continue;
        port_irqs_.push_back(irq);
        avr_irq_register_notify(irq, &VcdRecorder::on_port_write, this);
    }
    rig_.encoders().set_edge_listener([this](unsigned channel, Cycles cycle, bool level) {
        writer_.change(encoder_[channel], cycle, level ? 1 : 0);
    });
    rig_.coupler().set_enable_listener([this](std::size_t m, Cycles cycle, bool level) {
        if (level == enable_level_[m]) return;
        enable_level_[m] = level;
        writer_.change(enable_[m], cycle, level ? 1 : 0);
    });
}

VcdRecorder::~VcdRecorder() {
    rig_.coupler().set_enable_listener(nullptr);
    rig_.encoders().set_edge_listener(nullptr);
    for (avr_irq_t* irq : port_irqs_) avr_irq_unregister_notify(irq, &VcdRecorder::on_port_write, this);
    avr_irq_unregister_notify(rx_irq_, &VcdRecorder::on_rx, this);
    avr_irq_unregister_notify(tx_irq_, &VcdRecorder::on_tx, this);
    for (IsrHook& h : isr_) avr_irq_unregister_notify(h.running, &VcdRecorder::on_isr, &h);
}

void VcdRecorder::on_isr(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* h = static_cast<IsrHook*>(param);
    VcdRecorder* self = h->self;
    if (value != 0) {
        if (h->depth++ == 0) self->writer_.change(h->signal, self->core_.cycle(), 1);
        return;
    }
    if (h->depth == 0) return;  // a RETI whose entry came before the recorder
    // simavr reports RETI before it charges RETI's cycles (as IsrMonitor counts).
    if (--h->depth == 0) self->writer_.change(h->signal, self->core_.cycle() + atmega328p::kRetiCycles, 0);
}

void VcdRecorder::on_tx(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* self = static_cast<VcdRecorder*>(param);
    self->draw_frame(self->tx_, static_cast<uint8_t>(value));
}

void VcdRecorder::on_rx(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* self = static_cast<VcdRecorder*>(param);
    self->draw_frame(self->rx_, static_cast<uint8_t>(value));
}

void VcdRecorder::draw_frame(SerialLine& line, uint8_t byte) {
    const Cycles bit = rig_.uart().cycles_per_bit();
    const Cycles start = std::max(core_.cycle(), line.free_at);
    writer_.change(line.signal, start, 0);  // start bit
    for (unsigned i = 0; i < kDataBits; ++i) {
        writer_.change(line.signal, start + (1 + i) * bit, (static_cast<unsigned>(byte) >> i) & 1U);
    }
    writer_.change(line.signal, start + (1 + kDataBits) * bit, 1);  // stop bit, then idle
    line.free_at = start + kFrameBits * bit;
}

void VcdRecorder::on_port_write(avr_irq_t* /*irq*/, uint32_t /*value*/, void* param) {
    static_cast<VcdRecorder*>(param)->sample_directions();
}

void VcdRecorder::sample_directions() {
    const Cycles now = core_.cycle();
    for (std::size_t m = 0; m < 2; ++m) {
        const bool level = port_bit(core_, direction_pin_[m]);
        if (level == direction_level_[m]) continue;
        direction_level_[m] = level;
        writer_.change(direction_[m], now, level ? 1 : 0);
    }
}

void VcdRecorder::mark_loop_iteration(Cycles cycle) {
    if (profiler_ != nullptr) return;
    writer_.change(loop_, cycle, ++loop_count_);
}

void VcdRecorder::poll_profiler() {
    if (profiler_ == nullptr) return;
    const std::vector<LoopIteration>& its = profiler_->iterations();
    for (; profiled_seen_ < its.size(); ++profiled_seen_) writer_.change(loop_, its[profiled_seen_].end, ++loop_count_);
}

void VcdRecorder::on_boundary(Cycles boundary) {
    poll_profiler();
    // The latest event source stamps one step back (LoopTracer); keep two.
    if (boundary > lag_cycles_) writer_.flush(boundary - lag_cycles_);
}

void VcdRecorder::finish() {
    poll_profiler();
    writer_.finish(core_.cycle());
}

}  // namespace ddmr::hil
