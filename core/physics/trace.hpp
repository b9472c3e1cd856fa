// SPDX-License-Identifier: MIT
// What one simulation of a conveyor profile recorded: belt motion and every body's pose per step.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/base/pose.hpp"

namespace pb {

/// Stored flat (frame-major) so a 24-item, 1000-step trace is a handful of allocations.
class Trace {
 public:
  explicit Trace(int n_items = 0) : n_items_(n_items) {}

  /// Belt displacement and velocity are relative to the rest state (travel since t = 0).
  struct BeltState {
    double x = 0.0;
    double y = 0.0;
    double vx = 0.0;
    double vy = 0.0;
  };

  void reserve(std::size_t frames);
  /// Appends a frame; `items` must hold n_items() poses.
  void push(double t, const BeltState& belt, const Pose& pallet, std::span<const Pose> items);

  int n_items() const { return n_items_; }
  std::size_t size() const { return t_.size(); }
  bool empty() const { return t_.empty(); }
  double time(std::size_t frame) const { return t_[frame]; }
  const BeltState& belt(std::size_t frame) const { return belt_[frame]; }
  const Pose& pallet(std::size_t frame) const { return pallet_[frame]; }
  std::span<const Pose> items(std::size_t frame) const {
    return {items_.data() + frame * static_cast<std::size_t>(n_items_),
            static_cast<std::size_t>(n_items_)};
  }

 private:
  int n_items_ = 0;
  std::vector<double> t_;
  std::vector<BeltState> belt_;
  std::vector<Pose> pallet_;
  std::vector<Pose> items_;
};

}  // namespace pb
