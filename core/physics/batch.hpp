// SPDX-License-Identifier: MIT
// Many simulations of one compiled model stepped in parallel (mjbatch's design, for MuJoCo 2.2.2):
// memory follows threads, not simulations. Each simulation stores only its state; each worker
// thread owns one mjData into which it loads, steps and stores the simulations of its slice.
// Stepping through the batch is bitwise equal to a serial pb::step loop (step.hpp), at every thread
// count.
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/physics/sim_state.hpp"

namespace pb {

/// The per-simulation arrays of a state, for views across the batch.
enum class StateField {
  time,
  qpos,
  qvel,
  act,
  qacc_warmstart,
  ctrl,
  qfrc_applied,
  xfrc_applied,
  mocap_pos,
  mocap_quat,
  userdata
};

/// A live, strided view of one field across all simulations: row `sim` holds `width` values.
/// Writes land in the batch (they take effect at the next call); never use a view while a call
/// runs on another thread, nor after the batch is gone.
struct BatchView {
  double* data = nullptr;
  int width = 0;
  std::ptrdiff_t stride = 0;
  int sims = 0;

  std::span<double> row(int sim) const { return {data + sim * stride, std::size_t(width)}; }
  double& operator()(int sim, int k) const { return data[sim * stride + k]; }
};

/// Which simulations a call touches: all (the default), sorted unique ids, or a mask with one
/// flag per simulation.
struct Selection {
  static Selection of_ids(std::vector<int> ids) { return {std::move(ids), std::nullopt}; }
  static Selection of_mask(std::vector<bool> mask) { return {std::nullopt, std::move(mask)}; }

  std::optional<std::vector<int>> ids;
  std::optional<std::vector<bool>> mask;
};

/// Per-step hooks, called on the worker thread that steps a simulation, concurrently for
/// different simulations: they must touch only `data` and state of their own simulation, and
/// must not throw (an exception fails that simulation).
struct StepHooks {
  /// Before every step: write the inputs of the step about to run (ctrl, qfrc_applied, ...).
  std::function<void(int sim, const mjModel& model, mjData& data)> control;
  /// After every step: return false to stop stepping this simulation for the rest of the call
  /// (its state after that step is kept).
  std::function<bool(int sim, const mjModel& model, const mjData& data)> observe;
  /// Before a simulation is loaded and stepped in a call: false skips it for that call (its state
  /// unchanged), e.g. once the work was cancelled. Absent: every selected simulation is stepped.
  std::function<bool(int sim)> wanted = nullptr;
};

/// Why a call did not complete for every simulation it touched.
struct BatchError {
  /// The lowest-index failing simulation, or -1 if the call itself was invalid (nothing ran).
  int sim = -1;
  std::vector<int> failed;  ///< every failing simulation, ascending
  std::string message;      ///< "simulation 3: <why>" (the lowest), or why the call is invalid
};

class Batch {
 public:
  /// Copies `model` (later changes to it do not reach the batch) and makes `sims` simulations at
  /// the model's reset state, stepped by `threads` workers (0: every logical CPU; at most
  /// `sims`). Fails on sims < 1, threads < 0, enabled sensor noise (MuJoCo draws it from a
  /// process-global generator, so results would depend on thread timing), or if MuJoCo cannot
  /// allocate.
  static Result<Batch> create(const mjModel& model, int sims, int threads = 0);

  Batch(Batch&&) noexcept;
  Batch& operator=(Batch&&) noexcept;
  ~Batch();

  int size() const;
  int threads() const;
  /// The batch's own copy of the model (expanded parameters are not in it).
  const mjModel& model() const;

  /// Runs `nstep` steps (pb::step, step.hpp) (nstep >= 0) on each selected simulation, with the
  /// hooks. A simulation whose step raises an engine error or becomes unstable (instability_reason)
  /// stops there and keeps its pre-call state; the others complete. Calls are serialised and
  /// block until done (the calling thread is one of the workers: never call from a GUI thread).
  std::optional<BatchError> step(const Selection& selection = {}, int nstep = 1,
                                 const StepHooks& hooks = {});

  /// Puts the selected simulations back at the reset state (see set_reset_state). Expanded
  /// parameters are configuration, not state, and stay.
  std::optional<BatchError> reset(const Selection& selection = {});

  /// The state of one simulation (0 <= sim < size()).
  SimState get_state(int sim) const;
  /// Sets the state of one simulation; fails if a field's size does not match the model.
  std::optional<BatchError> set_state(int sim, const SimState& state);

  /// The state reset() restores: the model's (mj_resetData, qpos0), unless set_reset_state set
  /// another (e.g. a settled rest state: start from reset_state() and fill qpos, qvel,
  /// qacc_warmstart).
  SimState reset_state() const;
  std::optional<BatchError> set_reset_state(const SimState& state);

  /// A live view of one state field across the batch.
  BatchView view(StateField field) const;

  /// Makes an mjtNum model field per simulation and returns its live (sims x size) view, seeded
  /// from the model: a pointer field by its mjModel name ("geom_friction", "pair_friction",
  /// "body_mass"; row = the whole array, e.g. 5 * npair values) or an option by "opt.<name>"
  /// ("opt.timestep", "opt.gravity"). Each simulation's row is written into its worker's model
  /// copy before it steps. Derived constants are not recomputed here, exactly as writing the
  /// field into a model copy in a serial loop: call set_const() after changing a field they
  /// depend on. Expanding a field again returns the same view. Fails on an unknown or non-mjtNum
  /// field.
  ///
  /// Derived constants matter for masses: MuJoCo 2.2 takes the inertia of a "simple" body (a free
  /// body with a diagonal inertia, e.g. every carton) from dof_M0, computed by mj_setConst, while
  /// gravity and contact loads use body_mass directly. A body whose body_mass (and body_inertia)
  /// changed without set_const() weighs the new mass but accelerates like the old one.
  Result<BatchView> expand(std::string_view field);

  /// Recomputes the derived constants (mj_setConst: dof_M0, body_subtreemass, the invweights,
  /// mjStatistic, ...) of the selected simulations from their expanded fields. Every derived
  /// mjtNum field that comes out different from the model's is expanded (for every simulation:
  /// the others get theirs computed too) and mjStatistic is kept per simulation, so each
  /// simulation then steps exactly like a model copy given the same fields and mj_setConst.
  /// Call it after writing body_mass, body_inertia, dof_armature, geom sizes and the like. An
  /// engine error names the lowest failing simulation; no constants change then.
  std::optional<BatchError> set_const(const Selection& selection = {});

 private:
  struct Impl;
  explicit Batch(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace pb
