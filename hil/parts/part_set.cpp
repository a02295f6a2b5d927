#include "hil/parts/part_set.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <stdexcept>

#include "hil/pin_probe.hpp"
#include "hil/yaml_reader.hpp"

namespace ddmr::hil {
namespace {

/// A board pin as a part's input: its level as the registers set it.
class PinSignal final : public LogicSignal {
public:
    PinSignal(AvrCore& core, int pin) : LogicSignal(fmt::format("pin {}", pin)), probe_(core, pin) {
        level_ = high(probe_.state());
        probe_.set_listener([this](const PinState& s, Cycles cycle) {
            const bool level = high(s);
            if (level == level_) return;
            level_ = level;
            changed(level, cycle);
        });
    }
    [[nodiscard]] bool level_at(Cycles /*cycle*/) const override { return level_; }
    [[nodiscard]] double duty() const override { return level_ ? 1.0 : 0.0; }

private:
    static bool high(const PinState& s) { return s.level == PinLevel::driven_high || s.level == PinLevel::pulled_up; }
    PinProbe probe_;
    bool level_ = false;
};

/// `high` or `low`.
class ConstantSignal final : public LogicSignal {
public:
    explicit ConstantSignal(bool level) : LogicSignal(level ? "high" : "low"), level_(level) {}
    [[nodiscard]] bool level_at(Cycles /*cycle*/) const override { return level_; }
    [[nodiscard]] double duty() const override { return level_ ? 1.0 : 0.0; }

private:
    bool level_;
};

[[noreturn]] void refuse(const std::string& source, int line, const std::string& key, const std::string& what) {
    throw std::invalid_argument(fmt::format("{}: key '{}': {}", file_line(source, line), key, what));
}

/// The index of the part entry `e`'s carrier key `key` names; refuses a
/// name no part has and a part that carries nothing.
std::size_t carrier_index(const std::vector<PartEntry>& entries, const std::map<std::string, std::size_t>& index,
                          const PartRegistry& registry, const std::string& source, const PartEntry& e,
                          const std::string& key) {
    const PartEntry::Value& v = e.values.at(key);
    const std::string where = fmt::format("parts.{}.{}", e.name, key);
    const auto it = index.find(v.text);
    if (it == index.end()) refuse(source, v.line, where, fmt::format("no part is called '{}'", v.text));
    const PartType* type = registry.find(entries[it->second].type);
    if (type == nullptr || !type->carries_parts) {
        refuse(source, v.line, where,
               fmt::format("part '{}' ({}) carries nothing: a sensor sits on a servo", v.text,
                           entries[it->second].type));
    }
    return it->second;
}

}  // namespace

std::optional<PartOutputRef> parse_part_output_ref(const std::string& text) {
    const auto dot = text.find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == text.size()) return std::nullopt;
    return PartOutputRef{text.substr(0, dot), text.substr(dot + 1)};
}

std::vector<std::size_t> part_order(const std::vector<PartEntry>& entries, const PartRegistry& registry,
                                    const std::string& source) {
    std::map<std::string, std::size_t> index;
    for (std::size_t i = 0; i < entries.size(); ++i) index.emplace(entries[i].name, i);
    // For each part, the parts it reads (checked: they exist and have the port).
    std::vector<std::vector<std::size_t>> reads(entries.size());
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const PartType* type = registry.find(entries[i].type);
        for (const auto& [key, value] : entries[i].values) {
            const PartKey* k = type != nullptr ? type->key(key) : nullptr;
            if (k != nullptr && k->kind == PartKeyKind::carrier && !value.text.empty()) {
                reads[i].push_back(carrier_index(entries, index, registry, source, entries[i], key));
                continue;
            }
            if (k == nullptr || k->kind != PartKeyKind::input) continue;
            const auto ref = parse_part_output_ref(value.text);
            if (!ref) continue;
            const std::string where = fmt::format("parts.{}.{}", entries[i].name, key);
            const auto it = index.find(ref->part);
            if (it == index.end()) {
                refuse(source, value.line, where, fmt::format("'{}': no part is called '{}': the input is fed by nothing",
                                                              value.text, ref->part));
            }
            const PartType* from = registry.find(entries[it->second].type);
            if (from == nullptr || !from->has_port(ref->port)) {
                refuse(source, value.line, where,
                       fmt::format("'{}': part '{}' ({}) has no output '{}': the input is fed by nothing", value.text,
                                   ref->part, entries[it->second].type, ref->port));
            }
            reads[i].push_back(it->second);
        }
    }
    // Depth-first, in file order: a part after what it reads; a part met again
    // while its own inputs are being followed closes a loop.
    std::vector<int> state(entries.size(), 0);  // 0 new, 1 in progress, 2 placed
    std::vector<std::size_t> order;
    std::function<void(std::size_t)> place = [&](std::size_t i) {
        if (state[i] == 2) return;
        if (state[i] == 1) {
            refuse(source, entries[i].line, fmt::format("parts.{}", entries[i].name),
                   "a loop of parts feeding each other: each part must be fed by pins or by parts it does not feed");
        }
        state[i] = 1;
        for (const std::size_t j : reads[i]) place(j);
        state[i] = 2;
        order.push_back(i);
    };
    for (std::size_t i = 0; i < entries.size(); ++i) place(i);
    return order;
}

PartSet::PartSet(AvrCore& core, const std::vector<PartEntry>& entries, const PartRegistry& registry,
                 const std::function<plant::Pose()>& pose, const plant::World* world)
    : core_(core) {
    static const plant::World kPlainFloor;
    for (const std::size_t i : part_order(entries, registry, "the board")) {
        const PartEntry& entry = entries[i];
        const PartType* type = registry.find(entry.type);
        if (type == nullptr) throw std::invalid_argument(fmt::format("part '{}': unknown type '{}'", entry.name, entry.type));
        if (type->on_wheel()) {
            throw std::invalid_argument(fmt::format("part '{}' ({}) sits on a wheel: the board file puts it there", entry.name,
                                                    entry.type));
        }
        const PartContext ctx(
            core_, entry, [this, &entry](const std::string& key) -> const LogicSignal& { return input_signal(entry, key); },
            pose, world != nullptr ? *world : kPlainFloor,
            [this](const std::string& name) -> const Part& { return *find(name); });
        parts_.push_back(Built{entry.name, type, type->create(ctx)});
    }
}

PartSet::~PartSet() = default;

const LogicSignal& PartSet::input_signal(const PartEntry& entry, const std::string& key) {
    const auto it = entry.values.find(key);
    if (it == entry.values.end()) {
        throw std::logic_error(fmt::format("part '{}': input '{}' is not wired", entry.name, key));
    }
    const PartEntry::Value& v = it->second;
    if (const auto ref = parse_part_output_ref(v.text)) return output(ref->part, ref->port);
    if (v.text == "high" || v.text == "low") {
        signals_.push_back(std::make_unique<ConstantSignal>(v.text == "high"));
    } else {
        signals_.push_back(std::make_unique<PinSignal>(core_, v.pin));
    }
    return *signals_.back();
}

const Part* PartSet::find(const std::string& name) const {
    for (const Built& b : parts_) {
        if (b.name == name) return b.part.get();
    }
    return nullptr;
}

const LogicSignal& PartSet::output(const std::string& name, const std::string& port) const {
    const Part* part = find(name);
    if (part == nullptr) throw std::invalid_argument(fmt::format("no part is called '{}'", name));
    return part->output(port);
}

std::vector<PartSet::Output> PartSet::outputs() const {
    std::vector<Output> out;
    for (const Built& b : parts_) {
        for (const PartPort& p : b.type->ports) out.push_back(Output{b.name, p.name, &b.part->output(p.name)});
    }
    return out;
}

const LogicSignal& PartSet::signal(const std::string& ref) const {
    const auto r = parse_part_output_ref(ref);
    if (!r) throw std::invalid_argument(fmt::format("'{}' is not a part output (NAME.PORT)", ref));
    return output(r->part, r->port);
}

std::vector<std::string> PartSet::truth_columns() const {
    std::vector<std::string> out;
    for (const Built& b : parts_) {
        for (const std::string& c : b.part->truth_columns()) {
            std::string column = b.name;
            column += '.';
            column += c;
            out.push_back(std::move(column));
        }
    }
    return out;
}

std::vector<std::string> PartSet::warnings() const {
    std::vector<std::string> out;
    for (const Built& b : parts_) {
        for (const std::string& w : b.part->warnings()) out.push_back(fmt::format("part '{}': {}", b.name, w));
    }
    return out;
}

void PartSet::truth_values(std::vector<double>& out) const {
    for (const Built& b : parts_) b.part->truth_values(out);
}

void PartSet::set_reading(const std::string& name, const std::string& reading, std::optional<double> value) {
    const auto it = std::find_if(parts_.begin(), parts_.end(), [&](const Built& b) { return b.name == name; });
    if (it == parts_.end() || it->type->readings.empty()) {
        std::vector<std::string> settable_parts;
        for (const Built& b : parts_) {
            if (!b.type->readings.empty()) settable_parts.push_back(fmt::format("{} ({})", b.name, b.type->type));
        }
        throw std::invalid_argument(fmt::format(
            "sensor '{}': {}; the board's parts with settable readings are: {}", name,
            it == parts_.end() ? "the board has no such part" : "its readings cannot be set (" + it->type->type + ")",
            settable_parts.empty() ? std::string("none") : fmt::format("{}", fmt::join(settable_parts, ", "))));
    }
    const std::vector<SettableReading>& readings = it->type->readings;
    const auto r = std::find_if(readings.begin(), readings.end(), [&](const SettableReading& s) { return s.name == reading; });
    if (r == readings.end()) {
        std::vector<std::string> names(readings.size());
        std::transform(readings.begin(), readings.end(), names.begin(), [](const SettableReading& s) { return s.name; });
        throw std::invalid_argument(fmt::format("sensor '{}' ({}) has no reading '{}'; it has: {}", name,
                                                it->type->type, reading, fmt::join(names, ", ")));
    }
    if (value && !(*value >= r->lo && *value <= r->hi)) {
        throw std::invalid_argument(fmt::format("sensor '{}': {} = {} is outside [{}, {}] ({})", name, reading, *value,
                                                r->lo, r->hi, r->description));
    }
    it->part->set_reading(reading, value);
}

void PartSet::on_plant_step(Cycles pose_cycle) {
    for (Built& b : parts_) b.part->on_plant_step(pose_cycle);
}

}  // namespace ddmr::hil
