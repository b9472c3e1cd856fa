// SPDX-License-Identifier: MIT
// The fidelity ladder: which model answers a question. Each level is a real model, not a shortcut
// in the result: closed-form quasi-static bounds (per-interface slip, per-sub-stack tip), a
// reduced multi-body model (items the wrap holds rigidly merged into the pallet body), or the full
// multi-body model. `automatic` picks the cheapest level whose agreement with the full model is
// established for pallets of that kind; the level actually used is reported in
// SafetyResult::fidelity.
#pragma once

#include <array>

#include "core/enums.hpp"

namespace pb {

enum class Fidelity { automatic, closed_form, reduced, full };

template <>
struct EnumTable<Fidelity> {
  static constexpr std::array<EnumName<Fidelity>, 4> names{{{Fidelity::automatic, "auto"},
                                                            {Fidelity::closed_form, "closed_form"},
                                                            {Fidelity::reduced, "reduced"},
                                                            {Fidelity::full, "full"}}};
};

}  // namespace pb
