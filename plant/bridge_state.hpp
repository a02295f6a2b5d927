#pragma once
// What an H-bridge does to its motor at one instant, whatever the chip. Every
// driver's truth table (motor_driver.hpp) maps its input levels to one of
// these four states; each state has one terminal equation (bridge_driver.hpp).
//
//   state    outputs (OUT1, OUT2)        motor terminals
//   coast    both off (high-Z)           open; a flowing current returns to the
//                                        supply through two flyback diodes
//   forward  OUT1 high, OUT2 low         +(V_supply - bridge drop)
//   reverse  OUT1 low, OUT2 high         -(V_supply - bridge drop)
//   brake    both on the same rail       shorted through the two conducting
//                                        switches; the supply sees nothing

#include <cstdint>

namespace ddmr::plant {

enum class BridgeState : std::uint8_t { coast, forward, reverse, brake };

/// "coast", "forward", "reverse", "brake" (logs, messages).
constexpr const char* to_string(BridgeState s) {
    switch (s) {
        case BridgeState::coast: return "coast";
        case BridgeState::forward: return "forward";
        case BridgeState::reverse: return "reverse";
        case BridgeState::brake: return "brake";
    }
    return "unknown";
}

}  // namespace ddmr::plant
