// SPDX-License-Identifier: MIT
// Everything a simulation carries from one step to the next, as values: MuJoCo 2.2.2 has no
// mj_getState, and these are the fields that make a restart bitwise equal to a continued run. The
// settle's rest state, the batch's rows and the benches all keep a state this way.
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <vector>

namespace pb {

struct SimState {
  double time = 0.0;
  std::vector<double> qpos, qvel, act, qacc_warmstart;
  std::vector<double> ctrl, qfrc_applied, xfrc_applied, mocap_pos, mocap_quat, userdata;
  std::array<mjWarningStat, mjNWARNING> warning{};  ///< MuJoCo prints a warning only when 0

  bool operator==(const SimState& other) const;
};

/// One array of the state: where it lives in mjData and in SimState, its name, and its length
/// for a model.
struct StateArray {
  mjtNum* mjData::*data;
  std::vector<double> SimState::*state;
  const char* name;
  int (*width)(const mjModel&);
};

/// The state's arrays in one order (time, a scalar, and the warnings apart).
inline constexpr std::array<StateArray, 10> kStateArrays{{
    {&mjData::qpos, &SimState::qpos, "qpos", [](const mjModel& m) { return m.nq; }},
    {&mjData::qvel, &SimState::qvel, "qvel", [](const mjModel& m) { return m.nv; }},
    {&mjData::act, &SimState::act, "act", [](const mjModel& m) { return m.na; }},
    {&mjData::qacc_warmstart, &SimState::qacc_warmstart, "qacc_warmstart",
     [](const mjModel& m) { return m.nv; }},
    {&mjData::ctrl, &SimState::ctrl, "ctrl", [](const mjModel& m) { return m.nu; }},
    {&mjData::qfrc_applied, &SimState::qfrc_applied, "qfrc_applied",
     [](const mjModel& m) { return m.nv; }},
    {&mjData::xfrc_applied, &SimState::xfrc_applied, "xfrc_applied",
     [](const mjModel& m) { return 6 * m.nbody; }},
    {&mjData::mocap_pos, &SimState::mocap_pos, "mocap_pos",
     [](const mjModel& m) { return 3 * m.nmocap; }},
    {&mjData::mocap_quat, &SimState::mocap_quat, "mocap_quat",
     [](const mjModel& m) { return 4 * m.nmocap; }},
    {&mjData::userdata, &SimState::userdata, "userdata",
     [](const mjModel& m) { return m.nuserdata; }},
}};

/// The state of `d` now.
SimState capture_state(const mjModel& m, const mjData& d);
/// Puts `s` into `d`; its arrays must have the model's lengths (capture_state's do).
void restore_state(const SimState& s, mjData& d);

}  // namespace pb
