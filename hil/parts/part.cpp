#include "hil/parts/part.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace ddmr::hil {

PartKey PartKey::number(std::string name, std::string description, double fallback, double lo, double hi) {
    return {std::move(name), PartKeyKind::option, std::move(description), false, fmt::format("{}", fallback), {}, lo, hi};
}

PartKey PartKey::choice(std::string name, std::string description, std::vector<std::string> choices) {
    std::string fallback = choices.empty() ? std::string() : choices.front();
    return {std::move(name), PartKeyKind::option, std::move(description), false, std::move(fallback), std::move(choices),
            0.0, 0.0};
}

const PartKey* PartType::key(const std::string& name) const {
    for (const PartKey& k : keys) {
        if (k.name == name) return &k;
    }
    return nullptr;
}

bool PartType::has_port(const std::string& name) const {
    return std::any_of(ports.begin(), ports.end(), [&](const PartPort& p) { return p.name == name; });
}

namespace {

const PartEntry::Value& value_of(const PartEntry& entry, const std::string& key) {
    const auto it = entry.values.find(key);
    if (it == entry.values.end()) {
        throw std::logic_error(fmt::format("part '{}' ({}): key '{}' was not wired", entry.name, entry.type, key));
    }
    return it->second;
}

}  // namespace

int PartContext::input_pin(const std::string& key) const {
    const PartEntry::Value& v = value_of(entry_, key);
    if (v.pin < 0) {
        throw std::invalid_argument(fmt::format("part '{}' ({}): key '{}' must be wired to a board pin, not '{}'",
                                                entry_.name, entry_.type, key, v.text));
    }
    return v.pin;
}

std::optional<int> PartContext::wired_pin(const std::string& key) const {
    const PartEntry::Value& v = value_of(entry_, key);
    if (v.pin < 0) return std::nullopt;
    return v.pin;
}

int PartContext::output_pin(const std::string& key) const { return value_of(entry_, key).pin; }

const std::string& PartContext::text(const std::string& key) const { return value_of(entry_, key).text; }

const Part* PartContext::carrier(const std::string& key) const {
    const std::string& name = value_of(entry_, key).text;
    if (name.empty()) return nullptr;
    if (!part_of_) {
        throw std::logic_error(fmt::format("part '{}': no parts to find carrier '{}' among", entry_.name, name));
    }
    return &part_of_(name);
}

double PartContext::number(const std::string& key) const { return std::stod(value_of(entry_, key).text); }

}  // namespace ddmr::hil
