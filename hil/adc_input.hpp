#pragma once
// AdcInput: the voltages on the board's analog pins, converted as the
// datasheet says, so the firmware's analogRead() returns the chip's code.
//
// The code (ATmega328P datasheet, section 24.7 "ADC Conversion Result"; 23.7
// in edition 7810D; ATmega2560 2549Q section 26.7):
//     ADC = floor(VIN * 1024 / VREF), clamped to 0 .. 1023
// VREF is what REFS1:0 in ADMUX select when the conversion starts
// (McuDescription::adc.refs): AVCC (01, what the Arduino core's
// analogRead selects by default: DEFAULT = 1), the voltage wired to the AREF
// pin (00; AdcSupply::aref_v, 0 = nothing wired: the code is then 0, and
// the real chip's is undefined), or the internal bandgap (1.1 V; the
// ATmega2560's 2.56 V) taken as its nominal value (the datasheet allows
// 1.0-1.2 V, section 28.2). The 328P's reserved REFS = 10 is converted as
// simavr 1.6 does (against AREF).
//
// Sampling: the conversion samples its input 1.5 ADC clocks after it starts,
// 13.5 for the first conversion after ADEN is set (section 24.4, Table 24-1
// "ADC Conversion Time"). A voltage given as a function of the AVR cycle is
// evaluated at that cycle: start + 1.5 (13.5) x the prescaler (ADPS2:0) from
// the write that set ADSC. simavr 1.6 starts the conversion at that write,
// not at the next ADC clock edge, and completes it 13 (25) ADC clocks later.
//
// Signals (simavr 1.6, avr_adc.{c,h}):
//   in   ADC_IRQ_OUT_TRIGGER: raised when ADSC starts a conversion, carrying
//        the input multiplexer's choice (avr_adc_mux_t)
//   in   ADCSRA iomem notification: ADEN (the next conversion is a first one)
//   out  ADC_IRQ_ADC0 + n: millivolts, set at the sampling instant. simavr
//        converts when the firmware reads ADCL (ADCH), as mV * 1023 / VREF_mV
//        (not * 1024): the driver gives it the millivolts that make simavr's
//        formula return the datasheet's code.
//   out  avr_t::avcc and avr_t::aref [mV]: the supply and the AREF voltage.
// simavr 1.6 keeps only ADC0..ADC7 (avr_adc_t::adc_values[8]): its ATmega2560
// table selects ADC8..ADC15 (MUX5 = 1, MUX4:0 = 0..7) but converts whatever
// lies past that array. The driver restores them: it turns those eight
// entries of simavr's mux table (avr_adc_t::muxmode, declared in avr_adc.h)
// into "reference" entries, whose value simavr converts as it is, keeps the
// channel in the entry's unused `diff` field, and writes the sampled
// millivolts into the entry's `src` at the sample instant. The 2560's
// differential inputs are not converted (no Arduino core uses them).
// Not thread-safe (like AvrCore). Construct after the AvrCore, destroy before.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/board_description.hpp"

struct avr_irq_t;
struct avr_adc_mux_t;

namespace ddmr::hil {

/// The board's analog supply and reference pin.
struct AdcSupply {
    /// AVCC [V]; 0: the board's supply (BoardDescription::supply_v: 5 V on the
    /// Uno, Nano and Mega, 3.3 V on the 8 MHz Pro Mini).
    double avcc_v = 0.0;
    double aref_v = 0.0;  ///< the voltage wired to AREF [V]; 0: nothing wired
};

/// One conversion the AdcInput fed (for tests and traces).
struct AdcSample {
    int channel = 0;
    Cycles start_cycle = 0;   ///< the write that set ADSC
    Cycles sample_cycle = 0;  ///< the sample-and-hold instant
    double vin_v = 0.0;       ///< the input voltage then
    double vref_v = 0.0;      ///< the reference REFS1:0 selected
    uint16_t code = 0;        ///< the datasheet's result
};

class AdcInput {
public:
    /// The input voltage [V] at an AVR cycle.
    using VoltageFn = std::function<double(Cycles)>;
    static constexpr std::size_t kRecordedSamples = 4096;

    /// Throws std::invalid_argument if AVCC is not in 1.8 .. 5.5 V or
    /// aref_v is neither 0 nor in 1.0 V .. avcc_v (datasheet 28.2, 28.8).
    explicit AdcInput(AvrCore& core, const AdcSupply& supply = {});
    ~AdcInput();
    AdcInput(const AdcInput&) = delete;
    AdcInput& operator=(const AdcInput&) = delete;

    /// The ADC channel (n of ADCn) of board pin `pin` (A0 = channel 0).
    /// Throws std::invalid_argument naming the pin when it has no ADC input.
    [[nodiscard]] static int channel_of(const BoardDescription& board, int pin);

    /// A constant voltage on analog pin `pin` [V].
    void set_voltage(int pin, double volts);
    /// A voltage that changes with time: `volts` is evaluated at each
    /// conversion's sample-and-hold cycle.
    void set_voltage(int pin, VoltageFn volts);

    /// The datasheet's result for `vin_v` against `vref_v` (section 24.7).
    [[nodiscard]] static uint16_t datasheet_code(double vin_v, double vref_v);

    /// Conversions of channels with a voltage set, oldest first (the first
    /// kRecordedSamples only); conversions() counts them all.
    [[nodiscard]] const std::vector<AdcSample>& samples() const { return samples_; }
    [[nodiscard]] uint64_t conversions() const { return conversions_; }

private:
    static void on_trigger(avr_irq_t* irq, uint32_t value, void* param);
    static void on_adcsra(avr_irq_t* irq, uint32_t value, void* param);
    static uint64_t on_sample(struct avr_t* avr, uint64_t when, void* param);
    /// The reference [V] REFS1:0 select now, and the one simavr divides by [mV].
    void reference(double& vref_v, uint32_t& simavr_mv) const;
    void sample(int channel, Cycles start, Cycles at);
    /// Takes over simavr's mux-table entries of ADC8..ADC15 (see above).
    void claim_high_channels();

    AvrCore& core_;
    AdcSupply supply_;
    std::array<VoltageFn, 16> volts_{};     ///< per ADC channel
    std::array<avr_irq_t*, 8> inputs_{};    ///< ADC_IRQ_ADC0..7
    std::array<avr_adc_mux_t*, 8> high_{};  ///< simavr's mux entries of ADC8..15
    avr_irq_t* trigger_ = nullptr;
    avr_irq_t* adcsra_ = nullptr;
    bool aden_ = false;        ///< ADEN as last seen
    bool next_first_ = true;   ///< the next conversion is the first after ADEN
    int pending_channel_ = -1; ///< the conversion waiting for its sample instant
    Cycles pending_start_ = 0;
    std::vector<AdcSample> samples_;
    uint64_t conversions_ = 0;
};

}  // namespace ddmr::hil
