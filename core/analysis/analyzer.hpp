// SPDX-License-Identifier: MIT
// The front door of the physics core: compile once, settle once, probe many — with compiled
// scenes, rest states and results cached by the fingerprint of the physically relevant fields.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/analysis/envelope.hpp"
#include "core/analysis/failure_map.hpp"
#include "core/analysis/fidelity.hpp"
#include "core/analysis/replay.hpp"
#include "core/analysis/uncertainty.hpp"
#include "core/inputs/friction.hpp"
#include "core/physics/quasi_static.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/simulate.hpp"
#include "core/physics/symmetry.hpp"

namespace pb {

struct AnalyzerOptions {
  SceneOptions scene;
  SettleOptions settle;
  SimOptions sim;
  LineDescription line;
  SearchConfig search;
  /// Which model answers (reported in SafetyResult::fidelity); automatic = the cheapest level
  /// whose agreement with the full model is established for pallets of that kind.
  Fidelity fidelity = Fidelity::automatic;
  /// The full model's own timestep (the numerics are part of a level): where the full model runs
  /// it steps at this, the reduced model at scene.timestep_s. 1.5 ms (1 ms until session 30):
  /// with Coulomb's circle and explicit kinetic friction it keeps the unwrapped corpus and the
  /// hold-out set within one search step of the reference configuration on 97 % of limits, none
  /// above, as 1 ms did, at 0.7 of its CPU; 2 ms puts one limit of the corpus more than a step
  /// below and agrees less on modes (core/README.md "Timestep of the full model"). nullopt:
  /// scene.timestep_s for every level (the study's fixed-timestep configurations, the reference).
  std::optional<double> full_model_timestep_s = 0.0015;
  /// The full model's contact time constant (solref[0], s; scene.contact_solref's damping ratio
  /// kept). 0.01 because with curves that turn the load (session 15) the shipped 0.02 let rows of
  /// a load pushed unequally part where the reference's stiff contacts (0.005) do not: on the
  /// unwrapped corpus 0.01 put no limit more than one step above the reference (0.02: one, +1.94)
  /// and none more than 1.7 steps below it (0.02: 4.1), 88 / 96 within one step against 89
  /// (core/README.md "Contact stiffness of the full model"). nullopt: scene.contact_solref for
  /// every level (the study's fixed configurations and the reference).
  std::optional<double> full_model_solref_s = 0.01;
  /// SafetyResult.confidence (uncertainty.hpp: limits_confidence): samples > 0 runs 4 x samples
  /// more simulations per envelope (5 x where the curve is checked in both turns: curve_turns);
  /// 0 (the default) leaves confidence null, not estimated.
  UncertaintyOptions confidence = {.samples = 0, .seed = 0, .threads = 0, .spread = {}};
  /// Where the automatic level is the full model, a load of identical stacks side by side across a
  /// probe's plane is searched on one copy of each (symmetry.hpp: reduce_symmetric_stacks), per
  /// plane; solves, maps and confidence still run every item. Off for an explicitly requested
  /// level and for the reference configurations.
  bool symmetry_reduction = true;
};

/// How long Analyzer::solve follows a failure at most (SimOptions::follow_failure_s).
inline constexpr double kSolveAftermathS = 3.0;

/// A symmetry-reduced model of a pallet for the probes of one plane, compiled and settled.
struct PlaneModel {
  LoadReduction reduction;
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Simulator> simulator;
  RestState rest;
};

/// A compiled, settled pallet: everything a probe needs.
struct PreparedPallet {
  std::string fingerprint;
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Simulator> simulator;
  RestState rest;
  QuasiStaticBounds bounds;
  FidelityChoice fidelity;  ///< the model level of `scene` (reduced or full), and why
  double prepare_ms = 0.0;  ///< compile + settle wall time
  /// The envelope searches' models along the belt and across it ([0], [1]) where the load reduces
  /// by symmetry (AnalyzerOptions::symmetry_reduction); null: the probes run on `scene`. Across
  /// the belt it never does any more: a curve turns the load (turning_frame.hpp), so copies side
  /// by side along the belt are not alike in a curve (Analyzer::prepare).
  std::array<std::unique_ptr<PlaneModel>, 2> planes;
  /// The same scene with whatever touches colliding (SceneOptions::aftermath), compiled the first
  /// time a solve fails, to follow the wreck; `aftermath_problem` says why there is none.
  std::unique_ptr<Scene> aftermath_scene;
  std::unique_ptr<Simulator> aftermath_simulator;
  std::string aftermath_problem;
};

/// One conveyor profile, simulated, with its replay.
struct Solve {
  SimResult sim;
  Replay replay;
};

/// Where a diagnostic about the line's curve radius points (AnalyzerOptions::line: not part of a
/// pallet; a client names its own setting, the CLI's and the service's --curve-radius).
inline constexpr const char* kLineRadiusPointer = "/line/curve_radius_m";

/// Not thread-safe: one Analyzer per thread (the console runs its own on a worker thread).
class Analyzer {
 public:
  explicit Analyzer(AnalyzerOptions options = {},
                    const FrictionModel& friction = FrictionModel::builtin());

  /// The compiled and settled pallet (cached). Fails for an invalid pallet, an engine error, or a
  /// load that will not come to rest (a build defect).
  Result<PreparedPallet*> prepare(const PalletConfig& config);

  /// What keeps a pallet that validate() accepts from being simulated here, found without
  /// compiling anything: a contact pair with no friction data, or a scene larger than the engine
  /// holds (capacity_problems) at the model level this analyzer would choose. Empty when it can be.
  Diagnostics simulation_problems(const PalletConfig& config) const;

  /// The line's curve radius against this pallet (validate_curve_radius at kLineRadiusPointer):
  /// what an envelope or a failure map refuses before it simulates.
  Diagnostics line_radius_problem(const PalletConfig& config) const;

  /// The full SafetyResult (cached: a second call costs about a millisecond and reports 0 sims).
  Result<SafetyResult> analyze(const PalletConfig& config);
  /// The envelope with its probes (not cached).
  Result<Envelope> envelope(const PalletConfig& config);
  /// The speed x start-up-acceleration failure map in one batched call (failure_map.hpp; not
  /// cached), with the analyzer's line, search and simulation options.
  Result<FailureMap> failure_map(const PalletConfig& config, const MapOptions& options = {});

  /// Runs one profile from rest with a full trace and a replay at `replay_hz`. The outcome and
  /// failure are the first detector crossing, on the model the searches use. A failed run is then
  /// run again on the aftermath model (SceneOptions::aftermath: cartons land on the deck, each
  /// other and the belt) to follow the wreck until the load moves with the belt again or
  /// kSolveAftermathS after the failure, past the profile's end if need be; its trace is the
  /// replay's when it reproduces the verdict (the same mode, time and items, as it must: nothing
  /// differs until something touches that no pair covers). SimResult::aftermath_cut says why a
  /// replay ends at the failure instead.
  Result<Solve> solve(const PalletConfig& config, const ConveyorProfile& profile,
                      double replay_hz = 30.0);

  const AnalyzerOptions& options() const { return options_; }
  /// Every later run checks `flag` (settle and probes: cancel.hpp); a call cancelled part-way
  /// fails with a diagnostic whose message contains "cancelled" and caches nothing of its work.
  /// nullptr: runs are not cancellable. The flag must outlive the calls that use it.
  void set_cancel(const CancelFlag* flag);
  /// Every later envelope and failure map reports its simulations to `callback` as they end,
  /// from the threads that ran them (ProgressCounter: done of planned; planned exact for a map,
  /// an estimate for a search, 4 a searched axis, raised as it runs past it; done == planned when
  /// the call ends). An empty callback: no reports.
  void set_progress(ProgressCounter::Callback callback);
  /// Every later envelope search tells `found` each start-up, stop and curve limit as soon as its
  /// search ends (search_envelope), from the thread that searched it. Empty: nothing is told.
  void set_axis_found(AxisFound found);
  int cache_hits() const { return cache_hits_; }
  /// Pallets prepared and kept (each holds its compiled scene and simulation data).
  std::size_t cached_pallets() const { return prepared_.size(); }
  void clear_cache();

 private:
  /// The analyzer's simulation options, counting on `counter` when a progress callback is set.
  SimOptions counting(ProgressCounter& counter) const;
  /// The scene numerics of a model level (merge for reduced and clustered; the full model's own
  /// timestep wherever an item is free).
  SceneOptions scene_options_for(const FidelityChoice& choice) const;
  /// The model level for `config` (choose_fidelity with this analyzer's options), before any
  /// scene is built.
  FidelityChoice fidelity_choice(const PalletConfig& config) const;

  /// The symmetry-reduced model of `config` for `plane` (PreparedPallet::planes), or null when
  /// the load does not reduce or the reduced model cannot be settled (the full model then runs).
  std::unique_ptr<PlaneModel> plane_model(const PalletConfig& config, ProbePlane plane,
                                          const SceneOptions& scene_options);

  /// After a contact or constraint buffer overflow (`why`): doubles the pallet's buffers, drops
  /// its prepared scene and says to run again; false when `why` is something else or the buffers
  /// were doubled three times already.
  bool grow_buffers(std::string key, const Diagnostics& why);

  /// Replaces a failed `verdict` by the same run on the pallet's aftermath model, followed past
  /// the failure, when that run reproduces the verdict; otherwise says why not in aftermath_cut.
  void follow_wreck(const PalletConfig& config, PreparedPallet& p, const ConveyorProfile& profile,
                    SimOptions o, SimResult& verdict);

  AnalyzerOptions options_;
  ProgressCounter::Callback progress_;
  AxisFound axis_found_;
  const FrictionModel* friction_;
  std::map<std::string, std::unique_ptr<PreparedPallet>> prepared_;
  std::map<std::string, SafetyResult> results_;
  /// Per fingerprint, the buffer growth a contact or constraint overflow asked for (doubled per
  /// overflow; the scene is rebuilt and the run repeated, never answered from the overflow).
  std::map<std::string, double> buffer_scale_;
  int cache_hits_ = 0;
};

}  // namespace pb
