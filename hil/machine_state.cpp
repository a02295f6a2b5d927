#include "hil/machine_state.hpp"

#include <fmt/format.h>
#include <sim_avr.h>

#include <algorithm>
#include <cstring>
#include <utility>

#include "hil/data_objects.hpp"
#include "hil/io_register_name.hpp"
#include "hil/mcu.hpp"
#include "hil/plant_coupler.hpp"
#include "hil/robot_rig.hpp"

namespace ddmr::hil {
namespace {

/// TCNTn as a read of it returns now, without changing the run: simavr's
/// read handler computes the count and stores it in the data space, so the
/// stored bytes are put back.
void read_counters(avr_t* avr, const McuDescription& mcu, std::vector<uint8_t>& data) {
    for (const TimerDesc& t : mcu.timers) {
        if (t.tcnt_low == 0) continue;
        const auto& io = avr->io[AVR_DATA_TO_IO(t.tcnt_low)];
        if (io.r.c == nullptr) continue;
        const uint8_t low = avr->data[t.tcnt_low];
        const uint8_t high = t.tcnt_high != 0 ? avr->data[t.tcnt_high] : 0;
        data[t.tcnt_low] = io.r.c(avr, t.tcnt_low, io.r.param);
        if (t.tcnt_high != 0) data[t.tcnt_high] = avr->data[t.tcnt_high];
        avr->data[t.tcnt_low] = low;
        if (t.tcnt_high != 0) avr->data[t.tcnt_high] = high;
    }
}

/// Collects differences, keeping the first `max` of them.
struct Collector {
    StateComparison& out;
    std::size_t max;
    template <typename Name>
    void add(const Name& name, std::string a, std::string b) {
        ++out.total;
        if (out.shown.size() < max) out.shown.push_back(StateDifference{name(), std::move(a), std::move(b)});
    }
};

std::string hex(unsigned v, int digits) { return fmt::format("0x{:0{}x}", v, digits); }

uint64_t bits_of(double v) {
    uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    return bits;
}

void compare_plant(const TruthSample& a, const TruthSample& b, Collector& c) {
    const std::pair<const char*, double TruthSample::*> values[] = {
        {"t_s", &TruthSample::t_s},
        {"x_m", &TruthSample::x_m},
        {"y_m", &TruthSample::y_m},
        {"theta_rad", &TruthSample::theta_rad},
        {"v_m_s", &TruthSample::v_m_s},
        {"omega_rad_s", &TruthSample::omega_rad_s},
        {"ia1_A", &TruthSample::ia1_A},
        {"ia2_A", &TruthSample::ia2_A},
        {"wheel1_rad_s", &TruthSample::wheel1_rad_s},
        {"wheel2_rad_s", &TruthSample::wheel2_rad_s},
        {"vbatt_V", &TruthSample::vbatt_V},
        {"duty1", &TruthSample::duty1},
        {"duty2", &TruthSample::duty2},
    };
    for (const auto& value : values) {
        const char* name = value.first;
        const double x = a.*value.second;
        const double y = b.*value.second;
        // Bit for bit: the same inputs give the same doubles (NaN included).
        if (bits_of(x) == bits_of(y)) continue;
        c.add([name] { return fmt::format("plant {}", name); }, fmt::format("{:.17g}", x), fmt::format("{:.17g}", y));
    }
    const auto other = [&c](const char* name, auto x, auto y) {
        if (x != y) c.add([name] { return fmt::format("plant {}", name); }, fmt::format("{}", x), fmt::format("{}", y));
    };
    other("edges1", a.edges1, b.edges1);
    other("edges2", a.edges2, b.edges2);
    other("dir1", a.dir1, b.dir1);
    other("dir2", a.dir2, b.dir2);
}

}  // namespace

uint8_t sreg_of(const avr_t* avr) {
    unsigned value = 0;
    for (unsigned bit = 0; bit < 8; ++bit) {
        if (avr->sreg[bit] != 0) value |= 1U << bit;
    }
    return static_cast<uint8_t>(value);
}

MachineState capture_machine_state(RobotRig& rig) {
    AvrCore& core = rig.core();
    avr_t* avr = core.raw();
    const McuDescription& mcu = core.mcu();
    MachineState s;
    s.cycle = avr->cycle;
    s.pc = avr->pc;
    s.data.assign(avr->data, avr->data + mcu.ram_end + 1);
    s.data[mcu.sreg] = sreg_of(avr);
    read_counters(avr, mcu, s.data);
    s.eeprom = rig.eeprom().read_all();
    s.plant = truth_sample_of(rig.robot(), s.cycle);
    return s;
}

std::string data_byte_name(uint16_t address, const McuDescription& mcu, const DataObjects* objects) {
    if (address < 32) return fmt::format("r{}", address);
    if (address < mcu.sram_start) return io_register_name(mcu, address);
    if (objects != nullptr) {
        if (const auto i = objects->at(address)) {
            const DataObject& o = (*objects)[*i];
            const unsigned offset = address - o.address;
            return offset == 0 ? fmt::format("SRAM {} ({})", hex(address, 4), o.name)
                               : fmt::format("SRAM {} ({}+{})", hex(address, 4), o.name, offset);
        }
    }
    return fmt::format("SRAM {}", hex(address, 4));
}

StateComparison compare_machine_states(const MachineState& a, const MachineState& b, const McuDescription& mcu,
                                       const DataObjects* objects, std::size_t max_shown) {
    StateComparison out;
    Collector c{out, max_shown};
    if (a.cycle != b.cycle) c.add([] { return std::string("cycle"); }, fmt::format("{}", a.cycle), fmt::format("{}", b.cycle));
    if (a.pc != b.pc) c.add([] { return std::string("PC"); }, hex(a.pc, 4), hex(b.pc, 4));
    const std::size_t n = std::min(a.data.size(), b.data.size());
    for (std::size_t i = 0; i < n; ++i) {
        if (a.data[i] == b.data[i]) continue;
        const auto address = static_cast<uint16_t>(i);
        c.add([&] { return data_byte_name(address, mcu, objects); }, hex(a.data[i], 2), hex(b.data[i], 2));
    }
    const std::size_t m = std::min(a.eeprom.size(), b.eeprom.size());
    for (std::size_t i = 0; i < m; ++i) {
        if (a.eeprom[i] == b.eeprom[i]) continue;
        c.add([&] { return fmt::format("EEPROM {}", hex(static_cast<unsigned>(i), 3)); }, hex(a.eeprom[i], 2),
              hex(b.eeprom[i], 2));
    }
    compare_plant(a.plant, b.plant, c);
    return out;
}

}  // namespace ddmr::hil
