// SPDX-License-Identifier: MIT
#include "core/lab/breakaway_study.hpp"

#include "core/analysis/envelope.hpp"

namespace pb {

bool fails_below_a_hold(std::span<const BandPoint> points) {
  bool failed = false;
  for (const BandPoint& p : points) {
    if (p.outcome == Outcome::failed) failed = true;
    if (failed && p.outcome == Outcome::safe) return true;
  }
  return false;
}

Result<BreakawayBand> breakaway_band(const PalletConfig& config, const AnalyzerOptions& options,
                                     std::span<const double> shares) {
  Analyzer analyzer(options);
  auto prepared = analyzer.prepare(config);
  if (!prepared) return Result<BreakawayBand>::failure(std::move(prepared.diagnostics));
  PreparedPallet& p = **prepared.value;
  BreakawayBand band;
  band.onset_mps2 = belt_onset_mps2(p.bounds.along);
  const PlaneModel* plane = p.planes[0].get();
  band.reduced = plane != nullptr;
  Simulator& simulator = plane ? *plane->simulator : *p.simulator;
  const RestState& rest = plane ? plane->rest : p.rest;
  const SearchConfig& s = options.search;
  SimOptions o = options.sim;
  o.record_trace = false;
  o.fail_fast = true;  // as the searches run
  auto point = [&](double share, double value, const ConveyorProfile& profile) {
    const SimResult r = simulator.run(rest, profile, o);
    return BandPoint{share, value, r.outcome, r.failure ? r.failure->mode : FailureMode::no_failure,
                     r.peak_ratio};
  };
  if (band.onset_mps2 <= 0.0) return Result<BreakawayBand>{std::move(band), {}};
  for (const double share : shares) {
    const double a = share * band.onset_mps2;
    if (a >= s.accel_min_mps2 && a <= s.accel_max_mps2) {
      band.start_up.push_back(point(share, a, accel_probe_profile(a, s)));
    }
    if (a >= s.decel_min_mps2 && a <= s.decel_max_mps2) {
      band.stop.push_back(point(share, a, decel_probe_profile(a, s.speed_max_mps, s)));
    }
  }
  return Result<BreakawayBand>{std::move(band), {}};
}

}  // namespace pb
