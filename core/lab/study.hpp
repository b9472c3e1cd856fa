// SPDX-License-Identifier: MIT
// Speed against accuracy: the numerical configurations of an envelope (fidelity level x timestep x
// cone/solver settings), the slow reference configuration that judges them, and the metrics of
// the comparison (error in search steps, governing-mode agreement, median wall time, Pareto front).
// What `palletballet-lab study speed-accuracy` and `study convergence` run.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/analysis/analyzer.hpp"
#include "core/analysis/envelope.hpp"
#include "core/base/diagnostic.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/contract/safety_result.hpp"

namespace pb {

/// One way of computing an envelope.
struct StudyConfig {
  std::string name;         ///< short and stable: "default", "full-5ms", ...
  std::string description;  ///< one line: what differs from the shipped default
  AnalyzerOptions options;
  bool is_default = false;               ///< the shipped configuration (AnalyzerOptions{})
  bool is_reference_equivalent = false;  ///< the reference system's algorithm
  bool is_reference = false;             ///< the judge itself
};

/// The reference configuration: the full multi-body model at 0.5 ms, stiff contacts (solref
/// 0.005 1 on top of the shipped stiff impedance), a converged Newton solve (1000 iterations,
/// tolerance 1e-12), plain bisection over the whole range (independent of the closed-form bounds)
/// at half the shipped search steps. Slow; used only to judge the others.
AnalyzerOptions reference_options();
/// The reference with its timestep halved (0.25 ms), everything else equal: its convergence check.
AnalyzerOptions reference_half_step_options();
/// The reference system's algorithm: full model, plain bisection, 2 ms, no early stop.
AnalyzerOptions reference_equivalent_options();

/// Every configuration of the study, the reference first, then the shipped default, the
/// reference-equivalent mode and the ladder (fidelity x timestep x cone/solver).
std::vector<StudyConfig> study_configs();
/// The configurations named in a comma-separated list (the reference is always added, first: it
/// judges the others). An unknown name is an error at `pointer` that lists the known ones.
Result<std::vector<StudyConfig>> select_study_configs(const std::string& names,
                                                      const std::string& pointer = "/configs");

/// A stable key of everything in `options` that changes an envelope (for caches of results).
std::string options_fingerprint(const AnalyzerOptions& options);

/// The unit of "one search step" per axis: the shipped default's precision (0.1 m/s^2 for start-up
/// and stops, 0.01 g for curves, 0.05 m/s for speed).
struct SearchSteps {
  double accel = 0.1, decel = 0.1, lateral = 0.01, speed = 0.05;
  static SearchSteps of(const SearchConfig& search);
};

inline constexpr std::array<Axis, 4> kStudyAxes{Axis::accel, Axis::decel, Axis::lateral,
                                                Axis::speed};

/// A candidate envelope against the reference's.
struct EnvelopeComparison {
  std::array<double, 4> error_steps{};  ///< |candidate - reference| / step, per kStudyAxes
  int limits_within = 0;                ///< of the four, within one step of the reference
  int limits_above = 0;            ///< of the four, more than one step above it (an unsafe answer)
  double worst_above_steps = 0.0;  ///< how far above, at worst (0 when none is above)
  double worst_steps = 0.0;
  Axis worst_axis = Axis::accel;
  bool within_one_step = false;  ///< every limit within one step (and the same verdict)
  bool verdict_agrees = false;
  /// Axes whose governing mode is compared: those where the reference fails more than one step
  /// inside the search range (closer to the ceiling, "what fails first" is not determined).
  int modes_compared = 0;
  int modes_agreeing = 0;
  bool modes_agree() const { return modes_agreeing == modes_compared; }
};

/// Compares two results limit by limit, in units of `steps`.
EnvelopeComparison compare_envelopes(const SafetyResult& reference, const SafetyResult& candidate,
                                     const SearchSteps& steps = {}, const SearchConfig& range = {});

/// A pallet of the study's corpus.
struct CorpusPallet {
  std::string label;  ///< the scenario's slug or "random-<seed>"
  PalletConfig pallet;
};

/// The curated scenarios (in display order), then `random_count` random pallets of the scanner
/// adapter's default options with seeds first_seed, first_seed + 1, ...
std::vector<CorpusPallet> study_corpus(int random_count, std::uint64_t first_seed = 1000,
                                       bool curated = true);

/// One envelope of one configuration on one pallet, from cold caches (compile and settle included).
struct StudySample {
  std::string config;
  std::string pallet;
  double wall_ms = 0.0;
  double cpu_ms =
      0.0;  ///< the process's CPU time (every axis thread): robust against a loaded machine
  int sims = 0;
  std::optional<SafetyResult> result;
  std::string error;                             ///< why there is no result
  std::optional<EnvelopeComparison> comparison;  ///< against the reference (when both exist)
  bool reference_ok = false;  ///< the reference has a result for this pallet (set by the caller)
};

/// Runs the envelope of `config` on `pallet` with a fresh Analyzer (cold caches).
StudySample measure_envelope(const StudyConfig& config, const CorpusPallet& pallet);

/// What one configuration achieved over the corpus.
struct StudySummary {
  std::string config;
  std::string description;
  bool is_default = false;
  bool is_reference_equivalent = false;
  bool is_reference = false;
  std::string fidelity;  ///< the levels its results reported, e.g. "full" or "reduced+full"
  int pallets = 0;       ///< compared against a reference result
  int errors = 0;        ///< runs that gave no result (counted as outside one step)
  double median_ms = 0.0;
  double median_cpu_ms = 0.0;
  double within_one_step = 0.0;  ///< fraction of `pallets`
  /// Limit by limit: the fraction within one step of the reference (4 a pallet), and how many are
  /// more than one step above it (unsafe), the worst by how much.
  double limits_within_one_step = 0.0;
  int limits_above = 0;
  double worst_above_steps = 0.0;
  double worst_error_steps = 0.0;
  std::string worst_pallet;
  std::string worst_axis;
  int mode_pallets = 0;         ///< pallets with at least one axis whose mode is compared
  double mode_agreement = 1.0;  ///< fraction of those whose compared modes all agree
  /// No other configuration is both faster and more accurate (the reference is left out: it
  /// agrees with itself by definition).
  bool pareto = false;
};

/// Summaries in the order of `configs`, with the Pareto front marked (faster = lower median wall
/// time; more accurate = higher within-one-step share, then lower worst error).
std::vector<StudySummary> summarize_study(const std::vector<StudyConfig>& configs,
                                          const std::vector<StudySample>& samples);

Json study_summary_to_json(const StudySummary& summary);

/// The reference's convergence on one pallet: its envelope at 0.5 ms and at 0.25 ms.
struct ConvergenceRow {
  std::string pallet;
  StudySample reference;
  StudySample half_step;
  std::optional<EnvelopeComparison> comparison;  ///< in the reference's own search steps
};

/// Runs both envelopes and compares them in units of the reference's (half) search steps.
ConvergenceRow reference_convergence(const CorpusPallet& pallet);

}  // namespace pb
