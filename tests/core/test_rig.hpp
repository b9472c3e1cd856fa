// SPDX-License-Identifier: MIT
// Test helper: a pallet's scene compiled, its simulator made and its load settled, for the physics
// tests that drive Simulator::run themselves.
#pragma once

#include <memory>
#include <string>
#include <utility>

#include "core/physics/simulate.hpp"

namespace pb::test {

struct Rig {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Simulator> sim;
  RestState rest;
  std::string error;  ///< what failed, empty when the rig is ready
};

inline Rig settled_rig(const PalletConfig& config, const FrictionModel& friction,
                       const SceneOptions& options = {}) {
  Rig rig;
  auto scene = build_scene(config, options, friction);
  if (!scene) return {nullptr, nullptr, {}, "build_scene failed"};
  rig.scene = std::make_unique<Scene>(std::move(*scene.value));
  auto sim = Simulator::create(*rig.scene);
  if (!sim) return {nullptr, nullptr, {}, "Simulator::create failed"};
  rig.sim = std::make_unique<Simulator>(std::move(*sim.value));
  auto rest = rig.sim->settle();
  if (!rest) return {nullptr, nullptr, {}, "settle failed"};
  rig.rest = std::move(*rest.value);
  return rig;
}

/// Options that step and record every step of a run to its end, no detector firing (the trace is
/// the measurement).
inline SimOptions every_step() {
  SimOptions o;
  o.fail_fast = false;
  o.early_stop = false;
  o.skip_comoving = false;
  o.record_trace = true;
  o.thresholds = {
      .tip_deg = 90.0, .item_slide_m = 10.0, .load_shift_m = 10.0, .pallet_slip_m = 10.0};
  return o;
}

}  // namespace pb::test
