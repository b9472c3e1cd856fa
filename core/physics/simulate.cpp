// SPDX-License-Identifier: MIT
#include "core/physics/simulate.hpp"

#include "core/base/text.hpp"
#include "core/physics/probe_run.hpp"
#include "core/physics/step.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace pb {

Result<Simulator> Simulator::create(const Scene& scene) {
  auto data = make_data(scene.model.get());
  if (!data) return Result<Simulator>::failure(std::move(data.diagnostics));
  return Result<Simulator>{Simulator(scene, std::move(*data.value)), {}};
}

double Simulator::data_bytes() const {
  return double(data_->nbuffer) + double(data_->nstack) * sizeof(mjtNum) -
         double(shared_data_bytes(data_.get()));
}

namespace {

// The state a probe starts from: the data as it is now, at t = 0, with no control, activation or
// applied force, and no warning counted (the settle's are not the probe's).
RestState capture(const mjModel& m, const mjData& d, const SceneLayout& l, double speed) {
  RestState rest;
  rest.state = capture_state(m, d);
  rest.state.time = 0.0;
  for (auto* v :
       {&rest.state.ctrl, &rest.state.act, &rest.state.qfrc_applied, &rest.state.xfrc_applied}) {
    std::fill(v->begin(), v->end(), 0.0);
  }
  rest.state.warning = {};
  rest.pallet = body_pose(d, l.pallet_body);
  read_item_poses(l, d, rest.items);
  rest.settle_time_s = d.time;
  rest.residual_speed_mps = speed;
  return rest;
}

// Why a load that moved (or never came to rest) on a still belt cannot stand, for a supervisor:
// the lowest item that moved is where the collapse starts; what is above it follows.
StandFailure stand_failure(const Scene& scene, const mjData& d, const DetectorThresholds& t,
                           const Pose& pallet0, const std::vector<Pose>& items0,
                           const std::vector<Pose>& items, std::optional<FailureEvent> event) {
  const auto& config = scene.config;
  const Pose pallet = body_pose(d, scene.layout.pallet_body);
  StandFailure out;
  // The culprit: lowest as built (to a micrometre), then the one that moved most.
  auto rank = [&](std::size_t i, double moved) {
    return std::pair{std::round(config.items[i].position[2] * 1e6), -moved};
  };
  std::pair<double, double> best{0.0, 0.0};
  for (std::size_t i = 0; i < items.size() && i < config.items.size(); ++i) {
    const Vec3 a = to_frame(pallet, items[i].pos);
    const Vec3 b = to_frame(pallet0, items0[i].pos);
    const double moved = std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    if (moved <= 0.5 * t.load_shift_m) continue;
    ++out.moved;
    if (out.item < 0 || rank(i, moved) < best) {
      out.item = static_cast<int>(i);
      best = rank(i, moved);
    }
  }
  const auto& l = scene.layout;
  if (out.item < 0 && l.item_dofs.size() == config.items.size()) {
    // Nothing moved far: the fastest item (or the event's).
    double fastest = -1.0;
    for (std::size_t i = 0; i < l.item_dofs.size(); ++i) {
      const mjtNum* v = d.qvel + l.item_dofs[i];
      const double speed = std::hypot(v[0], v[1], v[2]);
      if (speed > fastest) {
        fastest = speed;
        out.item = static_cast<int>(i);
      }
    }
    if (event && !event->items.empty()) out.item = event->items.front();
  }
  std::string name = "the load";
  if (out.item >= 0 && std::size_t(out.item) < config.items.size()) {
    const Item& it = config.items[std::size_t(out.item)];
    name = "item " + std::to_string(out.item) + " (" + it.sku + ")";
  }
  const double t_s = d.time;  // from the start of the settle
  if (event) {
    out.event = *event;
    const int others = std::max(0, out.moved - 1);
    out.sentence = name + " cannot stand: with the belt standing still, " + what_moved(*event) +
                   " within " + fixed(t_s, 2) + " s of being stacked" +
                   (others > 0 ? " (" + std::to_string(others) + " other item" +
                                     (others == 1 ? "" : "s") + " moved with it)"
                               : "") +
                   "; re-stack it squarely over what carries it. This is a build defect, not a "
                   "conveyor limit";
  } else {
    out.sentence = "the load does not come to rest on a still belt: " + name +
                   " is still moving after " + fixed(t_s, 1) +
                   " s; re-stack it squarely over what carries it. This is a build defect, not a "
                   "conveyor limit";
  }
  return out;
}

}  // namespace

Result<RestState> Simulator::settle(const SettleOptions& o, const DetectorThresholds& thresholds) {
  const mjModel* m = scene_->model.get();
  mjData* d = data_.get();
  reset_data(m, d);
  std::optional<std::string> error = numerical_limits_problem(*scene_);
  const int check_every =
      std::max(1, static_cast<int>(std::lround(o.check_every_s / m->opt.timestep)));
  const int max_steps = static_cast<int>(std::ceil(o.max_time_s / m->opt.timestep));
  const int hold_steps = static_cast<int>(std::lround(o.hold_s / m->opt.timestep));
  const SceneLayout& l = scene_->layout;
  // The as-built poses: what a detector crossing on a still belt is measured against.
  mj_kinematics(m, d);
  const Pose pallet0 = body_pose(*d, l.pallet_body);
  std::vector<Pose> items0, items;
  read_item_poses(l, *d, items0);
  const FailureDetector detector(thresholds, pallet0, items0);
  double speed = 0.0, spin = 0.0;
  int quiet_since = -1;  // the step from which the load has been at rest at every check
  bool settled = false;
  // The state where the load first came to rest: the rest state, once the hold confirms it (the
  // hold checks; it does not move the start of the probes).
  RestState first;
  int first_step = -1;
  // How far a body has gone from where the load first came to rest, and how far it has turned
  // (radians, as the chord its axes swept: small angles): each item relative to its pallet, the
  // pallet relative to its (still) belt.
  struct Drift {
    double m = 0.0, rad = 0.0;
  };
  auto turned = [](const Quat& frame0, const Quat& q0, const Quat& frame, const Quat& q) {
    double chord = 0.0;
    for (const Vec3& e : {Vec3{1.0, 0.0, 0.0}, Vec3{0.0, 0.0, 1.0}}) {
      const Vec3 a = rotate_inverse(frame, rotate(q, e));
      const Vec3 b = rotate_inverse(frame0, rotate(q0, e));
      chord = std::max(chord, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
    }
    return chord;
  };
  auto drift_from_first = [&] {
    const Pose pallet = body_pose(*d, l.pallet_body);
    Drift out;
    for (std::size_t i = 0; i < items.size() && i < first.items.size(); ++i) {
      const Vec3 a = to_frame(pallet, items[i].pos);
      const Vec3 b = to_frame(first.pallet, first.items[i].pos);
      out.m = std::max(out.m, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
      out.rad = std::max(
          out.rad, turned(first.pallet.quat, first.items[i].quat, pallet.quat, items[i].quat));
    }
    const std::vector<double>& q0 = first.state.qpos;  // the belt's position then, too
    out.m =
        std::max(out.m, std::hypot(pallet.pos[0] - first.pallet.pos[0] -
                                       (d->qpos[l.belt_x_qpos] - q0[std::size_t(l.belt_x_qpos)]),
                                   pallet.pos[1] - first.pallet.pos[1] -
                                       (d->qpos[l.belt_y_qpos] - q0[std::size_t(l.belt_y_qpos)]),
                                   pallet.pos[2] - first.pallet.pos[2]));
    const Quat level{1.0, 0.0, 0.0, 0.0};
    out.rad = std::max(out.rad, turned(level, first.pallet.quat, level, pallet.quat));
    return out;
  };
  // Contact chatter: a tall load's stacks rock by a tenth of a millimetre at a few millimetres a
  // second and never pass a whole hold below the rest speed. A load whose bodies stay, at every
  // check of the hold after it first came to rest, within what the rest speed and spin would carry
  // them over the hold has held there on average no faster: it is settled at the first check
  // after that at which it is at rest again (a load that starts to tip slowly, within that bound,
  // is moving faster than the rest speed at the hold's end, and is followed on).
  const double calm_m = o.rest_speed_mps * o.hold_s;
  const double calm_rad = o.rest_spin_radps * o.hold_s;
  bool calm = o.calm_hold;
  std::optional<FailureEvent> moved;
  int step = 0;
  BeltWatch belt;
  while (step < max_steps && !settled && !moved && !error) {
    error = guarded([&] {
      for (int k = 0; k < check_every && !error; ++k) {
        pb::step(m, d);
        error = belt.check(std::hypot(d->qvel[l.belt_x_dof], d->qvel[l.belt_y_dof]));
      }
    });
    step += check_every;
    if (!error && is_cancelled(o.cancel)) error = std::string(kCancelledReason);
    if (!error) error = instability_reason(m, d);
    if (error) {
      *error += " (by t = " + fixed(step * m->opt.timestep, 3) + " s)";
      break;
    }
    read_item_poses(l, *d, items);
    // The belt is held still: its travel is the pallet's slip.
    const Trace::BeltState still{d->qpos[l.belt_x_qpos], d->qpos[l.belt_y_qpos], 0.0, 0.0};
    moved = detector.update(d->time, still, body_pose(*d, l.pallet_body), items);
    speed = max_relative_speed(l, *d, 0.0, 0.0, &spin);
    const bool at_rest =
        d->time >= o.min_time_s && speed < o.rest_speed_mps && spin < o.rest_spin_radps;
    if (!at_rest) {
      quiet_since = -1;
    } else if (quiet_since < 0) {
      quiet_since = step;
      if (first_step < 0) {
        first = capture(*m, *d, l, speed);
        first_step = step;
      }
    }
    if (calm && first_step >= 0) {
      const Drift drift = drift_from_first();
      calm = drift.m <= calm_m && drift.rad <= calm_rad;
    }
    settled = !moved && ((quiet_since >= 0 && step - quiet_since >= hold_steps) ||
                         (calm && at_rest && step - first_step >= hold_steps));
  }
  if (error) {
    reset_data(m, d);
    if (is_cancelled(o.cancel))
      return Result<RestState>::failure("", std::string(kCancelledReason));
    return Result<RestState>::failure(
        "", "the load could not be settled on a still belt: " + *error +
                "; the layout or the numerical settings are at fault, not the conveyor");
  }
  read_item_poses(l, *d, items);
  // Never quiet for the whole hold, but nothing crossed a detector: contact chatter keeps a
  // speed above the rest threshold now and then while nothing goes anywhere. A load whose items
  // have all stayed within a quarter of the load-shift threshold of where it first came to rest
  // stands; one that has crept further does not.
  if (!settled && !moved && first_step >= 0) {
    settled = drift_from_first().m < 0.25 * thresholds.load_shift_m;
  }
  if (settled) {
    first.settle_run_s = d->time;
    return Result<RestState>{std::move(first), {}};
  }
  RestState rest = capture(*m, *d, l, speed);
  rest.settle_run_s = d->time;
  rest.cannot_stand = stand_failure(*scene_, *d, thresholds, pallet0, items0, items, moved);
  return Result<RestState>{std::move(rest), {}};
}

SimResult Simulator::run(const RestState& rest, const ConveyorProfile& profile,
                         const SimOptions& o) {
  const auto wall_start = std::chrono::steady_clock::now();
  const mjModel* m = scene_->model.get();
  mjData* d = data_.get();
  ProbeRun probe(*scene_, rest, profile, o);
  load_rest_state(scene_->layout, rest, probe.initial_speed(), *d);
  if (probe.done()) {
    if (probe.result().outcome == Outcome::unstable) return probe.take_result();
    probe.finish(*m, *d);  // nothing to step
  }
  while (!probe.done()) {
    probe.before_step(*d);
    if (auto error = guarded([&] { pb::step(m, d); })) {
      probe.engine_error(*error);
      reset_data(m, d);
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
