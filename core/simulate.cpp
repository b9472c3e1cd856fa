// SPDX-License-Identifier: MIT
#include "core/simulate.hpp"

#include "core/text.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

namespace pb {

namespace {

constexpr int kWarnings[] = {mjWARN_CONTACTFULL, mjWARN_CNSTRFULL, mjWARN_BADQACC, mjWARN_BADQVEL,
                             mjWARN_BADQPOS,     mjWARN_BADCTRL,   mjWARN_INERTIA};

// A belt that stops following its command, its error growing step after step, has diverged (an
// explicit velocity drive with kv dt / M >= 2 triples its error every step); a detector would
// otherwise report the runaway motion as a conveyor failure.
class BeltWatch {
 public:
  std::optional<std::string> check(double error) {
    growth_ = (error > 0.05 && error > last_) ? growth_ + 1 : 0;
    last_ = error;
    if (growth_ < 3) return std::nullopt;
    return "the belt no longer follows its command (error " + fixed(error, 2) +
           " m/s and growing): the belt drive's integration diverged";
  }

 private:
  double last_ = 0.0;
  int growth_ = 0;
};

bool any_warning(const mjData* d) {
  for (int w : kWarnings) {
    if (d->warning[w].number > 0) return true;
  }
  return false;
}

double norm3(const mjtNum* v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace

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

Pose Simulator::body_pose(int body) const {
  const mjData* d = data_.get();
  Pose p;
  for (int k = 0; k < 3; ++k) p.pos[static_cast<std::size_t>(k)] = d->xpos[3 * body + k];
  for (int k = 0; k < 4; ++k) p.quat[static_cast<std::size_t>(k)] = d->xquat[4 * body + k];
  return p;
}

void Simulator::read_items(std::vector<Pose>& out) const {
  const auto& bodies = scene_->layout.item_bodies;
  out.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) out[i] = body_pose(bodies[i]);
}

double Simulator::max_relative_speed(double belt_vx, double belt_vy, double* spin) const {
  const mjData* d = data_.get();
  const SceneLayout& l = scene_->layout;
  double fastest = 0.0;
  double fastest_spin = 0.0;
  auto visit = [&](int dof) {
    const mjtNum rel[3] = {d->qvel[dof] - belt_vx, d->qvel[dof + 1] - belt_vy, d->qvel[dof + 2]};
    fastest = std::max(fastest, norm3(rel));
    fastest_spin = std::max(fastest_spin, norm3(d->qvel + dof + 3));
  };
  visit(l.pallet_dof);
  for (int dof : l.item_dofs) visit(dof);
  if (spin != nullptr) *spin = fastest_spin;
  return fastest;
}

void Simulator::load(const RestState& rest, double initial_speed) {
  const mjModel* m = scene_->model.get();
  mjData* d = data_.get();
  const SceneLayout& l = scene_->layout;
  std::copy(rest.qpos.begin(), rest.qpos.end(), d->qpos);
  std::copy(rest.qvel.begin(), rest.qvel.end(), d->qvel);
  std::copy(rest.qacc_warmstart.begin(), rest.qacc_warmstart.end(), d->qacc_warmstart);
  d->time = 0.0;
  std::fill(d->ctrl, d->ctrl + m->nu, 0.0);
  std::fill(d->act, d->act + m->na, 0.0);
  std::fill(d->qfrc_applied, d->qfrc_applied + m->nv, 0.0);
  std::fill(d->xfrc_applied, d->xfrc_applied + 6 * m->nbody, 0.0);
  std::memset(d->warning, 0, sizeof(d->warning));
  if (initial_speed != 0.0) {  // everything rides along at the initial speed
    d->qvel[l.belt_x_dof] += initial_speed;
    d->qvel[l.pallet_dof] += initial_speed;
    for (int dof : l.item_dofs) d->qvel[dof] += initial_speed;
    d->ctrl[l.belt_x_act] = initial_speed;
  }
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
    speed = max_relative_speed(0.0, 0.0, &spin);
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
  rest.pallet = body_pose(scene_->layout.pallet_body);
  read_items(rest.items);
  rest.settle_time_s = d->time;
  rest.residual_speed_mps = speed;
  return Result<RestState>{std::move(rest), {}};
}

SimResult Simulator::run(const RestState& rest, const ConveyorProfile& profile,
                         const SimOptions& o) {
  const auto wall_start = std::chrono::steady_clock::now();
  const mjModel* m = scene_->model.get();
  mjData* d = data_.get();
  const SceneLayout& l = scene_->layout;
  const double v0 = profile.initial_speed_mps();
  load(rest, v0);

  SimResult r;
  r.trace = Trace(static_cast<int>(l.item_bodies.size()));
  const double dt = m->opt.timestep;
  const int n_steps = static_cast<int>(std::ceil(profile.duration_s / dt - 1e-9));
  const auto breakpoints = profile.breakpoints();
  const double last_breakpoint = breakpoints.empty() ? 0.0 : breakpoints.back();
  const double belt_x0 = rest.qpos[static_cast<std::size_t>(l.belt_x_qpos)];
  const double belt_y0 = rest.qpos[static_cast<std::size_t>(l.belt_y_qpos)];
  const FailureDetector detector(o.thresholds, rest.pallet, rest.items);
  if (auto problem = numerical_limits_problem(*scene_)) {
    r.outcome = Outcome::unstable;
    r.reason = *problem;
    return r;
  }
  // Divergence a detector could mistake for a failure: a belt that stops following its command
  // (its error growing step after step) or a pallet sinking through the belt.
  BeltWatch belt_watch;
  const double fall_through_z = rest.pallet.pos[2] - 0.01;
  if (o.record_trace) {
    r.trace.reserve(static_cast<std::size_t>(n_steps) + 1);
    r.trace.push(0.0, {0.0, 0.0, v0, 0.0}, rest.pallet, rest.items);
  }

  // Co-moving must hold this long before a run stops early (a rocking load passes through
  // matching velocities for an instant).
  const int comove_needed = std::max(1, static_cast<int>(std::lround(0.05 / dt)));
  int comove_steps = 0;
  std::vector<Pose> items;
  for (int k = 1; k <= n_steps; ++k) {
    const double t_next = k * dt;
    // A velocity actuator with kv = M/dt reaches its command in one step: command the velocity
    // the belt should have at the end of this step.
    d->ctrl[l.belt_x_act] = profile.velocity_at(t_next);
    d->ctrl[l.belt_y_act] = profile.lateral_velocity_at(t_next);
    const double command_x = d->ctrl[l.belt_x_act], command_y = d->ctrl[l.belt_y_act];
    if (auto error = guarded([&] { mj_step(m, d); })) {
      r.outcome = Outcome::unstable;
      r.reason = *error + " (at t = " + fixed(t_next, 3) + " s)";
      mj_resetData(m, d);
      break;
    }
    r.steps = k;
    r.sim_time_s = t_next;
    std::optional<std::string> broken;
    if (any_warning(d)) broken = instability_reason(m, d).value_or("MuJoCo raised a warning");
    if (!broken) {
      broken = belt_watch.check(
          std::hypot(d->qvel[l.belt_x_dof] - command_x, d->qvel[l.belt_y_dof] - command_y));
    }
    if (!broken && d->xpos[3 * l.pallet_body + 2] < fall_through_z) {
      broken = std::string("the pallet sank through the belt: contacts could not hold it");
    }
    if (broken) {
      r.outcome = Outcome::unstable;
      r.reason = *broken + " (at t = " + fixed(t_next, 3) + " s)";
      break;
    }
    const Trace::BeltState belt{d->qpos[l.belt_x_qpos] - belt_x0, d->qpos[l.belt_y_qpos] - belt_y0,
                                d->qvel[l.belt_x_dof], d->qvel[l.belt_y_dof]};
    const Pose pallet = body_pose(l.pallet_body);
    read_items(items);
    if (o.record_trace) r.trace.push(t_next, belt, pallet, items);
    if (!r.failure) {
      if (auto event = detector.update(t_next, belt, pallet, items)) {
        r.failure = std::move(event);
        r.outcome = Outcome::failed;
        if (o.fail_fast) break;
      }
    }
    if (o.early_stop && !r.failure && t_next >= last_breakpoint) {
      double spin = 0.0;
      const double speed = max_relative_speed(belt.vx, belt.vy, &spin);
      comove_steps =
          (speed < o.comove_speed_mps && spin < o.comove_spin_radps) ? comove_steps + 1 : 0;
      if (comove_steps >= comove_needed) {
        r.stopped_early = k < n_steps;
        break;
      }
    }
  }
  if (r.outcome != Outcome::unstable) {
    if (auto reason = instability_reason(m, d)) {
      r.outcome = Outcome::unstable;
      r.reason = *reason + " (by t = " + fixed(r.sim_time_s, 3) + " s)";
      r.failure.reset();
    }
  } else {
    r.failure.reset();
  }
  r.wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start)
          .count();
  return r;
}

}  // namespace pb
