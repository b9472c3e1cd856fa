// SPDX-License-Identifier: MIT
// The search along one axis of the envelope: from a seed, walk out until the limit is bracketed,
// then bisect. It sees only verdicts (ProbeFn), so it is tested on made-up ones
// (tests/core/analysis/axis_search_test.cpp); envelope.cpp gives it simulations.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "core/analysis/envelope.hpp"
#include "core/base/enums.hpp"

namespace pb {

struct ProbeVerdict {
  bool failed = false;
  FailureMode mode = FailureMode::no_failure;
  double peak_ratio = 0.0;  ///< SimResult::peak_ratio
  /// A failure: how far into the probe's demand it came (0 at the demand's onset, 1 at its end;
  /// more once the load went on sliding after it). 1 where unknown.
  double failed_at = 1.0;
  double load_peak_ratio = 0.0;  ///< SimResult::load_peak_ratio
};

/// A probe that failed before this share of its demand had passed is likely far above its limit
/// (a load just above its limit fails near the demand's end, or after it, as its slide builds):
/// the walk down doubles its steps from it instead of stepping singly (AxisSearch). A 72-carton
/// brick's curve far above its limit fails 13 % into its arc; tall-unwrapped-tower's one step above
/// at 39 % (so 0.5, until session 41, hastened it past its limit: a probe more) and its start-up
/// at 65 %.
constexpr double kEarlyFailure = 0.3;

// A safe probe whose detectors came this near their thresholds (SimResult::peak_ratio) is likely
// within a step or two of the limit: the walk up keeps its step there instead of doubling.
constexpr double kNearFailure = 0.5;

// A safe probe whose detectors came this near their thresholds is taken to fail half a step
// above it: a detector's measure there (a slide's length, a tilt) grows with the demand, and
// within 1 % of its threshold half a step more crosses it (a pallet slipping through a start-up
// to 2 m/s on a belt of mu_d 0.28: +1.5 % at 4.6 m/s^2, more lower down). So the walk up from such
// a probe tries the half step first, which closes the bracket at once where it fails, and walks
// on from there where it holds.
constexpr double kAtFailure = 0.99;
// One axis: probe near the seed, step outwards until the boundary is bracketed, then bisect while
// the bracket is wider than half the precision (finest()). Down from a failing
// seed the steps are three of the precision, then doubling (a seed just above the weakest onset
// lands within about two steps of the limit), except that a failure early in its demand
// (ProbeVerdict::failed_at < kEarlyFailure) starts the doubling at once and the next late one
// returns to single steps; up from a safe one, one step at a time while the last
// probe came near failing (kNearFailure), else doubling (a pallet that must slip 0.3 m can be ten
// steps above its onset), and half a step first from one at the point of failing (kAtFailure).
// Every walk's steps are the precision times powers of two, so the bisection grid, and the limit
// when failure is monotone, do not depend on the walk. Failure is assumed monotone along the axis,
// except for a load whose items can move (`vouch`, run()): just below a seed at its weakest onset
// that came near failing, and, where asked (`band_checks`), one step below its answer. With a batch
// function and k > 1 the bracket is narrowed by k-section instead: each round probes k points of
// the bisection grid of the bracket at once (one batched call), so rounds drop from log2 n to
// log_{k+1} n; the walk that brackets the boundary takes its next k points per round.
class AxisSearch {
 public:
  using ProbeFn = std::function<std::optional<ProbeVerdict>(double)>;  // nullopt: unstable
  /// One verdict per value, in order; nullopt when any probe was unstable (or the batch failed).
  using BatchFn =
      std::function<std::optional<std::vector<ProbeVerdict>>(const std::vector<double>&)>;

  /// `vouch`: a safe seed that came near failing is checked below (see run()); for a load whose
  /// items can move, seeded one step above its weakest onset. A one-body load's seed is its
  /// closed-form prediction, half a step below the slip it predicts: near failing by design.
  /// `band_checks` (with `vouch`): the answer is probed once more a step below, and a failure there
  /// walks down again from it, at most that many times (SearchConfig::band_checks).
  AxisSearch(double lo, double hi, double precision, ProbeFn probe, bool seeded = true,
             bool vouch = false, BatchFn batch = {}, int k = 1, int band_checks = 0)
      : min_(lo),
        max_(hi),
        precision_(precision),
        probe_(std::move(probe)),
        seeded_(seeded),
        vouch_(vouch),
        batch_(std::move(batch)),
        k_(k),
        band_checks_(vouch ? band_checks : 0) {}

  /// The limit from `seed` (clamped to the range); nullopt when a probe was unstable.
  std::optional<AxisLimit> run(double seed);

 private:
  // The walk's n-th step (n from 0): the precision three times, then doubling.
  double walk_step(int n) const { return precision_ * double(1 << std::clamp(n - 2, 0, 30)); }
  // The widest bracket the seeded search leaves: half the precision (with a hair of slack for
  // brackets built from sums of steps), so a limit lies within half a step of its threshold on
  // the search's grid. Until session 16 it was the precision as computed: a one-step bracket
  // reached by adding steps to the seed usually computed a hair wider and was halved once more,
  // one reached by bisection did not, so which limits ended within half a step and which within
  // one hung on round-off; a walk that takes other steps (hasten_walk) moved them (u2021's curve
  // 0.5 -> 1.03 steps below the reference). Explicit, on the unwrapped corpus: the same 88 of 96
  // limits within one step, 3 more simulations of 359 (core/README.md, "The walk").
  double finest() const { return 0.5 * precision_ * (1.0 + 1e-6); }

  // Appends the points bisection of [a, b] until brackets are at most `width` wide can probe after
  // a, ascending, b last: the same expressions as the bisection, so the same doubles and, when
  // failure is monotone, the same limit.
  void bisection_grid(double a, double b, double width, int depth, std::vector<double>& out) const {
    if (b - a > width && depth < kMaxDepth) {
      const double m = 0.5 * (a + b);
      bisection_grid(a, m, width, depth + 1, out);
      bisection_grid(m, b, width, depth + 1, out);
    } else {
      out.push_back(b);
    }
  }
  static constexpr int kMaxDepth = 16;  // 65537 points: far finer than any search needs

  static AxisLimit finish(AxisLimit out, std::optional<double> safe, std::optional<double> fail,
                          FailureMode fail_mode) {
    out.at_ceiling = !fail;
    out.at_floor = !safe;
    out.limit = safe.value_or(0.0);
    out.mode = fail ? fail_mode : FailureMode::no_failure;
    return out;
  }

  double min_, max_, precision_;
  ProbeFn probe_;
  bool seeded_ = true;
  bool vouch_ = false;
  BatchFn batch_;
  int k_ = 1;
  int band_checks_ = 0;
};

}  // namespace pb
