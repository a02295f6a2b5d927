#pragma once
// PlantCoupler: advances the plant in lockstep with the AVR clock.
//
// Every `step_cycles` (a cycle timer, default 62.5 us: 1000 cycles at 16 MHz) at
// boundary b it
//   1. takes the bridges' drive from the MotorDriverReader as of b,
//   2. advances the plant over [b, b + step): in averaged mode in one step
//      with the time-averaged drive; in switched mode split at every level
//      change of a driver input (the decoded timer waveforms), each piece
//      with the bridge state the driver's truth table gives, so each PWM
//      edge falls on a plant step boundary at its exact cycle,
//   3. hands the encoder edges of that interval to the EncoderInjector, which
//      raises them at their exact cycles (all still in the AVR's future).
// The plant therefore runs one step ahead of the AVR: a register write at
// cycle c reaches the plant at the first boundary >= c (OCR writes: at the
// first boundary >= the timer's next TOP). Input latency is below one step.
//
// Ground truth is sampled every `truth_period_cycles` (default 1 ms: 16,000 at 16 MHz)
// at a boundary, before the next interval is stepped.
// A plant that diverges (non-finite state) or overflows its edge buffer stops
// the AVR cleanly (AvrCore::request_stop); status() says which and when.

#include <cstdint>
#include <functional>
#include <string>

#include "hil/avr_core.hpp"
#include "hil/encoder_injector.hpp"
#include "hil/motor_driver_reader.hpp"
#include "plant/robot.hpp"

namespace ddmr::hil {

class PartSet;

struct CouplerConfig {
    /// Defaults in time, turned into cycles at the board's clock.
    static constexpr double kDefaultStepS = 62.5e-6;
    static constexpr double kDefaultTruthPeriodS = 1e-3;
    plant::DriveMode mode = plant::DriveMode::switched;
    Cycles step_cycles = 0;          ///< coupling step [cycles], >= 1; 0: kDefaultStepS at the board's clock
    /// Ground-truth sample period [cycles], a multiple of the step; 0: kDefaultTruthPeriodS at the board's clock.
    Cycles truth_period_cycles = 0;
};

/// `config` with its 0 (default) periods in cycles of `clock_hz`.
CouplerConfig resolved(const CouplerConfig& config, uint32_t clock_hz);

/// One ground-truth sample (the plant at a cycle, and what it was driven with).
struct TruthSample {
    Cycles cycle = 0;
    double t_s = 0.0;
    double x_m = 0.0, y_m = 0.0, theta_rad = 0.0;
    double v_m_s = 0.0, omega_rad_s = 0.0;
    double ia1_A = 0.0, ia2_A = 0.0;
    double wheel1_rad_s = 0.0, wheel2_rad_s = 0.0;
    double vbatt_V = 0.0;
    uint64_t edges1 = 0, edges2 = 0;
    double duty1 = 0.0, duty2 = 0.0;  ///< mean enable level of the interval
    bool dir1 = false, dir2 = false;  ///< direction pins (true = forward)
};

/// The plant's outputs now, as a truth sample at `cycle` (time and drive
/// fields from the plant's own time and input).
TruthSample truth_sample_of(const plant::Robot& robot, Cycles cycle);

class PlantCoupler {
public:
    /// Validates `config` (throws std::invalid_argument naming the value) and
    /// arms the step timer at the current cycle. `parts` (may be null): the
    /// board's parts, told after each plant step (Part::on_plant_step, with
    /// the cycle the plant's new state stands for: boundary + step).
    PlantCoupler(AvrCore& core, plant::Robot& robot, MotorDriverReader& reader,
                 EncoderInjector& injector, const CouplerConfig& config, PartSet* parts = nullptr);
    ~PlantCoupler();
    PlantCoupler(const PlantCoupler&) = delete;
    PlantCoupler& operator=(const PlantCoupler&) = delete;

    /// Called with each ground-truth sample (inside the simulation: keep it
    /// short, do not throw).
    void set_truth_sink(std::function<void(const TruthSample&)> sink) { sink_ = std::move(sink); }
    /// Called at every boundary, after the plant has been stepped (for parts
    /// that poll the firmware, such as LoopTracer).
    void set_boundary_hook(std::function<void(Cycles)> hook) { hook_ = std::move(hook); }
    /// Called at every boundary with the interval [from, to) the plant is
    /// about to be stepped over, after the drive was read (for VcdRecorder,
    /// which draws the driver inputs' waveforms over it; inside the
    /// simulation: keep it short, do not throw).
    void set_step_listener(std::function<void(Cycles, Cycles)> listener) { step_listener_ = std::move(listener); }

    plant::StepStatus status() const { return status_; }
    /// Plant time at which the status stopped being ok [s].
    double failed_at_s() const { return failed_at_s_; }
    uint64_t steps() const { return steps_; }
    /// Plant sub-steps taken (more than steps() in switched mode).
    uint64_t plant_steps() const { return plant_steps_; }
    /// Largest delay from a drive-changing register write to the boundary at
    /// which the plant saw it [cycles] (OCR writes count from their TOP).
    Cycles max_input_latency_cycles() const { return max_latency_; }
    const CouplerConfig& config() const { return config_; }

private:
    static uint64_t on_step(struct avr_t* avr, uint64_t when, void* param);
    void step(Cycles boundary);
    void advance(Cycles from, Cycles to, plant::RobotInput& input);
    void sample_truth(Cycles boundary, const plant::RobotInput& input);

    AvrCore& core_;
    plant::Robot& robot_;
    MotorDriverReader& reader_;
    EncoderInjector& injector_;
    CouplerConfig config_;
    PartSet* parts_ = nullptr;
    std::function<void(const TruthSample&)> sink_;
    std::function<void(Cycles)> hook_;
    std::function<void(Cycles, Cycles)> step_listener_;
    plant::EdgeBuffer edges_;
    plant::StepStatus status_ = plant::StepStatus::ok;
    double failed_at_s_ = 0.0;
    uint64_t steps_ = 0;
    uint64_t plant_steps_ = 0;
    Cycles start_cycle_ = 0;
    Cycles next_boundary_ = 0;  ///< when the step timer fires next
    Cycles max_latency_ = 0;
};

}  // namespace ddmr::hil
