#pragma once
// The built-in part types, one function per part file (the explicit list that
// static linking keeps: builtin_parts.cpp). To add a part: write its file
// with a `PartType <name>_type()`, declare it here and list it in
// builtin_parts.cpp (docs/architecture.md, "How to add a part").

#include "hil/parts/part.hpp"

namespace ddmr::hil {

PartType shift_register_74hc595_type();  // shift_register_74hc595.cpp

}  // namespace ddmr::hil
