// SPDX-License-Identifier: MIT
#include "core/probe_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/engine.hpp"
#include "core/text.hpp"

namespace pb {

namespace {

constexpr int kWarnings[] = {mjWARN_CONTACTFULL, mjWARN_CNSTRFULL, mjWARN_BADQACC, mjWARN_BADQVEL,
                             mjWARN_BADQPOS,     mjWARN_BADCTRL,   mjWARN_INERTIA};

bool any_warning(const mjData& d) {
  for (int w : kWarnings) {
    if (d.warning[w].number > 0) return true;
  }
  return false;
}

double norm3(const mjtNum* v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace

std::optional<std::string> BeltWatch::check(double error) {
  growth_ = (error > 0.05 && error > last_) ? growth_ + 1 : 0;
  last_ = error;
  if (growth_ < 3) return std::nullopt;
  return "the belt no longer follows its command (error " + fixed(error, 2) +
         " m/s and growing): the belt drive's integration diverged";
}

Pose body_pose(const mjData& d, int body) {
  Pose p;
  for (int k = 0; k < 3; ++k) p.pos[static_cast<std::size_t>(k)] = d.xpos[3 * body + k];
  for (int k = 0; k < 4; ++k) p.quat[static_cast<std::size_t>(k)] = d.xquat[4 * body + k];
  return p;
}

void read_item_poses(const SceneLayout& layout, const mjData& d, std::vector<Pose>& out) {
  const auto& bodies = layout.item_bodies;
  out.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) out[i] = body_pose(d, bodies[i]);
}

double max_relative_speed(const SceneLayout& l, const mjData& d, double belt_vx, double belt_vy,
                          double* spin) {
  double fastest = 0.0;
  double fastest_spin = 0.0;
  auto visit = [&](int dof) {
    const mjtNum rel[3] = {d.qvel[dof] - belt_vx, d.qvel[dof + 1] - belt_vy, d.qvel[dof + 2]};
    fastest = std::max(fastest, norm3(rel));
    fastest_spin = std::max(fastest_spin, norm3(d.qvel + dof + 3));
  };
  visit(l.pallet_dof);
  for (int dof : l.item_dofs) visit(dof);
  if (spin != nullptr) *spin = fastest_spin;
  return fastest;
}

void load_rest_state(const mjModel& m, const SceneLayout& l, const RestState& rest,
                     double initial_speed, mjData& d) {
  std::copy(rest.qpos.begin(), rest.qpos.end(), d.qpos);
  std::copy(rest.qvel.begin(), rest.qvel.end(), d.qvel);
  std::copy(rest.qacc_warmstart.begin(), rest.qacc_warmstart.end(), d.qacc_warmstart);
  d.time = 0.0;
  std::fill(d.ctrl, d.ctrl + m.nu, 0.0);
  std::fill(d.act, d.act + m.na, 0.0);
  std::fill(d.qfrc_applied, d.qfrc_applied + m.nv, 0.0);
  std::fill(d.xfrc_applied, d.xfrc_applied + 6 * m.nbody, 0.0);
  std::memset(d.warning, 0, sizeof(d.warning));
  if (initial_speed != 0.0) {  // everything rides along at the initial speed
    d.qvel[l.belt_x_dof] += initial_speed;
    d.qvel[l.pallet_dof] += initial_speed;
    for (int dof : l.item_dofs) d.qvel[dof] += initial_speed;
    d.ctrl[l.belt_x_act] = initial_speed;
  }
}

ProbeRun::ProbeRun(const Scene& scene, const RestState& rest, const ConveyorProfile& profile,
                   const SimOptions& options)
    : scene_(&scene),
      rest_(&rest),
      profile_(profile),
      o_(options),
      detector_(options.thresholds, rest.pallet, rest.items) {
  const mjModel* m = scene.model.get();
  const SceneLayout& l = scene.layout;
  v0_ = profile_.initial_speed_mps();
  r_.trace = Trace(static_cast<int>(l.item_bodies.size()));
  dt_ = m->opt.timestep;
  n_steps_ = static_cast<int>(std::ceil(profile_.duration_s / dt_ - 1e-9));
  const auto breakpoints = profile_.breakpoints();
  last_breakpoint_ = breakpoints.empty() ? 0.0 : breakpoints.back();
  belt_x0_ = rest.qpos[static_cast<std::size_t>(l.belt_x_qpos)];
  belt_y0_ = rest.qpos[static_cast<std::size_t>(l.belt_y_qpos)];
  if (auto problem = numerical_limits_problem(scene)) {
    r_.outcome = Outcome::unstable;
    r_.reason = *problem;
    done_ = true;
    return;
  }
  // Divergence a detector could mistake for a failure: a belt that stops following its command
  // (its error growing step after step) or a pallet sinking through the belt.
  fall_through_z_ = rest.pallet.pos[2] - 0.01;
  if (o_.record_trace) {
    r_.trace.reserve(static_cast<std::size_t>(n_steps_) + 1);
    r_.trace.push(0.0, {0.0, 0.0, v0_, 0.0}, rest.pallet, rest.items);
  }
  // Co-moving must hold this long before a run stops early (a rocking load passes through
  // matching velocities for an instant).
  comove_needed_ = std::max(1, static_cast<int>(std::lround(0.05 / dt_)));
  if (n_steps_ <= 0) done_ = true;  // finish() gives the final check
}

void ProbeRun::before_step(mjData& d) {
  const SceneLayout& l = scene_->layout;
  const double t_next = (k_ + 1) * dt_;
  // A velocity actuator with kv = M/dt reaches its command in one step: command the velocity
  // the belt should have at the end of this step.
  d.ctrl[l.belt_x_act] = profile_.velocity_at(t_next);
  d.ctrl[l.belt_y_act] = profile_.lateral_velocity_at(t_next);
  command_x_ = d.ctrl[l.belt_x_act];
  command_y_ = d.ctrl[l.belt_y_act];
}

void ProbeRun::unstable(const std::string& reason) {
  r_.outcome = Outcome::unstable;
  r_.reason = reason;
  r_.failure.reset();
  done_ = true;
}

void ProbeRun::engine_error(const std::string& reason) {
  unstable(reason + " (at t = " + fixed((k_ + 1) * dt_, 3) + " s)");
}

void ProbeRun::finish(const mjModel& m, const mjData& d) {
  done_ = true;
  if (r_.outcome == Outcome::unstable) {
    r_.failure.reset();
    return;
  }
  if (auto reason = instability_reason(&m, &d)) {
    unstable(*reason + " (by t = " + fixed(r_.sim_time_s, 3) + " s)");
  }
}

bool ProbeRun::after_step(const mjModel& m, const mjData& d) {
  const SceneLayout& l = scene_->layout;
  const int k = ++k_;
  const double t_next = k * dt_;
  r_.steps = k;
  r_.sim_time_s = t_next;
  std::optional<std::string> broken;
  if (any_warning(d)) broken = instability_reason(&m, &d).value_or("MuJoCo raised a warning");
  if (!broken) {
    broken = belt_watch_.check(
        std::hypot(d.qvel[l.belt_x_dof] - command_x_, d.qvel[l.belt_y_dof] - command_y_));
  }
  if (!broken && d.xpos[3 * l.pallet_body + 2] < fall_through_z_) {
    broken = std::string("the pallet sank through the belt: contacts could not hold it");
  }
  if (broken) {
    unstable(*broken + " (at t = " + fixed(t_next, 3) + " s)");
    return false;
  }
  const Trace::BeltState belt{d.qpos[l.belt_x_qpos] - belt_x0_, d.qpos[l.belt_y_qpos] - belt_y0_,
                              d.qvel[l.belt_x_dof], d.qvel[l.belt_y_dof]};
  const Pose pallet = body_pose(d, l.pallet_body);
  read_item_poses(l, d, items_);
  if (o_.record_trace) r_.trace.push(t_next, belt, pallet, items_);
  if (!r_.failure) {
    if (auto event = detector_.update(t_next, belt, pallet, items_)) {
      r_.failure = std::move(event);
      r_.outcome = Outcome::failed;
      if (o_.fail_fast) {
        finish(m, d);
        return false;
      }
    }
  }
  if (o_.early_stop && !r_.failure && t_next >= last_breakpoint_) {
    double spin = 0.0;
    const double speed = max_relative_speed(l, d, belt.vx, belt.vy, &spin);
    comove_steps_ =
        (speed < o_.comove_speed_mps && spin < o_.comove_spin_radps) ? comove_steps_ + 1 : 0;
    if (comove_steps_ >= comove_needed_) {
      r_.stopped_early = k < n_steps_;
      finish(m, d);
      return false;
    }
  }
  if (k >= n_steps_) {
    finish(m, d);
    return false;
  }
  return true;
}

}  // namespace pb
