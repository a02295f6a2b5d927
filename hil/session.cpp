#include "hil/session.hpp"

#include <fmt/format.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace ddmr::hil {

const char* to_string(SessionStop stop) {
    switch (stop) {
        case SessionStop::kReachedCycle: return "reached_cycle";
        case SessionStop::kCondition: return "condition";
        case SessionStop::kEnded: return "ended";
        case SessionStop::kTimeLimit: return "time_limit";
        case SessionStop::kWallLimit: return "wall_limit";
        case SessionStop::kKilled: return "killed";
        case SessionStop::kFailure: return "failure";
    }
    return "?";
}

Session::Session(const ElfImage& elf, const RigConfig& config, SessionOptions options)
    : elf_(elf), options_(std::move(options)) {
    if (options_.time_limit == 0) throw std::invalid_argument("session: the time limit must be >= 1 cycle");
    if (!(options_.wall_limit_s >= 0.0)) throw std::invalid_argument("session: the wall-clock limit must be >= 0 s");
    rig_ = std::make_unique<RobotRig>(elf, config);
    AvrCore& core = rig_->core();
    clock_hz_ = core.clock_hz();
    core.log().set_echo(options_.echo_simavr_log ? stderr : nullptr);
    if (options_.eeprom_preload) rig_->eeprom().preload(*options_.eeprom_preload);
    const SessionInstruments& in = options_.instruments;
    if (in.isr_monitor) isr_ = std::make_unique<IsrMonitor>(core, elf);
    if (in.stack_guard) stack_guard_ = std::make_unique<StackGuard>(core, elf);
    if (in.race_detector) races_ = std::make_unique<RaceDetector>(core, elf);
    if (options_.adapter_baud) adapter_ = std::make_unique<HostAdapter>(core, rig_->uart().usart(), *options_.adapter_baud);
    if (options_.gdb) gdb_ = std::make_unique<GdbServer>(core, *options_.gdb);
    core.set_fast_forward(options_.fast_forward && !gdb_);
    rig_->uart().set_listener([this](const UartByte& b) {
        scratch_.clear();
        if (adapter_) {
            adapter_->on_firmware_byte(b, scratch_);
        } else {
            scratch_.push_back(LineByte{static_cast<double>(b.cycle), b.value, false});
        }
        deliver(scratch_);
    });
    rig_->coupler().set_boundary_hook([this](Cycles c) { on_boundary(c); });
    rig_->coupler().set_truth_sink([this](const TruthSample& s) {
        for (SessionObserver* o : observers_) o->on_truth(s);
    });
    wall_start_ = std::chrono::steady_clock::now();
    // The wall-clock limit: checked every simulated second by a cycle timer,
    // so it also ends a boot that never returns from its ready function.
    wall_period_ = s_to_cycles(1.0, clock_hz_);
    if (options_.wall_limit_s > 0.0 && !gdb_) {
        avr_cycle_timer_register(core.raw(), wall_period_, &Session::on_wall_check, this);
    }
    next_progress_ = wall_period_;
}

Session::~Session() {
    if (!rig_) return;
    avr_cycle_timer_cancel(rig_->core().raw(), &Session::on_wall_check, this);
    for (const auto& p : periodic_) avr_cycle_timer_cancel(rig_->core().raw(), &Session::on_periodic, p.get());
}

void Session::every(Cycles period, std::function<void(Cycles)> sample) {
    if (period == 0) throw std::invalid_argument("session: a periodic sample needs a period >= 1 cycle");
    periodic_.push_back(std::make_unique<Periodic>(Periodic{std::move(sample), period}));
    avr_cycle_timer_register(rig_->core().raw(), period, &Session::on_periodic, periodic_.back().get());
}

uint64_t Session::on_periodic(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* p = static_cast<Periodic*>(param);
    p->sample(when);
    return when + p->period;
}

uint64_t Session::on_wall_check(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* self = static_cast<Session*>(param);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - self->wall_start_).count();
    if (elapsed > self->options_.wall_limit_s) {
        self->wall_tripped_ = true;
        self->rig_->core().request_stop();
        return 0;
    }
    return when + self->wall_period_;
}

void Session::wait_for_debugger() {
    if (!gdb_) return;
    gdb_->wait_for_attach();
    wall_start_ = std::chrono::steady_clock::now();  // the wait for a person is not run time
}

double Session::wall_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
}

std::string Session::send(const std::string& text) {
    std::string bytes = adapter_ ? adapter_->as_firmware_receives(text) : text;
    rig_->uart().send(bytes);
    return bytes;
}

void Session::flush_host_bytes() {
    if (!adapter_) return;
    scratch_.clear();
    adapter_->flush(scratch_);
    deliver(scratch_);
}

void Session::deliver(const std::vector<LineByte>& bytes) {
    for (const LineByte& b : bytes) {
        for (SessionObserver* o : observers_) o->on_host_byte(static_cast<char>(b.value), static_cast<Cycles>(b.cycle));
    }
}

void Session::on_boundary(Cycles cycle) {
    if (adapter_) {
        scratch_.clear();
        adapter_->settle(cycle, scratch_);  // bytes whose stop bit the adapter has sampled
        deliver(scratch_);
    }
    for (SessionObserver* o : observers_) o->on_boundary(cycle);
    if (until_ != nullptr && until_->poll_each_boundary && until_->met && until_->met()) rig_->core().request_stop();
}

void Session::at(Cycles cycle, std::function<void()> action) {
    const auto pos = std::upper_bound(timed_.begin(), timed_.end(), cycle,
                                      [](Cycles c, const auto& entry) { return c < entry.first; });
    timed_.insert(pos, {cycle, std::move(action)});
}

void Session::post(std::function<void()> action) {
    at(cycle(), std::move(action));
    interrupt();
}

void Session::end_run() {
    end_requested_ = true;
    end_now_ = true;
    rig_->core().request_stop();
}

void Session::end_after(Cycles delay) {
    end_requested_ = true;
    rig_->core().stop_after(delay);
}

void Session::run_due_actions() {
    while (!timed_.empty() && timed_.front().first <= cycle()) {
        auto action = std::move(timed_.front().second);
        timed_.erase(timed_.begin());
        action();
    }
}

SessionStop Session::classify(RunStop stop) {
    if (wall_tripped_) return SessionStop::kWallLimit;
    if (gdb_ && gdb_->killed()) return SessionStop::kKilled;
    failure_ = describe_run_failure(observe_run_end(stop, *rig_, stack_guard()), wording_);
    if (failure_) return SessionStop::kFailure;
    if (stop == RunStop::kCondition && end_requested_) {
        end_now_ = true;  // later run() calls return at once
        return SessionStop::kEnded;
    }
    rig_->core().clear_stop_request();
    return SessionStop::kReachedCycle;  // not an end: the loop goes on
}

SessionStop Session::run(Cycles target, const RunCondition& until) {
    until_ = &until;
    const auto done = [this](SessionStop s) {
        until_ = nullptr;
        return s;
    };
    if (gdb_ && gdb_->killed()) return done(SessionStop::kKilled);
    while (true) {
        if (end_now_) return done(SessionStop::kEnded);
        run_due_actions();
        if (end_now_) return done(SessionStop::kEnded);  // an action ended the run
        if (until.met && until.met()) return done(SessionStop::kCondition);
        if (cycle() >= target) return done(SessionStop::kReachedCycle);
        if (cycle() >= options_.time_limit) return done(SessionStop::kTimeLimit);
        Cycles next = std::min({target, options_.time_limit, next_progress_});
        if (!timed_.empty()) next = std::min(next, std::max(timed_.front().first, cycle()));
        const RunStop stop = next > cycle() ? rig_->core().run_until(next) : RunStop::kReachedCycle;
        if (gdb_) gdb_->release_if_detached();  // back to full speed once gdb has left
        const SessionStop s = classify(stop);
        if (s != SessionStop::kReachedCycle) return done(s);
        if (cycle() >= next_progress_) {
            if (options_.on_progress) options_.on_progress(cycle());
            next_progress_ = cycle() + wall_period_;
        }
    }
}

SessionStop Session::run_to_first_return_from(const ElfSymbol& function) {
    if (gdb_ && gdb_->killed()) return SessionStop::kKilled;
    const RunStop stop = rig_->core().run_until_return_from(function, options_.time_limit);
    if (gdb_) gdb_->release_if_detached();
    if (stop == RunStop::kCondition && !wall_tripped_ && !(gdb_ && gdb_->killed()) && !end_requested_) {
        failure_ = describe_run_failure(observe_run_end(stop, *rig_, stack_guard()), wording_);
        if (failure_) return SessionStop::kFailure;
        rig_->core().clear_stop_request();
        return SessionStop::kCondition;
    }
    const SessionStop s = classify(stop);
    return s == SessionStop::kReachedCycle ? SessionStop::kTimeLimit : s;
}

std::string Session::end_message(SessionStop stop) const {
    const double sim_s = seconds(rig_->core().cycle());
    switch (stop) {
        case SessionStop::kWallLimit:
            return fmt::format("wall-clock timeout after {} s (--wall-timeout) at t = {:.6f} simulated s",
                               options_.wall_limit_s, sim_s);
        case SessionStop::kKilled:
            return fmt::format("killed by the debugger at cycle {} (t = {:.6f} s)", rig_->core().cycle(), sim_s);
        case SessionStop::kFailure: return failure_ ? failure_->message : std::string();
        default: return {};
    }
}

}  // namespace ddmr::hil
