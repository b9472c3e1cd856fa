// SPDX-License-Identifier: MIT
#include "core/physics/probe_run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/base/text.hpp"
#include "core/physics/engine.hpp"
#include "core/physics/quasi_static.hpp"
#include "core/physics/step.hpp"

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

// The largest linear magnitude of `v` (qvel or qacc) at the pallet's or an item's free joint
// relative to the belt's (bx, by), and (in `spin`) the largest angular one.
double max_relative(const SceneLayout& l, const mjtNum* v, double bx, double by, double* spin) {
  double fastest = 0.0, fastest_spin = 0.0;
  auto visit = [&](int dof) {
    const mjtNum rel[3] = {v[dof] - bx, v[dof + 1] - by, v[dof + 2]};
    fastest = std::max(fastest, norm3(rel));
    fastest_spin = std::max(fastest_spin, norm3(v + dof + 3));
  };
  visit(l.pallet_dof);
  for (int dof : l.item_dofs) visit(dof);
  if (spin != nullptr) *spin = fastest_spin;
  return fastest;
}

}  // namespace

double max_relative_accel(const SceneLayout& l, const mjData& d, double* spin) {
  return max_relative(l, d.qacc, d.qacc[l.belt_x_dof], d.qacc[l.belt_y_dof], spin);
}

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
  return max_relative(l, d.qvel, belt_vx, belt_vy, spin);
}

SimState start_state(const SceneLayout& l, const RestState& rest, double initial_speed) {
  SimState s = rest.state;
  if (initial_speed != 0.0) {
    for (int dof : {l.belt_x_dof, l.pallet_dof}) s.qvel[std::size_t(dof)] += initial_speed;
    for (int dof : l.item_dofs) s.qvel[std::size_t(dof)] += initial_speed;
    s.ctrl[std::size_t(l.belt_x_act)] = initial_speed;
  }
  return s;
}

void load_rest_state(const SceneLayout& l, const RestState& rest, double initial_speed, mjData& d) {
  restore_state(start_state(l, rest, initial_speed), d);
}

ProbeRun::ProbeRun(const Scene& scene, const RestState& rest, const ConveyorProfile& profile,
                   const SimOptions& options)
    : scene_(&scene),
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
  // Deciding early (co-moving, or below every barrier) rests on the belt's frame being inertial
  // after the last breakpoint. A run that ends with the belt still changing speed (its profile's
  // motion goes on past duration_s) has no such phase: it is stepped to its end.
  const double after = last_breakpoint_ + dt_, end = profile_.duration_s;
  steady_after_last_ = profile_.velocity_at(after) == profile_.velocity_at(end) &&
                       profile_.lateral_velocity_at(after) == profile_.lateral_velocity_at(end);
  stops_early_ = o_.early_stop && steady_after_last_;
  if (profile_.shape == ProfileShape::curve) turning_.emplace(*m, l);
  belt_x0_ = rest.state.qpos[static_cast<std::size_t>(l.belt_x_qpos)];
  belt_y0_ = rest.state.qpos[static_cast<std::size_t>(l.belt_y_qpos)];
  if (auto problem = numerical_limits_problem(scene)) {
    r_.outcome = Outcome::unstable;
    r_.reason = *problem;
    done_ = true;
    return;
  }
  if (rest.cannot_stand) {  // a collapsed load is no rest state: nothing to probe
    r_.outcome = Outcome::unstable;
    r_.reason = "no conveyor motion is simulated: " + rest.cannot_stand->sentence;
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
  calm_needed_ = std::max(1, static_cast<int>(std::lround(0.01 / dt_)));
  breakpoints_ = breakpoints;
  dwell_needed_ = std::max(1, static_cast<int>(std::lround(o_.skip_dwell_s / dt_)));
  creep_needed_ = std::max(1, static_cast<int>(std::lround(kSteadyCreepWindowS / dt_)));
  project_needed_ = std::max(2, static_cast<int>(std::lround(kProjectWindowS / dt_)));
  if (n_steps_ <= 0) done_ = true;  // finish() gives the final check
}

void ProbeRun::before_step(mjData& d) {
  const SceneLayout& l = scene_->layout;
  if (skip_n_ > 0) {  // the jump after_step planned: the belt's rigid motion (and the creep's)
    const double span = skip_n_ * dt_;
    const std::array<double, 2> travel = jump_travel(skip_n_, 0);  // captured: no binding
    auto move = [&](int qpos, int dof, std::size_t body) {
      d.qpos[qpos] += travel[0];
      d.qpos[qpos + 1] += travel[1];
      d.qvel[dof] += skip_dvx_;
      d.qvel[dof + 1] += skip_dvy_;
      if (skip_creep_) {
        const double* v = creep_v_.data() + 6 * body;
        for (int c = 0; c < 3; ++c) d.qpos[qpos + c] += v[c] * span;
        mju_quatIntegrate(d.qpos + qpos + 3, v + 3, span);
      }
    };
    d.qpos[l.belt_x_qpos] += travel[0];
    d.qpos[l.belt_y_qpos] += travel[1];
    d.qvel[l.belt_x_dof] += skip_dvx_;
    d.qvel[l.belt_y_dof] += skip_dvy_;
    move(l.pallet_qpos, l.pallet_dof, 0);
    for (std::size_t i = 0; i < l.item_qpos.size(); ++i)
      move(l.item_qpos[i], l.item_dofs[i], i + 1);
    d.time += skip_n_ * dt_;
    skip_n_ = 0;
  }
  if (o_.extrapolate_warmstart && qacc_known_ >= 2) {
    for (std::size_t i = 0; i < qacc1_.size(); ++i)
      d.qacc_warmstart[i] = 2.0 * qacc1_[i] - qacc2_[i];
  }
  const double t_next = (k_ + 1) * dt_;
  // A velocity actuator with kv = M/dt reaches its command in one step: command the velocity
  // the belt should have at the end of this step.
  d.ctrl[l.belt_x_act] = profile_.velocity_at(t_next);
  d.ctrl[l.belt_y_act] = profile_.lateral_velocity_at(t_next);
  command_x_ = d.ctrl[l.belt_x_act];
  command_y_ = d.ctrl[l.belt_y_act];
  if (turning_) {
    const double omega = profile_.yaw_rate_at(k_ * dt_);
    // The first step's positions are the rest state's (restored, not yet computed).
    if (omega != 0.0 && k_ == 0) mj_kinematics(scene_->model.get(), &d);
    double axis[2];
    turning_axis(d, axis);
    const double belt_v[2] = {d.qvel[l.belt_x_dof], d.qvel[l.belt_y_dof]};
    const double belt_a[2] = {(command_x_ - profile_.velocity_at(k_ * dt_)) / dt_,
                              (command_y_ - profile_.lateral_velocity_at(k_ * dt_)) / dt_};
    turning_->apply(*scene_->model, d, omega, axis, belt_v, belt_a);
  }
}

int ProbeRun::plan_skip() const {
  int last = n_steps_ - 1;  // the last step is always stepped
  if (phase_ < breakpoints_.size()) {
    // The step ending at or before the breakpoint is the phase's last: step it, and the one
    // crossing the breakpoint.
    last = std::min(last, static_cast<int>(std::floor(breakpoints_[phase_] / dt_ + 1e-9)) - 1);
  } else if (stops_early_) {
    return 0;  // after the last breakpoint the early stop decides
  }
  const int n = last - k_;
  // A jump shorter than the dwell saves less than it cost, and near the phase's end it perturbs
  // a marginal load for nothing (a 3-step jump flipped a top-heavy load's e-stop verdict).
  if (n < std::max(2, dwell_needed_)) return 0;
  // The command must be affine in time over the whole jump (the step after it included): an
  // EUMOS rise is a phase, but its velocity is quadratic.
  return command_affine(n) ? n : 0;
}

bool ProbeRun::command_affine(int n) const {
  if (n <= 0) return false;
  auto affine = [&](auto&& v) {
    const double v0 = v(k_ * dt_), v1 = v((k_ + n) * dt_);
    for (int j : {n / 4, n / 2, (3 * n) / 4, n + 1}) {
      const double expected = v0 + (v1 - v0) * j / n;
      if (std::abs(v((k_ + j) * dt_) - expected) > 1e-7 * (1.0 + std::abs(expected))) return false;
    }
    return true;
  };
  return affine([&](double t) { return profile_.velocity_at(t); }) &&
         affine([&](double t) { return profile_.lateral_velocity_at(t); });
}

std::optional<double> ProbeRun::slip_certain(const mjModel& m, const mjData& d, double t,
                                             double slip) {
  auto not_now = [&]() -> std::optional<double> {
    slip_window_.clear();
    return std::nullopt;
  };
  // Only the belt's pair slides: the load rides its pallet, which friction alone pulls along.
  if (phase_ >= breakpoints_.size() || !only_pair_sliding(&m, &d, kBeltPalletPair)) {
    return not_now();
  }
  // The demand holds to the phase's end: the belt's frame accelerates (and turns) at a constant
  // rate (checked once a phase, from a step in it to its end).
  const double t_end = breakpoints_[phase_];
  if (affine_phase_ != int(phase_)) {
    const int last = static_cast<int>(std::floor(t_end / dt_ + 1e-9)) - 1;
    if (!command_affine(last - k_)) return not_now();
    affine_phase_ = int(phase_);
  }
  // The demand at the load's centre of mass (pallet and items): opposite to the belt's
  // acceleration, and a curve's turning outwards from its axis (turning_frame.hpp), which carries
  // the whole load's mass at its centre.
  const LoadMoments load = load_moments(m, d);
  if (!(load.mass > 0.0)) return not_now();
  double field[2] = {
      -(profile_.velocity_at(t) - profile_.velocity_at(t - dt_)) / dt_,
      -(profile_.lateral_velocity_at(t) - profile_.lateral_velocity_at(t - dt_)) / dt_};
  if (turning_) {
    const double omega = profile_.yaw_rate_at(t - dt_);
    double axis[2];
    turning_axis(d, axis);
    for (int c = 0; c < 2; ++c) field[c] += omega * omega * (load.moment[c] / load.mass - axis[c]);
  }
  const FrictionValue& pair = scene_->friction.belt_pallet;
  const double friction = kProjectFrictionMargin * std::min(pair.mu_s, pair.mu_d) * kGravity;
  const double excess = std::hypot(field[0], field[1]) - friction;
  if (!(excess > 0.0)) return not_now();
  // The slip has sped up over the window.
  slip_window_.push_back(slip);
  const auto n = static_cast<std::size_t>(project_needed_);
  if (slip_window_.size() > n + 1) slip_window_.erase(slip_window_.begin());
  if (slip_window_.size() <= n) return std::nullopt;
  const std::size_t half = n / 2;
  const double early = (slip_window_[half] - slip_window_[0]) / (double(half) * dt_);
  const double late = (slip_window_[n] - slip_window_[n - half]) / (double(half) * dt_);
  if (!(early > 0.0 && late >= early)) return std::nullopt;
  // At no more than `friction` against `excess` to the phase's end, then (on a steady belt) no
  // more than `friction` against nothing while it coasts.
  const double left = o_.thresholds.pallet_slip_m - slip;
  const double tau = std::max(0.0, t_end - t);
  const double reach = late * tau + 0.5 * excess * tau * tau;
  if (reach >= left) {  // within the phase
    return t + (std::sqrt(late * late + 2.0 * excess * left) - late) / excess;
  }
  const double v_end = late + excess * tau;
  const double coast = left - reach;
  if (!(steady_after_last_ && t_end >= last_breakpoint_) ||
      v_end * v_end < 2.0 * friction * coast) {
    return std::nullopt;
  }
  return t_end + (v_end - std::sqrt(v_end * v_end - 2.0 * friction * coast)) / friction;
}

bool ProbeRun::creeping_steadily(const mjModel& m, const mjData& d, double belt_vx,
                                 double belt_vy) {
  const SceneLayout& l = scene_->layout;
  const std::size_t bodies = 1 + l.item_dofs.size();
  creep_v_.resize(6 * bodies);
  creep_v0_.resize(6 * bodies);
  creep_sums_.resize(12 * bodies);
  if (any_pair_sliding(&m, &d)) {
    creep_steps_ = 0;
    return false;
  }
  // A window that ended without a jump (none planned from there) is not extended: a new one starts.
  const int half = std::max(1, creep_needed_ / 2);
  bool within = creep_steps_ > 0 && creep_steps_ < 2 * half;
  for (std::size_t b = 0; b < bodies; ++b) {
    // The body's velocity relative to the belt: linear (world frame), angular (its own frame).
    const int dof = b == 0 ? l.pallet_dof : l.item_dofs[b - 1];
    double* v = creep_v_.data() + 6 * b;
    v[0] = d.qvel[dof] - belt_vx;
    v[1] = d.qvel[dof + 1] - belt_vy;
    for (int c = 2; c < 6; ++c) v[c] = d.qvel[dof + c];
    if (norm3(v) >= kSteadyCreepMps || norm3(v + 3) >= o_.comove_spin_radps) {
      creep_steps_ = 0;
      return false;
    }
    const double* v0 = creep_v0_.data() + 6 * b;
    const double dv[6] = {v[0] - v0[0], v[1] - v0[1], v[2] - v0[2],
                          v[3] - v0[3], v[4] - v0[4], v[5] - v0[5]};
    within = within && norm3(dv) <= kSteadyCreepTolMps && norm3(dv + 3) <= kSteadyCreepTolRadps;
  }
  if (!within) {  // a window starts with this step
    creep_v0_ = creep_v_;
    std::fill(creep_sums_.begin(), creep_sums_.end(), 0.0);
    creep_steps_ = 0;
    creep_cone_use_ = 0.0;
  }
  creep_cone_use_ = std::max(creep_cone_use_, max_cone_use(&m, &d));
  // The window's velocities summed by half: the first half's sums, then the second's.
  const std::size_t second = creep_steps_ < half ? 0 : 6;
  for (std::size_t b = 0; b < bodies; ++b) {
    for (std::size_t c = 0; c < 6; ++c) creep_sums_[12 * b + second + c] += creep_v_[6 * b + c];
  }
  return ++creep_steps_ == 2 * half;
}

double ProbeRun::creep_span_s() {
  // Each half's mean velocity; the change between them, over the half's length, is the window's
  // drift. The jump carries the second half's mean.
  const int half = std::max(1, creep_needed_ / 2);
  const double lag = half * dt_;
  double span = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; 12 * b < creep_sums_.size(); ++b) {
    double drift[6];
    for (std::size_t c = 0; c < 6; ++c) {
      const double first = creep_sums_[12 * b + c] / half,
                   last = creep_sums_[12 * b + 6 + c] / half;
      creep_v_[6 * b + c] = last;
      drift[c] = (last - first) / lag;
    }
    // The jump carries the velocity unchanged: the drift would add 0.5 |drift| span^2.
    if (const double linear = norm3(drift); linear > 0.0) {
      span = std::min(span, std::sqrt(2.0 * kCreepDriftM / linear));
    }
    if (const double angular = norm3(drift + 3); angular > 0.0) {
      span = std::min(span, std::sqrt(2.0 * kCreepDriftRad / angular));
    }
  }
  return span;
}

double ProbeRun::creep_reach(double span) const {
  // How far the creep can take each detector's reading over `span`: an item against another by
  // the spread of the items' velocities, against the pallet by the largest difference from the
  // pallet's, the pallet against the belt by its own, a tilt by the fastest spin.
  const std::size_t bodies = creep_v_.size() / 6;
  const double* pallet = creep_v_.data();
  double lo[2] = {0.0, 0.0}, hi[2] = {0.0, 0.0}, item = 0.0, spin = norm3(pallet + 3);
  for (std::size_t b = 1; b < bodies; ++b) {
    const double* v = creep_v_.data() + 6 * b;
    for (int c = 0; c < 2; ++c) {
      lo[c] = b == 1 ? v[c] : std::min(lo[c], v[c]);
      hi[c] = b == 1 ? v[c] : std::max(hi[c], v[c]);
    }
    item = std::max(item, std::hypot(v[0] - pallet[0], v[1] - pallet[1]));
    spin = std::max(spin, norm3(v + 3));
  }
  const DetectorThresholds& t = o_.thresholds;
  return span * std::max({std::hypot(hi[0] - lo[0], hi[1] - lo[1]) / t.load_shift_m,
                          item / t.item_slide_m, std::hypot(pallet[0], pallet[1]) / t.pallet_slip_m,
                          spin * 180.0 / std::numbers::pi / t.tip_deg});
}

std::array<double, 2> ProbeRun::jump_travel(int j, int lag) const {
  // Semi-implicit Euler moves the belt by dt v(t0 + i dt) in its i-th step, the command affine
  // in time: j dt v0 + dv/n dt j (j + 1) / 2 over the first j of n steps. A pose read `lag` steps
  // behind moved by j dt v0 + dv/n dt j (j + 1 - 2 lag) / 2 (the steps before it, dt v0 each).
  const double ramp = 0.5 * (j + 1 - 2 * lag) * dt_ * (double(j) / double(skip_n_));
  return {j * dt_ * skip_v0x_ + skip_dvx_ * ramp, j * dt_ * skip_v0y_ + skip_dvy_ * ramp};
}

Trace::BeltState ProbeRun::jumped(const Trace::BeltState& belt, int j) const {
  const auto [dx, dy] = jump_travel(j, 0);
  const double share = double(j) / double(skip_n_);
  return {belt.x + dx, belt.y + dy, belt.vx + skip_dvx_ * share, belt.vy + skip_dvy_ * share};
}

void ProbeRun::shift(Pose& p, std::size_t body, int j) const {
  // The poses read after a step are where the step started (mj_step's kinematics come before its
  // integration; the belt is read from qpos, where it ended), so a body's pose lags the belt by a
  // step. Moved by the belt's own j steps, the load lagged its belt by dt v0 over the whole jump
  // and by dt v1 in the step after it: a ramp's jump put a step of dt (v1 - v0) into the trace's
  // slip and its pallet velocity.
  const auto [dx, dy] = jump_travel(j, 1);
  p.pos[0] += dx;
  p.pos[1] += dy;
  if (!skip_creep_) return;
  const double span = j * dt_;
  const double* v = creep_v_.data() + 6 * body;
  for (std::size_t c = 0; c < 3; ++c) p.pos[c] += v[c] * span;
  mju_quatIntegrate(p.quat.data(), v + 3, span);
}

// The share of the barrier the load's energy must stay below: the barriers are first-order in the
// distance (a rocking item's centre of mass rises by (b/2)/h per metre only while the angle is
// small) and friction dissipates at mu N only while N is the item's weight.
constexpr double kBarrierShare = 0.5;
/// The aftermath of a failure lasts at least this long before a load moving with the belt ends it.
constexpr double kMinAftermathS = 0.25;

ProbeRun::LoadMoments ProbeRun::load_moments(const mjModel& m, const mjData& d) const {
  LoadMoments out;
  for (int b = 1; b < m.nbody; ++b) {
    if (b == scene_->layout.belt_body) continue;
    out.mass += m.body_mass[b];
    for (int c = 0; c < 3; ++c) out.moment[c] += m.body_mass[b] * d.xipos[3 * b + c];
  }
  return out;
}

void ProbeRun::turning_axis(const mjData& d, double axis[2]) const {
  const mjtNum* belt = d.xpos + 3 * scene_->layout.belt_body;
  axis[0] = belt[0] - belt_x0_;
  axis[1] = belt[1] - belt_y0_;
}

double ProbeRun::potential_energy(const mjModel& m, const mjData& d) const {
  return load_moments(m, d).moment[2] * kGravity;
}

bool ProbeRun::below_barrier(const mjModel& m, const mjData& d, const Trace::BeltState& belt,
                             const DetectorReadings& r) {
  const RestBarriers& b = scene_->barriers;
  const DetectorThresholds& t = o_.thresholds;
  const double s_item = std::min(t.item_slide_m - r.item_slide_m,
                                 0.5 * (t.load_shift_m - r.load_shift_m));  // both items move
  const double s_slip = t.pallet_slip_m - r.pallet_slip_m;
  const double s_tilt = (t.tip_deg - r.tilt_deg) * std::numbers::pi / 180.0;
  if (!(s_item > 0.0 && s_slip > 0.0 && s_tilt > 0.0)) return false;
  const double barrier = std::min(
      {b.item_force_n * s_item, b.pallet_slip_force_n * s_slip, b.tilt_moment_nm * s_tilt});
  const SceneLayout& l = scene_->layout;
  vrel_.assign(d.qvel, d.qvel + m.nv);
  vrel_[std::size_t(l.belt_x_dof)] = 0.0;
  vrel_[std::size_t(l.belt_y_dof)] = 0.0;
  auto relative = [&](int dof) {
    vrel_[std::size_t(dof)] -= belt.vx;
    vrel_[std::size_t(dof) + 1] -= belt.vy;
  };
  relative(l.pallet_dof);
  for (int dof : l.item_dofs) relative(dof);
  mv_.resize(vrel_.size());
  mj_mulM(&m, &d, mv_.data(), vrel_.data());
  double kinetic = 0.0;
  for (std::size_t i = 0; i < vrel_.size(); ++i) kinetic += 0.5 * vrel_[i] * mv_[i];
  return kinetic + potential_energy(m, d) - pe0_ < kBarrierShare * barrier;
}

void ProbeRun::unstable(const std::string& reason) {
  r_.outcome = Outcome::unstable;
  r_.reason = reason;
  r_.failure.reset();
  done_ = true;
}

void ProbeRun::engine_error(const std::string& reason) {
  const std::string why = reason + " (at t = " + fixed((k_ + 1) * dt_, 3) + " s)";
  if (r_.failure) {  // the verdict came first: only the aftermath is cut short
    r_.aftermath_cut = why;
    done_ = true;
    return;
  }
  unstable(why);
}

void ProbeRun::finish(const mjModel& m, const mjData& d) {
  done_ = true;
  if (r_.outcome == Outcome::unstable) {
    r_.failure.reset();
    return;
  }
  if (auto reason = instability_reason(&m, &d)) {
    const std::string why = *reason + " (by t = " + fixed(r_.sim_time_s, 3) + " s)";
    if (r_.failure) {
      r_.aftermath_cut = why;
    } else {
      unstable(why);
    }
  }
}

std::optional<FailureEvent> ProbeRun::detect(double t, const Trace::BeltState& belt,
                                             const Pose& pallet, DetectorReadings& readings) {
  auto event = detector_.update(t, belt, pallet, items_, &readings);
  const DetectorThresholds& th = detector_.thresholds();
  r_.load_peak_ratio =
      std::max({r_.load_peak_ratio, readings.tilt_deg / th.tip_deg,
                readings.item_slide_m / th.item_slide_m, readings.load_shift_m / th.load_shift_m});
  r_.peak_ratio =
      std::max({r_.peak_ratio, r_.load_peak_ratio, readings.pallet_slip_m / th.pallet_slip_m});
  if (event) {
    r_.peak_ratio = std::max(r_.peak_ratio, 1.0);
    if (event->mode != FailureMode::pallet_slip) {
      r_.load_peak_ratio = std::max(r_.load_peak_ratio, 1.0);
    }
  }
  return event;
}

bool ProbeRun::after_step(const mjModel& m, const mjData& d) {
  const SceneLayout& l = scene_->layout;
  const int k = ++k_;
  const double t_next = k * dt_;
  r_.steps = k;
  if (o_.extrapolate_warmstart) {
    qacc2_.swap(qacc1_);
    qacc1_.assign(d.qacc, d.qacc + m.nv);
    qacc_known_ = std::min(qacc_known_ + 1, 2);
  }
  r_.sim_time_s = t_next;
  std::optional<std::string> broken;
  if (is_cancelled(o_.cancel) || is_cancelled(o_.abandon)) broken = std::string(kCancelledReason);
  if (!broken && any_warning(d)) {
    broken = instability_reason(&m, &d).value_or("MuJoCo raised a warning");
  }
  if (!broken) {
    broken = belt_watch_.check(
        std::hypot(d.qvel[l.belt_x_dof] - command_x_, d.qvel[l.belt_y_dof] - command_y_));
  }
  if (!broken && d.xpos[3 * l.pallet_body + 2] < fall_through_z_) {
    broken = std::string("the pallet sank through the belt: contacts could not hold it");
  }
  if (broken) {
    const std::string why = *broken + " (at t = " + fixed(t_next, 3) + " s)";
    if (r_.failure && !is_cancelled(o_.cancel)) {  // after the verdict: the aftermath ends here
      r_.aftermath_cut = why;
      done_ = true;
    } else {
      unstable(why);
    }
    return false;
  }
  const Trace::BeltState belt{d.qpos[l.belt_x_qpos] - belt_x0_, d.qpos[l.belt_y_qpos] - belt_y0_,
                              d.qvel[l.belt_x_dof], d.qvel[l.belt_y_dof]};
  const Pose pallet = body_pose(d, l.pallet_body);
  read_item_poses(l, d, items_);
  if (o_.record_trace) r_.trace.push(t_next, belt, pallet, items_);
  if (k == 1) pe0_ = potential_energy(m, d);
  // The profile's phase this step ends in (skipping stays within one; the early stop comes after
  // the last breakpoint).
  std::size_t phase = 0;
  while (phase < breakpoints_.size() && breakpoints_[phase] < t_next - 1e-9) ++phase;
  if (phase != phase_) dwell_steps_ = creep_steps_ = 0;
  phase_ = phase;
  DetectorReadings readings;
  if (!r_.failure) {
    if (auto event = detect(t_next, belt, pallet, readings)) {
      r_.failure = std::move(event);
      r_.outcome = Outcome::failed;
      if (o_.fail_fast) {
        finish(m, d);
        return false;
      }
    } else if (const auto crossing = o_.fail_fast && o_.project_pallet_slip
                                         ? slip_certain(m, d, t_next, readings.pallet_slip_m)
                                         : std::nullopt) {
      r_.failure = FailureEvent{.mode = FailureMode::pallet_slip,
                                .time_s = *crossing,
                                .value = o_.thresholds.pallet_slip_m,
                                .items = {},
                                .item_tilt_deg = 0.0,
                                .least_item_move_m = 0.0,
                                .projected = true};
      r_.outcome = Outcome::failed;
      r_.peak_ratio = std::max(r_.peak_ratio, 1.0);
      finish(m, d);
      return false;
    }
  }
  const bool want_stop = stops_early_ && !r_.failure && t_next >= last_breakpoint_;
  const bool want_skip = o_.skip_comoving && !r_.failure && k < n_steps_;
  bool comoving = false;
  if (want_stop || want_skip) {
    double spin = 0.0;
    const double speed = max_relative_speed(l, d, belt.vx, belt.vy, &spin);
    comoving = speed < o_.comove_speed_mps && spin < o_.comove_spin_radps;
  }
  // Skipping also needs the load steady, not at the turning point of a slow rock (velocities
  // matching the belt's for an instant while the accelerations do not).
  bool steady = false;
  if (want_skip && comoving) {
    double spin_accel = 0.0;
    const double accel = max_relative_accel(l, d, &spin_accel);
    steady = accel < o_.comove_speed_mps / o_.skip_dwell_s &&
             spin_accel < o_.comove_spin_radps / o_.skip_dwell_s;
  }
  dwell_steps_ = steady ? dwell_steps_ + 1 : 0;
  const bool comoved = dwell_steps_ >= dwell_needed_;
  // After the last breakpoint of a run that stops early no jump is planned: no window is kept.
  const bool can_jump = phase_ < breakpoints_.size() || !stops_early_;
  const bool creeping = want_skip && o_.skip_creeping && !comoved && can_jump &&
                        creeping_steadily(m, d, belt.vx, belt.vy);
  if (want_stop) {
    comove_steps_ = comoving ? comove_steps_ + 1 : 0;
    calm_steps_ =
        o_.energy_stop && !comoving && below_barrier(m, d, belt, readings) ? calm_steps_ + 1 : 0;
    if (comove_steps_ >= comove_needed_ || calm_steps_ >= calm_needed_) {
      r_.stopped_early = k < n_steps_;
      finish(m, d);
      return false;
    }
  }
  if (want_skip && (comoved || creeping)) {
    int n = plan_skip();
    // A creeping load jumps only where its creep cannot take it near a threshold meanwhile.
    skip_creep_ = !comoved;
    if (skip_creep_ && n > 0) {
      // Cut where the window's drift would move a body too far, if a cut may be taken there
      // (kCutJumpSettleS).
      const int cut = static_cast<int>(std::min<double>(n, std::floor(creep_span_s() / dt_)));
      const double in_phase = k * dt_ - (phase_ == 0 ? 0.0 : breakpoints_[phase_ - 1]);
      const bool may_cut =
          in_phase >= kCutJumpSettleS && cut >= creep_needed_ && creep_cone_use_ < kCutJumpConeUse;
      if (cut < n) n = may_cut ? cut : 0;
      const double span = n * dt_;
      if (n == 0 || r_.peak_ratio + creep_reach(span) >= kCreepJumpMaxRatio) {
        n = 0;
        creep_steps_ = 0;  // a new window, from the next step
      }
    }
    if (n > 0) {
      const double t0 = k * dt_, t1 = (k + n) * dt_;
      const double v0x = profile_.velocity_at(t0), v1x = profile_.velocity_at(t1);
      const double v0y = profile_.lateral_velocity_at(t0), v1y = profile_.lateral_velocity_at(t1);
      skip_dvx_ = v1x - v0x;
      skip_dvy_ = v1y - v0y;
      skip_v0x_ = v0x;
      skip_v0y_ = v0y;
      skip_n_ = n;
      k_ = k + n;
      r_.steps = k_;
      r_.sim_time_s = t1;
      r_.steps_skipped += n;
      r_.jumps.push_back({k, n});
      r_.skipped_s += n * dt_;
      // The trace gets every skipped step's frame, as stepping would have recorded it: what reads
      // it interpolates between frames (replays, the reference API's trace), and across one
      // frame at the jump's end it drew the belt's ramp as a straight line and the pallet
      // outrunning its belt.
      for (int j = 1; o_.record_trace && j < n; ++j) {
        Pose pallet_j = pallet;
        shift(pallet_j, 0, j);
        jumped_items_ = items_;
        for (std::size_t i = 0; i < items_.size(); ++i) shift(jumped_items_[i], i + 1, j);
        r_.trace.push((k + j) * dt_, jumped(belt, j), pallet_j, jumped_items_);
      }
      // The jump's endpoint, as the detectors and the trace see it (the measures are invariant
      // under the belt's rigid motion: the detector is run for consistency, not for news).
      Pose pallet1 = pallet;
      shift(pallet1, 0, n);
      for (std::size_t i = 0; i < items_.size(); ++i) shift(items_[i], i + 1, n);
      creep_steps_ = 0;
      const Trace::BeltState belt1 = jumped(belt, n);
      if (o_.record_trace) r_.trace.push(t1, belt1, pallet1, items_);
      DetectorReadings at_end;
      if (auto event = detect(t1, belt1, pallet1, at_end)) {
        r_.failure = std::move(event);
        r_.outcome = Outcome::failed;
        if (o_.fail_fast) {
          finish(m, d);
          return false;
        }
      }
    }
  }
  if (r_.failure && o_.follow_failure_s > 0.0) {
    // The aftermath: until the load moves with the belt again or the time is up, past the
    // profile's end if need be (the belt keeps its last command).
    double spin = 0.0;
    const bool with_belt =
        max_relative_speed(l, d, belt.vx, belt.vy, &spin) < o_.comove_speed_mps &&
        spin < o_.comove_spin_radps;
    settled_after_failure_ = with_belt ? settled_after_failure_ + 1 : 0;
    const double since = t_next - r_.failure->time_s;
    if (since >= o_.follow_failure_s ||
        (since >= kMinAftermathS && settled_after_failure_ >= comove_needed_)) {
      finish(m, d);
      return false;
    }
    return true;
  }
  if (k_ >= n_steps_) {
    finish(m, d);
    return false;
  }
  return true;
}

}  // namespace pb
