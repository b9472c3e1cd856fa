// SPDX-License-Identifier: MIT
// The breakaway band: how a load fares in start-ups and stops just below its pallet's slip onset.
// Up to its breakaway the pallet passes on nearly all it can for the whole demand, and past it
// only mu_d g, so a load can fail in that band and hold above it: failure is not monotone there
// (core/README "A check that came near failing does not vouch for the band above it"). What
// `palletballet-lab study breakaway` prints, for any configuration of the study.
#pragma once

#include <span>
#include <vector>

#include "core/analysis/analyzer.hpp"
#include "core/base/diagnostic.hpp"
#include "core/base/enums.hpp"
#include "core/contract/pallet_config.hpp"

namespace pb {

/// The shares of the pallet's onset the study probes by default.
inline constexpr double kBreakawayShares[] = {0.95, 0.96, 0.97, 0.98, 0.985, 0.99, 0.995, 1.0};

struct BandPoint {
  double share = 0.0;       ///< of the pallet's slip onset
  double value_mps2 = 0.0;  ///< the start-up's or stop's acceleration
  Outcome outcome = Outcome::safe;
  FailureMode mode = FailureMode::no_failure;
  double peak_ratio = 0.0;  ///< SimResult::peak_ratio
};

struct BreakawayBand {
  double onset_mps2 = 0.0;  ///< the pallet's slip onset along the belt (mu_s g); 0: none
  bool reduced = false;     ///< probed on the symmetry-reduced model the searches use
  std::vector<BandPoint> start_up, stop;
};

/// Whether `points` (in rising shares) fail at one share and hold at a higher one: failure is not
/// monotone there.
bool fails_below_a_hold(std::span<const BandPoint> points);

/// Start-ups and stops of `config` (the envelope's probe profiles, to and from the search's top
/// speed) at `shares` of its pallet's slip onset along the belt, under `options`, on the model the
/// envelope's searches along the belt use (the plane model where the load reduces by symmetry).
/// A share whose demand is outside the search's range is skipped. Fails where the pallet cannot
/// be prepared.
Result<BreakawayBand> breakaway_band(const PalletConfig& config, const AnalyzerOptions& options,
                                     std::span<const double> shares = kBreakawayShares);

}  // namespace pb
