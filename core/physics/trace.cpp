// SPDX-License-Identifier: MIT
#include "core/physics/trace.hpp"

#include <cassert>

namespace pb {

void Trace::reserve(std::size_t frames) {
  t_.reserve(frames);
  belt_.reserve(frames);
  pallet_.reserve(frames);
  items_.reserve(frames * static_cast<std::size_t>(n_items_));
}

void Trace::push(double t, const BeltState& belt, const Pose& pallet, std::span<const Pose> items) {
  assert(items.size() == static_cast<std::size_t>(n_items_));
  t_.push_back(t);
  belt_.push_back(belt);
  pallet_.push_back(pallet);
  items_.insert(items_.end(), items.begin(), items.end());
}

}  // namespace pb
