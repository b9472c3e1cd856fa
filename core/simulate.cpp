// SPDX-License-Identifier: MIT
#include "core/simulate.hpp"

#include "core/probe_run.hpp"
#include "core/text.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace pb {

std::string_view to_string(Outcome outcome) {
  switch (outcome) {
    case Outcome::safe:
      return "safe";
    case Outcome::failed:
      return "failed";
    case Outcome::unstable:
      return "unstable";
  }
  return "?";
}

Result<Simulator> Simulator::create(const Scene& scene) {
  auto data = make_data(scene.model.get());
  if (!data) return Result<Simulator>::failure(std::move(data.diagnostics));
  return Result<Simulator>{Simulator(scene, std::move(*data.value)), {}};
}

double Simulator::data_bytes() const {
  return double(data_->nbuffer) + double(data_->nstack) * sizeof(mjtNum);
}

Result<RestState> Simulator::settle(const SettleOptions& o) {
  const mjModel* m = scene_->model.get();
  mjData* d = data_.get();
  mj_resetData(m, d);
  std::optional<std::string> error = numerical_limits_problem(*scene_);
  const int check_every =
      std::max(1, static_cast<int>(std::lround(o.check_every_s / m->opt.timestep)));
  const int max_steps = static_cast<int>(std::ceil(o.max_time_s / m->opt.timestep));
  const SceneLayout& l = scene_->layout;
  double speed = 0.0, spin = 0.0;
  bool at_rest = false;
  int step = 0;
  BeltWatch belt;
  while (step < max_steps && !at_rest && !error) {
    error = guarded([&] {
      for (int k = 0; k < check_every && !error; ++k) {
        mj_step(m, d);
        error = belt.check(std::hypot(d->qvel[l.belt_x_dof], d->qvel[l.belt_y_dof]));
      }
    });
    step += check_every;
    if (!error) error = instability_reason(m, d);
    if (error) *error += " (by t = " + fixed(step * m->opt.timestep, 3) + " s)";
    speed = max_relative_speed(l, *d, 0.0, 0.0, &spin);
    at_rest = d->time >= o.min_time_s && speed < o.rest_speed_mps && spin < o.rest_spin_radps;
  }
  if (error) {
    mj_resetData(m, d);
    return Result<RestState>::failure(
        "", "the load could not be settled on a still belt: " + *error +
                "; the layout or the numerical settings are at fault, not the conveyor");
  }
  if (!at_rest) {
    return Result<RestState>::failure(
        "/items", "the load is still moving after " + std::to_string(o.max_time_s) +
                      " s on a still belt (fastest body " + std::to_string(speed * 100.0) +
                      " cm/s): a build defect, not a conveyor failure; check for items that lean, "
                      "overhang or rest on too little");
  }
  RestState rest;
  rest.qpos.assign(d->qpos, d->qpos + m->nq);
  rest.qvel.assign(d->qvel, d->qvel + m->nv);
  rest.qacc_warmstart.assign(d->qacc_warmstart, d->qacc_warmstart + m->nv);
  rest.pallet = body_pose(*d, l.pallet_body);
  read_item_poses(l, *d, rest.items);
  rest.settle_time_s = d->time;
  rest.residual_speed_mps = speed;
  return Result<RestState>{std::move(rest), {}};
}

SimResult Simulator::run(const RestState& rest, const ConveyorProfile& profile,
                         const SimOptions& o) {
  const auto wall_start = std::chrono::steady_clock::now();
  const mjModel* m = scene_->model.get();
  mjData* d = data_.get();
  ProbeRun probe(*scene_, rest, profile, o);
  load_rest_state(*m, scene_->layout, rest, probe.initial_speed(), *d);
  if (probe.done()) {
    if (probe.result().outcome == Outcome::unstable) return probe.take_result();
    probe.finish(*m, *d);  // nothing to step
  }
  while (!probe.done()) {
    probe.before_step(*d);
    if (auto error = guarded([&] { mj_step(m, d); })) {
      probe.engine_error(*error);
      mj_resetData(m, d);
      break;
    }
    if (!probe.after_step(*m, *d)) break;
  }
  SimResult r = probe.take_result();
  r.wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start)
          .count();
  return r;
}

}  // namespace pb
