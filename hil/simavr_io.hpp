#pragma once
// simavr's I/O modules of one instance, found by kind: the one place that
// walks avr->io_port (each module starts with its avr_io_t, so the pointer
// is also the module's own struct: avr_adc_t, avr_uart_t, avr_timer_t ...).

#include <vector>

struct avr_t;
struct avr_io_t;

namespace ddmr::hil {

/// The modules whose kind is `kind` ("adc", "uart", "twi", "port", "timer"),
/// in simavr's list order.
std::vector<avr_io_t*> simavr_io_modules(avr_t* avr, const char* kind);

/// The first module of `kind` as its own struct type, or nullptr.
template <typename Module>
Module* simavr_io_module(avr_t* avr, const char* kind) {
    const std::vector<avr_io_t*> all = simavr_io_modules(avr, kind);
    return all.empty() ? nullptr : reinterpret_cast<Module*>(all.front());
}

}  // namespace ddmr::hil
