#pragma once
// VcdRecorder: what the Uno's pins, its interrupts and the firmware's control
// loop do during a RobotRig run, as VcdWriter signals (`--vcd FILE`).
//
// Signals (scope.name; pins named D<Uno pin>_<wheel>_<input> from the
// board's wiring, e.g. with the default board D10_right_PWM, D12_right_DIR,
// D2_right_OUT):
//   <board>.D0_RX        host -> firmware serial line: idle high, each byte the
//                      UartLink delivers (UART_IRQ_INPUT) as start bit, 8 data
//                      bits LSB first, stop bit, at UartLink::cycles_per_bit()
//                      from the delivery cycle (frames queue, never overlap)
//   <board>.D1_TX        firmware -> host, the same from the cycle the firmware
//                      wrote UDR0 (UART_IRQ_OUTPUT); both lines are drawn
//                      idle high from reset and as 8N1, the sketch's framing
//   encoder pins       (_OUT, _A, _B) each EncoderInjector edge at the cycle
//                      it is raised, from the sensor's power-on level
//   driver inputs      on a pin with a timer output (3, 5, 6, 9, 10, 11): the
//                      level the plant is driven with (PlantCoupler's step
//                      listener), the decoded timer waveform with its edges
//                      at their exact cycles, or the static level from the
//                      coupling boundary at which the plant saw it; on any
//                      other pin: its level (the PORT bit of an output,
//                      the pull-up of an input) from the cycle of the PORTx,
//                      DDRx or MCUCR write that changed it (PinWaveforms'
//                      port listener)
//   <part>.<PORT>      each output of each board part (parts:), e.g.
//                      shield.Q2: its level from the cycle of each change
//   isr.isr_<NAME>     one per vector the ELF has a handler for (INT0,
//                      TIMER0_OVF, USART_UDRE, ...): 1 from the vector's entry
//                      to the end of its RETI, as IsrMonitor times a duration
//   firmware.loop_iteration [31:0]  control-loop iterations so far:
//                      - with a LoopProfiler: exact, +1 at each return of the
//                        loop mark (delay()) after the profiler was armed;
//                      - otherwise: +1 at each mark_loop_iteration(cycle), which
//                        the orchestration calls from LoopTracer (the cycle of
//                        the coupling boundary at which the sketch's `t` was
//                        first seen changed: one coupling step resolution,
//                        1000 cycles by default, up to one step late).
//
// Wiring: construct after the rig (and profiler), before the run; destroy
// before them. Call on_boundary() at every coupling boundary (from the
// PlantCoupler's boundary hook): it writes everything older than two
// coupling steps, so memory stays bounded. finish() at the end of the run
// ends the dump at the current cycle. The hooks into simavr and the rig's
// parts are removed by the destructor. Callbacks do not allocate (beyond the
// writer's event buffer growing to its steady size) and never throw.

#include <array>
#include <cstdint>
#include <vector>

#include "hil/board.hpp"
#include "hil/elf_image.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/robot_rig.hpp"
#include "hil/vcd_writer.hpp"

struct avr_irq_t;

namespace ddmr::hil {

class VcdRecorder {
public:
    /// Declares the signals on `writer` (which must have none yet) and hooks
    /// the rig. `profiler` (optional) makes the loop marker exact.
    VcdRecorder(RobotRig& rig, const ElfImage& elf, VcdWriter& writer, const LoopProfiler* profiler = nullptr);
    ~VcdRecorder();
    VcdRecorder(const VcdRecorder&) = delete;
    VcdRecorder& operator=(const VcdRecorder&) = delete;

    /// At each coupling boundary: picks up profiled iterations and writes the
    /// events older than two coupling steps.
    void on_boundary(Cycles boundary);
    /// One loop iteration detected at `cycle` (ignored with a profiler).
    void mark_loop_iteration(Cycles cycle);
    /// Writes everything up to the current cycle and ends the dump there.
    void finish();

    uint32_t loop_iterations() const { return loop_count_; }

private:
    struct IsrHook {
        VcdRecorder* self = nullptr;
        avr_irq_t* running = nullptr;
        VcdWriter::SignalId signal = 0;
        int depth = 0;  ///< nesting of this vector (stays high while > 0)
    };
    struct SerialLine {
        VcdWriter::SignalId signal = 0;
        Cycles free_at = 0;  ///< end of the last frame drawn
    };
    static void on_isr(avr_irq_t* irq, uint32_t value, void* param);
    static void on_tx(avr_irq_t* irq, uint32_t value, void* param);
    static void on_rx(avr_irq_t* irq, uint32_t value, void* param);
    static void on_part_pin(avr_irq_t* irq, uint32_t value, void* param);
    void hook_part_pins(const BoardWiring& board, const std::string& scope, std::vector<int> traced);
    void draw_frame(SerialLine& line, uint8_t byte);
    void sample_directions();
    void draw_timer_pins(Cycles from, Cycles to);
    void poll_profiler();

    RobotRig& rig_;
    AvrCore& core_;
    VcdWriter& writer_;
    const LoopProfiler* profiler_ = nullptr;
    Cycles lag_cycles_ = 0;

    std::vector<IsrHook> isr_;  ///< sized once: hooks hold pointers into it
    SerialLine tx_, rx_;
    avr_irq_t* tx_irq_ = nullptr;
    avr_irq_t* rx_irq_ = nullptr;
    struct PinTrace {
        int pin = -1;
        VcdWriter::SignalId signal = 0;
        bool level = false;          ///< last level written
        bool timer_capable = false;  ///< an OC pin: drawn from the plant's view at each step
        bool declared = false;
    };
    std::vector<PinTrace> encoder_;     ///< sized once: signals are declared through pointers into it
    std::vector<PinTrace> driver_pin_;  ///< likewise
    /// Each part output's signal and its listener (removed by the destructor).
    struct PartTrace {
        const LogicSignal* signal = nullptr;
        LogicSignal::ListenerId listener = 0;
    };
    std::vector<PartTrace> part_outputs_;
    /// Each board pin of a part (a sensor's TRIG, ECHO, OUT) not traced above:
    /// simavr's pin IRQ, carrying what the firmware drives on it and what the
    /// part drives into it.
    struct PartPinHook {
        VcdRecorder* self = nullptr;
        avr_irq_t* irq = nullptr;
        VcdWriter::SignalId signal = 0;
        bool level = false;
    };
    std::vector<PartPinHook> part_pins_;  ///< sized once: hooks hold pointers into it
    VcdWriter::SignalId loop_ = 0;
    uint32_t loop_count_ = 0;
    std::size_t profiled_seen_ = 0;
};

}  // namespace ddmr::hil
