#include "hil/simavr_io.hpp"

#include <sim_avr.h>
#include <sim_io.h>

#include <cstring>

namespace ddmr::hil {

std::vector<avr_io_t*> simavr_io_modules(avr_t* avr, const char* kind) {
    std::vector<avr_io_t*> out;
    for (avr_io_t* io = avr->io_port; io != nullptr; io = io->next) {
        if (io->kind != nullptr && std::strcmp(io->kind, kind) == 0) out.push_back(io);
    }
    return out;
}

}  // namespace ddmr::hil
