// SPDX-License-Identifier: MIT
// A curve turns the pallet. The simulation runs in the belt's frame, which a curve both accelerates
// sideways (v^2 / r at the belt's centre line: the belt's own lateral motion) and turns, at
// omega = v / r about the vertical through that centre. The turning adds the fictitious forces of
// a rotating frame on every body: centrifugal m omega^2 d (d: the body's centre of mass from the
// turning axis, horizontal) and Coriolis -2 m omega z x v (v: its velocity relative to the belt).
// So an item 0.3 m outboard on a 3 m curve feels 10 % more than the centre line's v^2 / r, one
// 0.3 m inboard 10 % less, and one 0.4 m ahead of the centre is pushed forward by 13 % of it
// (0.9 % more in all, against an isotropic friction cone: the friction pyramids are turned along
// the push, step.hpp's DemandField).
//
// Not modelled: the yaw acceleration at the curve's entry and exit (the Euler force). The load
// turns with the belt from the arc's first step, as the lateral acceleration starts in one step;
// how fast a real pallet's heading changes as it enters depends on the curve's transition.
#pragma once

#include <mujoco/mujoco.h>

#include <utility>
#include <vector>

#include "core/physics/scene.hpp"

namespace pb {

class TurningFrame {
 public:
  /// The pallet's body and every item's (free or merged into what carries it), each with the free
  /// joint that moves it (its own, or its carrier's).
  explicit TurningFrame(const mjModel& model, const SceneLayout& layout);

  /// Writes the fictitious forces of a frame turning at `omega` (rad/s, positive counter-clockwise
  /// seen from above) about the vertical through `axis_xy` (world X, Y) into `data.xfrc_applied`,
  /// at each body's centre of mass, and states the field they and the belt's acceleration
  /// `belt_a` (X, Y) push the load with (step.hpp's DemandField, along which the friction pyramids
  /// are turned). `belt_v` is the belt's velocity (X, Y). Positions are `data.xipos` (the last
  /// kinematics: one step behind, the same for every body and the axis). With omega = 0 the
  /// forces and the field are cleared.
  void apply(const mjModel& model, mjData& data, double omega, const double axis_xy[2],
             const double belt_v[2], const double belt_a[2]) const;

 private:
  std::vector<std::pair<int, int>> bodies_;  ///< (body, dof of the free joint that moves it)
};

}  // namespace pb
