#include "hil/parts/part_registry.hpp"

#include <fmt/format.h>

#include <set>
#include <stdexcept>

namespace ddmr::hil {

PartRegistry& PartRegistry::global() {
    static PartRegistry* registry = [] {
        auto* r = new PartRegistry;  // never destroyed: parts may be looked up at exit
        for (PartType& t : builtin_part_types()) r->add(std::move(t));
        return r;
    }();
    return *registry;
}

void PartRegistry::add(PartType type) {
    if (type.type.empty()) throw std::invalid_argument("a part type needs a name");
    if (!type.create && !type.on_wheel()) throw std::invalid_argument(fmt::format("part type '{}' has no factory", type.type));
    std::set<std::string> names{"name", "type"};
    for (const PartKey& k : type.keys) {
        if (!names.insert(k.name).second) {
            throw std::invalid_argument(fmt::format("part type '{}': key '{}' is declared twice (or is name/type)",
                                                    type.type, k.name));
        }
    }
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const PartType& t : types_) {
        if (t.type == type.type) throw std::invalid_argument(fmt::format("part type '{}' is already registered", t.type));
    }
    types_.push_back(std::move(type));
}

const PartType* PartRegistry::find(const std::string& type) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const PartType& t : types_) {
        if (t.type == type) return &t;
    }
    return nullptr;
}

std::vector<const PartType*> PartRegistry::types() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::vector<const PartType*> out;
    for (const PartType& t : types_) out.push_back(&t);
    return out;
}

std::string PartRegistry::type_list() const {
    std::string out;
    for (const PartType* t : types()) out += (out.empty() ? "" : ", ") + t->type;
    return out;
}

}  // namespace ddmr::hil
