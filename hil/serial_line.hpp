#pragma once
// SerialLine: what a UART receiver on the other end of a wire reads, when the
// two ends may disagree on the baud rate (issue 7: a host's USB-serial
// adapter at 9600 baud listening to a firmware that runs its UART at another
// rate sees framing errors and garbage, as on the bench).
//
// The wire carries 8N1 frames: idle high; start bit low; 8 data bits, least
// significant first; stop bit high. Each frame is sent with its own bit time
// (the sender's clock / baud; the AVR's is (U2X0 ? 8 : 16) (UBRR0 + 1)
// cycles). The receiver, with bit time `rx_bit_cycles`:
//   1. waits for a falling edge (high -> low);
//   2. samples the line in the middle of each bit: at edge + (k + 1.5) bit
//      times for data bit k, at edge + 9.5 bit times for the stop bit;
//   3. delivers the byte; a low stop bit is a framing error (the byte is
//      still delivered, as USB-serial adapters and the ATmega's own receiver
//      do, with the error flagged);
//   4. looks for the next falling edge from the stop-bit sample on.
// Equal rates decode every byte exactly; rates a few percent apart still do
// (the sampling drifts by less than half a bit over the 9.5 bits); rates
// further apart give wrong bytes, framing errors and lost bytes.
//
// Frames are pushed in time order; decoding runs as far as the pushed frames
// determine the line, and flush() finishes it (the line idles afterwards).
// Deterministic, no allocation beyond the frame queue. Not thread-safe.

#include <cstdint>
#include <deque>
#include <vector>

#include "hil/cycle_time.hpp"

namespace ddmr::hil {

struct LineByte {
    double cycle = 0.0;         ///< when the receiver sampled the stop bit
    uint8_t value = 0;
    bool framing_error = false; ///< the stop bit was low
};

class SerialLine {
public:
    /// `rx_bit_cycles` > 0: the receiver's bit time in sender clock cycles.
    explicit SerialLine(double rx_bit_cycles);

    /// A frame whose start bit begins at `start` (not before the end of the
    /// previous frame: it is delayed to it, as a transmitter would) with bit
    /// time `tx_bit_cycles` > 0. Appends the bytes it can now decode.
    void push(double start, uint8_t value, double tx_bit_cycles, std::vector<LineByte>& out);
    /// Decodes everything the receiver has sampled by `now`, given that no
    /// frame will start before `now` (later pushes start at or after it).
    void settle(double now, std::vector<LineByte>& out);
    /// Decodes what is left (the line stays idle after the last frame).
    void flush(std::vector<LineByte>& out);

    uint64_t framing_errors() const { return framing_errors_; }
    double rx_bit_cycles() const { return rx_bit_; }

    /// Bit time of the AVR's USART0 from its registers [cycles].
    static double avr_bit_cycles(uint16_t ubrr, bool u2x) { return (u2x ? 8.0 : 16.0) * (ubrr + 1.0); }

private:
    struct Frame {
        double start;
        double bit;
        uint8_t value;
        double end() const { return start + 10.0 * bit; }
    };
    bool level_at(double t) const;
    /// First falling edge at or after t, if the known frames determine it
    /// before `horizon`.
    bool next_falling_edge(double t, double horizon, double& edge) const;
    void decode(double horizon, std::vector<LineByte>& out);

    double rx_bit_;
    std::deque<Frame> frames_;
    double search_from_ = 0.0;  ///< the receiver looks for a start bit from here
    double settled_ = 0.0;      ///< no frame starts before this
    uint64_t framing_errors_ = 0;
};

}  // namespace ddmr::hil
