#include "hil/simavr_log.hpp"

#include <sim_avr.h>

#include <cstdarg>
#include <mutex>

namespace ddmr::hil {
namespace {

thread_local SimavrLog* t_loading_log = nullptr;

std::string trim_newline(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    return s;
}

void route(avr_t* avr, const int level, const char* format, va_list ap) {
    if (level > SimavrLog::kLevelWarning) return;  // trace and debug: dropped
    char buf[512];
    std::vsnprintf(buf, sizeof buf, format, ap);
    std::string message = trim_newline(buf);
    SimavrLog* log = nullptr;
    if (avr != nullptr && avr->custom.data != nullptr) {
        log = static_cast<SimavrLog*>(avr->custom.data);
    } else {
        log = t_loading_log;
    }
    if (log != nullptr) {
        log->record(level, std::move(message));
    } else if (level <= SimavrLog::kLevelError) {
        std::fprintf(stderr, "simavr: %s\n", message.c_str());
    }
}

}  // namespace

void SimavrLog::record(int level, std::string message) {
    // simavr colours some messages (ESC [ ... m) and ends them with spaces.
    std::string clean;
    for (std::size_t i = 0; i < message.size(); ++i) {
        if (message[i] == '\x1b' && i + 1 < message.size() && message[i + 1] == '[') {
            const auto end = message.find('m', i + 2);
            if (end != std::string::npos) {
                i = end;
                continue;
            }
        }
        clean.push_back(message[i]);
    }
    while (!clean.empty() && (clean.back() == ' ' || clean.back() == '\n' || clean.back() == '\r')) clean.pop_back();
    message = std::move(clean);
    if (level == kLevelError) {
        if (hard_errors_++ == 0) first_error_ = message;
    }
    if (level <= kLevelError) {
        ++errors_;
    } else if (level == kLevelWarning) {
        ++warnings_;
    }
    if (echo_ != nullptr) std::fprintf(echo_, "simavr: %s\n", message.c_str());
    auto [it, inserted] = counts_.try_emplace(std::move(message), 0);
    ++it->second;
    if (inserted && first_.size() < kKeepFirst) first_.push_back(it->first);
}

void install_simavr_logger() {
    static std::once_flag once;
    std::call_once(once, [] { avr_global_logger_set(&route); });
}

LoadingLogScope::LoadingLogScope(SimavrLog* log) : previous_(t_loading_log) {
    t_loading_log = log;
}

LoadingLogScope::~LoadingLogScope() { t_loading_log = previous_; }

}  // namespace ddmr::hil
