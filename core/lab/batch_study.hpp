// SPDX-License-Identifier: MIT
// The batch study (the reference's 400-random-pallet study): random pallets by seed, analysed in
// parallel (T threads, each with its own Analyzer, one results cache shared by fingerprint),
// per-pallet results and the distribution of limits and governing modes.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/analysis/analyzer.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/random_pallet.hpp"

namespace pb {

struct BatchStudyOptions {
  int n = 400;  ///< pallets: seeds seed, seed + 1, ..., seed + n - 1
  std::uint64_t seed = 0;
  int threads = 0;             ///< 0: every CPU (at most n)
  RandomPalletOptions pallet;  ///< its seed is replaced by each pallet's
  AnalyzerOptions analyzer;
  /// When not empty: analyse these pallets (n is their count; seeds are their indices) instead of
  /// random ones.
  std::vector<PalletConfig> pallets;
};

struct StudyEntry {
  std::uint64_t seed = 0;
  std::string pallet_id;
  std::string fingerprint;
  std::string notes;  ///< pattern, Ti x Hi, anomaly (random_pallet)
  int items = 0;
  bool cached = false;  ///< the shared cache answered (a pallet identical to an earlier one)
  std::optional<SafetyResult> result;
  std::string error;  ///< why there is no result (a build defect, an unstable run)
  double wall_ms = 0.0;
};

/// Five-number summary (plus mean) of one limit over the pallets with a result and verdict ok.
struct Distribution {
  int count = 0;
  double min = 0, p10 = 0, median = 0, p90 = 0, max = 0, mean = 0;
};
Distribution distribution_of(std::vector<double> values);

struct BatchStudy {
  std::vector<StudyEntry> pallets;  ///< in seed order
  int analysed = 0, errors = 0, cache_hits = 0, rejects = 0;
  int sims = 0;
  int threads = 0;
  double wall_s = 0.0;
  double pallets_per_s = 0.0;
  Distribution max_speed_mps, max_accel_mps2, max_decel_mps2, max_lateral_g;
  std::map<std::string, int> dominant_modes;  ///< dominant_failure_mode over all results
  std::map<std::string, int> speed_governed_by;
  std::map<std::string, int> reject_modes;  ///< why rejected pallets are rejected
};

/// Recomputes the counts, modes and distributions of `study` from its pallets (the wall time,
/// threads and rate are left as they are): how shards of one study are joined.
void summarise(BatchStudy& study);

/// Runs the study. Fails only on bad options (naming the field); a pallet that cannot be analysed
/// is an entry with its error.
Result<BatchStudy> run_batch_study(const BatchStudyOptions& options,
                                   const Catalog& catalog = Catalog::builtin(),
                                   const FrictionModel& friction = FrictionModel::builtin());

}  // namespace pb
