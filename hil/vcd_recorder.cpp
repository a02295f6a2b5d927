// VcdRecorder: rig events => VcdWriter signals (see vcd_recorder.hpp).
#include "hil/vcd_recorder.hpp"

#include <avr_ioport.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_interrupts.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "hil/fast_forward.hpp"
#include "hil/isr_monitor.hpp"

namespace ddmr::hil {
namespace {

/// 8N1: start bit, 8 data bits, stop bit.
constexpr unsigned kDataBits = 8;
constexpr unsigned kFrameBits = 1 + kDataBits + 1;


std::string pin_name(int pin, const std::string& function) { return "D" + std::to_string(pin) + "_" + function; }

/// The VCD scope of the board's pins: its board-file key, '-' as '_' ("uno", "pro_mini_8mhz").
std::string board_scope(const BoardDescription& board) {
    std::string s = board.key;
    std::replace(s.begin(), s.end(), '-', '_');
    return s;
}

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
    // The host link's USART pins (the Uno's D0 = RXD, D1 = TXD; Serial1 on a Mega: D19, D18).
    const BoardDescription& desc = core_.board();
    const UsartDesc& usart = rig_.uart().usart();
    const int rx_pin = pin_number_of(desc, usart.rxd).value_or(-1);
    const int tx_pin = pin_number_of(desc, usart.txd).value_or(-1);
    std::vector<PinSignal> pins = {{rx_pin, pin_name(rx_pin, "RX"), true, &rx_.signal},
                                   {tx_pin, pin_name(tx_pin, "TX"), true, &tx_.signal}};
    // Encoder outputs, then one signal per driver input pin (a pin shared
    // by both wheels, a dual module's STBY / SLEEP, once).
    encoder_.clear();
    driver_pin_.clear();
    encoder_.reserve(4);
    driver_pin_.reserve(static_cast<std::size_t>(desc.pin_count()));
    for (std::size_t m = 0; m < 2; ++m) {
        const EncoderWiring& e = board.wheel[m].encoder;
        for (unsigned s = 0; s < e.signals(); ++s) {
            encoder_.push_back(PinTrace{e.pin[s], 0, rig_.encoders().level(static_cast<unsigned>(m), s), false});
        }
        for (std::size_t r = 0; r < kDriverRoleCount; ++r) {
            const InputWire& in = board.wheel[m].motor.input[r];
            if (!in.on_pin()) continue;
            if (std::any_of(driver_pin_.begin(), driver_pin_.end(), [&](const PinTrace& t) { return t.pin == in.pin; })) continue;
            const bool timer = board_pin(desc, in.pin)->oc.has_value();
            driver_pin_.push_back(PinTrace{in.pin, 0, rig_.driver().pins().level_at(in.pin, now), timer});
        }
    }
    for (std::size_t m = 0; m < 2; ++m) {
        const EncoderWiring& e = board.wheel[m].encoder;
        for (unsigned s = 0; s < e.signals(); ++s) {
            for (PinTrace& t : encoder_) {
                if (t.pin == e.pin[s]) pins.push_back({t.pin, pin_name(t.pin, std::string(wheel_name(m)) + "_" + encoder_signal_key(e, s)), t.level, &t.signal});
            }
        }
        for (std::size_t r = 0; r < kDriverRoleCount; ++r) {
            const InputWire& in = board.wheel[m].motor.input[r];
            if (!in.on_pin()) continue;
            for (PinTrace& t : driver_pin_) {
                if (t.pin != in.pin || t.declared) continue;
                t.declared = true;
                pins.push_back({t.pin, pin_name(t.pin, std::string(wheel_name(m)) + "_" + role_key(static_cast<DriverRole>(r))), t.level, &t.signal});
            }
        }
    }
    std::stable_sort(pins.begin(), pins.end(), [](const PinSignal& a, const PinSignal& b) { return a.pin < b.pin; });
    const std::string scope = board_scope(desc);
    for (const PinSignal& p : pins) *p.id = writer_.add_wire(scope, p.name, p.initial);
    std::vector<int> traced(pins.size());
    std::transform(pins.begin(), pins.end(), traced.begin(), [](const PinSignal& p) { return p.pin; });
    hook_part_pins(board, scope, std::move(traced));

    avr_t* avr = core_.raw();
    const McuDescription& mcu = core_.mcu();
    isr_.reserve(static_cast<std::size_t>(mcu.vector_count()));
    for (int v = 1; v < mcu.vector_count(); ++v) {
        const std::string handler = vector_handler_name(core_, elf, v);
        if (handler == kNoHandler || handler == "?") continue;
        avr_irq_t* irqs = avr_get_interrupt_irq(avr, static_cast<uint8_t>(v));
        if (irqs == nullptr) continue;  // a vector simavr's core does not declare is never raised
        IsrHook h;
        h.self = this;
        h.running = irqs + AVR_INT_IRQ_RUNNING;
        h.signal = writer_.add_wire("isr", "isr_" + mcu.vector_name(v), false);
        isr_.push_back(h);
    }
    loop_ = writer_.add_vector("firmware", "loop_iteration", 32, 0);
    for (const PartSet::Output& o : rig_.parts().outputs()) {
        const VcdWriter::SignalId id = writer_.add_wire(o.part, o.port, o.signal->level_at(now));
        const auto listener = o.signal->add_listener(
            [this, id](bool level, Cycles cycle) { writer_.change(id, cycle, level ? 1 : 0); });
        part_outputs_.push_back(PartTrace{o.signal, listener});
    }

    writer_.add_comment("ddmr-hil HIL run; time in ns of AVR time (cycle x 1e9 / " +
                        std::to_string(core_.clock_hz()) + " Hz, rounded down)");
    writer_.add_comment(scope + ".*_RX/_TX: synthesised 8N1 serial frames, idle high; D<pin>_<wheel>_OUT/A/B: injected "
                                "encoder edges");
    writer_.add_comment(scope + ".D<pin>_<wheel>_<input>: motor driver inputs; on a timer pin the waveform the plant is "
                                "driven with (decoded from the timer registers), elsewhere the PORT bit at its write");
    writer_.add_comment(scope + ".D<pin>_<part>_<key>: a board part's pins (a sensor's TRIG, ECHO, OUT): the level "
                                "simavr's port shows, what the firmware drives or the part drives into it");
    writer_.add_comment("isr.isr_*: 1 from the vector's entry to the end of its RETI");
    writer_.add_comment(profiler_ != nullptr
                            ? "firmware.loop_iteration: exact, +1 at each return of the loop mark (LoopProfiler)"
                            : "firmware.loop_iteration: +1 at the coupling boundary where the sketch's t was first "
                              "seen changed (LoopTracer; resolution " +
                                  std::to_string(rig_.coupler().config().step_cycles) + " cycles)");

    // Hooks. The rig's parts report through their listeners; simavr IRQs for the rest.
    for (IsrHook& h : isr_) avr_irq_register_notify(h.running, &VcdRecorder::on_isr, &h);
    avr_irq_t* uart = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ(usart_irq_name(usart)), 0);
    if (uart == nullptr) throw std::runtime_error("VcdRecorder: simavr's USART" + std::to_string(usart.index) + " has no IRQs");
    tx_irq_ = uart + UART_IRQ_OUTPUT;
    rx_irq_ = uart + UART_IRQ_INPUT;
    avr_irq_register_notify(tx_irq_, &VcdRecorder::on_tx, this);
    avr_irq_register_notify(rx_irq_, &VcdRecorder::on_rx, this);
    // The other driver pins as the driver's pin model samples them (timer
    // pins are drawn as the plant is driven: the step listener).
    rig_.driver().pins().set_port_listener([this] { sample_directions(); });
    rig_.encoders().set_edge_listener([this](int pin, Cycles cycle, bool level) {
        for (PinTrace& t : encoder_) {
            if (t.pin == pin) writer_.change(t.signal, cycle, level ? 1 : 0);
        }
    });
    rig_.coupler().set_step_listener([this](Cycles from, Cycles to) { draw_timer_pins(from, to); });
}

void VcdRecorder::hook_part_pins(const BoardWiring& board, const std::string& scope, std::vector<int> traced) {
    const BoardDescription& desc = core_.board();
    std::size_t count = 0;
    for (const PartEntry& p : board.parts) {
        for (const auto& [key, v] : p.values) count += v.pin >= 0 ? 1U : 0U;
    }
    part_pins_.reserve(count);
    for (const PartEntry& p : board.parts) {
        for (const auto& [key, v] : p.values) {
            if (v.pin < 0 || std::find(traced.begin(), traced.end(), v.pin) != traced.end()) continue;
            traced.push_back(v.pin);
            const std::optional<PinInfo> info = board_pin(desc, v.pin);
            avr_irq_t* irq = avr_io_getirq(core_.raw(), static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ(info->port)), info->bit);
            if (irq == nullptr) throw std::runtime_error("VcdRecorder: simavr has no IRQ for pin " + std::to_string(v.pin));
            const bool level = ((core_.data(info->pin_register) >> info->bit) & 1U) != 0;
            part_pins_.push_back(PartPinHook{this, irq, writer_.add_wire(scope, pin_name(v.pin, p.name + "_" + key), level), level});
        }
    }
    for (PartPinHook& h : part_pins_) avr_irq_register_notify(h.irq, &VcdRecorder::on_part_pin, &h);
}

void VcdRecorder::on_part_pin(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* h = static_cast<PartPinHook*>(param);
    const bool level = (value & 1U) != 0;
    if (level == h->level) return;
    h->level = level;
    h->self->writer_.change(h->signal, h->self->core_.cycle(), level ? 1 : 0);
}

VcdRecorder::~VcdRecorder() {
    for (PartPinHook& h : part_pins_) avr_irq_unregister_notify(h.irq, &VcdRecorder::on_part_pin, &h);
    rig_.coupler().set_step_listener(nullptr);
    rig_.encoders().set_edge_listener(nullptr);
    rig_.driver().pins().set_port_listener(nullptr);
    avr_irq_unregister_notify(rx_irq_, &VcdRecorder::on_rx, this);
    avr_irq_unregister_notify(tx_irq_, &VcdRecorder::on_tx, this);
    for (IsrHook& h : isr_) avr_irq_unregister_notify(h.running, &VcdRecorder::on_isr, &h);
    for (const PartTrace& t : part_outputs_) t.signal->remove_listener(t.listener);
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
    if (--h->depth == 0) self->writer_.change(h->signal, self->core_.cycle() + self->core_.mcu().reti_cycles, 0);
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

void VcdRecorder::sample_directions() {
    const Cycles now = core_.cycle();
    const PinWaveforms& pins = rig_.driver().pins();
    for (PinTrace& t : driver_pin_) {
        if (t.timer_capable) continue;
        const bool level = pins.level_at(t.pin, now);
        if (level == t.level) continue;
        t.level = level;
        writer_.change(t.signal, now, level ? 1 : 0);
    }
}

void VcdRecorder::draw_timer_pins(Cycles from, Cycles to) {
    // The waveform the plant is driven with over [from, to): every edge of a
    // timer output at its exact cycle, a static level from the boundary on.
    const PinWaveforms& pins = rig_.driver().pins();
    for (PinTrace& t : driver_pin_) {
        if (!t.timer_capable) continue;
        for (Cycles c = from; c < to; c = pins.next_change_after(t.pin, c)) {
            const bool level = pins.level_at(t.pin, c);
            if (level == t.level) continue;
            t.level = level;
            writer_.change(t.signal, c, level ? 1 : 0);
        }
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
    // Inside a fast-forward jump, pin edges held back may still come
    // (FastForward::unsettled_from).
    if (boundary <= lag_cycles_) return;
    const FastForward* ff = core_.fast_forward();
    writer_.flush(std::min(boundary - lag_cycles_, ff != nullptr ? ff->unsettled_from() : FastForward::kAllSettled));
}

void VcdRecorder::finish() {
    poll_profiler();
    writer_.finish(core_.cycle());
}

}  // namespace ddmr::hil
