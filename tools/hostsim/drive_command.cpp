#include "tools/hostsim/drive_command.hpp"

#include <algorithm>
#include <cmath>

#include "plant/pwm_waveform.hpp"

namespace ddmr::hostsim {

namespace {
constexpr int kInt16Min = -32768;
constexpr int kInt16Max = 32767;
constexpr int kByteMask = 0xFF;
}  // namespace

int firmware_int(double u) {
    if (!(u > kInt16Min)) return kInt16Min;  // also NaN
    if (u >= kInt16Max) return kInt16Max;
    return static_cast<int>(u);  // truncation toward zero, as avr-gcc's __fixsfsi
}

BridgeCommand continuous_drive(double u, bool previous_forward) {
    BridgeCommand b;
    b.duty = std::min(std::abs(u) / firmware::kPwmFullScale, 1.0);
    if (!(b.duty >= 0.0)) b.duty = 0.0;  // NaN: bridge off
    b.forward = u > 0.0 ? true : (u < 0.0 ? false : previous_forward);
    b.ocr = plant::PhaseCorrectPwm::ocr_for_duty(b.duty);
    return b;
}

BridgeCommand quantised_drive(int vdc, PwmTimer timer, bool previous_forward) {
    BridgeCommand b;
    b.forward = previous_forward;
    if (vdc > 0) b.forward = true;                                // if (Vdc1>0) DIR HIGH
    if (vdc > firmware::kMaxDutyValue) vdc = firmware::kMaxDutyValue;  // if (Vdc1>255) Vdc1=255
    if (vdc < 0) b.forward = false;                               // if (Vdc1<0) DIR LOW
    b.value = vdc;
    int ocr = vdc;  // analogWrite(EN, Vdc)
    if (vdc < 0) {
        ocr = timer == PwmTimer::timer1_ocr1b ? 0 : (vdc & kByteMask);
    }
    b.ocr = static_cast<std::uint8_t>(ocr);
    b.duty = static_cast<double>(ocr) / firmware::kPwmFullScale;
    return b;
}

}  // namespace ddmr::hostsim
