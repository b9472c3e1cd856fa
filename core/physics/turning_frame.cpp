// SPDX-License-Identifier: MIT
#include "core/physics/turning_frame.hpp"

#include "core/physics/step.hpp"

namespace pb {

TurningFrame::TurningFrame(const mjModel& m, const SceneLayout& l) {
  auto moved_by = [&](int body) {  // the nearest body up the tree with a free joint
    int b = body;
    while (b > 0 && m.body_jntnum[b] == 0) b = m.body_parentid[b];
    return b > 0 ? m.jnt_dofadr[m.body_jntadr[b]] : -1;
  };
  bodies_.emplace_back(l.pallet_body, moved_by(l.pallet_body));
  for (int b : l.item_bodies) bodies_.emplace_back(b, moved_by(b));
}

void TurningFrame::apply(const mjModel& m, mjData& d, double omega, const double axis_xy[2],
                         const double belt_v[2], const double belt_a[2]) const {
  DemandField field;
  if (omega != 0.0) {  // the load is pushed opposite to the belt's acceleration
    field = {-belt_a[0], -belt_a[1], omega * omega, axis_xy[0], axis_xy[1]};
  }
  set_demand_field(&m, &d, field);
  const double w2 = omega * omega;
  for (const auto& [b, dof] : bodies_) {
    mjtNum* f = d.xfrc_applied + 6 * b;
    if (omega == 0.0) {
      f[0] = f[1] = 0.0;
      continue;
    }
    const double mass = m.body_mass[b];
    const double dx = d.xipos[3 * b] - axis_xy[0], dy = d.xipos[3 * b + 1] - axis_xy[1];
    // A merged body moves with its carrier: the carrier's velocity stands for its own (the
    // difference, the carrier's spin times the offset, is second order in a turn's forces).
    const double vx = dof >= 0 ? d.qvel[dof] - belt_v[0] : 0.0;
    const double vy = dof >= 0 ? d.qvel[dof + 1] - belt_v[1] : 0.0;
    f[0] = mass * (w2 * dx + 2.0 * omega * vy);
    f[1] = mass * (w2 * dy - 2.0 * omega * vx);
  }
}

}  // namespace pb
