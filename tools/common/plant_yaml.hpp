#pragma once
// A plant as YAML, before it is parsed: the embedded defaults or a plant
// file, then overrides merged in, then the encoders' seeds from one run seed.
// What a scenario's `plant: {file, overrides}` and `seed:` do, and the
// Python API's Session(plant=..., seed=...): one merge for both.

#include <yaml-cpp/yaml.h>

#include <cstdint>

namespace ddmr::tools {

/// The embedded default plant (plant/params/default.yaml) as YAML.
YAML::Node default_plant_yaml();

/// Merges `over` into `base`, key by key (a mapping merges into a mapping;
/// anything else replaces). An encoder's resolution is one of two keys:
/// giving one drops the other from `base`.
void merge_plant_yaml(YAML::Node base, const YAML::Node& over);

/// The encoders' noise seeds from one run seed: encoder1 gets `seed`,
/// encoder2 `seed + 1`.
void seed_plant_yaml(YAML::Node& plant, uint64_t seed);

}  // namespace ddmr::tools
