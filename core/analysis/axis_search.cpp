// SPDX-License-Identifier: MIT
#include "core/analysis/axis_search.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace pb {

std::optional<AxisLimit> AxisSearch::run(double seed) {
  AxisLimit out;
  out.closed_form = seed;
  std::optional<double> safe, fail;
  FailureMode fail_mode = FailureMode::no_failure;
  double last_ratio = 0.0;                      // the peak ratio of the probe recorded last
  double last_failed_at = 1.0;                  // ProbeVerdict::failed_at of the last failure
  std::vector<std::pair<double, bool>> probed;  // every verdict: value, failed
  auto record = [&](double x, const ProbeVerdict& v) {
    ++out.probes;
    last_ratio = v.peak_ratio;
    probed.emplace_back(x, v.failed);
    if (v.failed) {
      last_failed_at = v.failed_at;
      if (!fail || x < *fail) {
        fail = x;
        fail_mode = v.mode;
      }
    } else if (!safe || x > *safe) {
      safe = x;
    }
  };
  auto test = [&](double x) -> std::optional<bool> {
    auto v = probe_(x);
    if (!v) {
      ++out.probes;
      return std::nullopt;
    }
    record(x, *v);
    return v->failed;
  };
  // One batched round: every verdict recorded; nullopt when a probe was unstable.
  auto round = [&](const std::vector<double>& xs) -> std::optional<std::vector<ProbeVerdict>> {
    auto verdicts = batch_(xs);
    if (!verdicts) {
      out.probes += int(xs.size());
      return std::nullopt;
    }
    for (std::size_t t = 0; t < xs.size(); ++t) record(xs[t], (*verdicts)[t]);
    return verdicts;
  };
  // k-section over the points bisection of [a, b] could probe (a and b known already).
  auto k_section = [&](double a, double b, double width) -> bool {
    std::vector<double> grid{a};
    bisection_grid(a, b, width, 0, grid);
    std::size_t i = 0, j = grid.size() - 1;
    while (j - i > 1) {
      const std::size_t m = std::min(std::size_t(k_), j - i - 1);
      std::vector<std::size_t> idx;
      for (std::size_t t = 1; t <= m; ++t) {
        const auto n = i + std::size_t(std::lround(double(t) * double(j - i) / double(m + 1)));
        if (n > i && n < j && (idx.empty() || n > idx.back())) idx.push_back(n);
      }
      std::vector<double> xs;
      for (std::size_t n : idx) xs.push_back(grid[n]);
      auto verdicts = round(xs);
      if (!verdicts) return false;
      std::size_t new_j = j, new_i = i;
      for (std::size_t t = 0; t < idx.size(); ++t) {
        if ((*verdicts)[t].failed && new_j == j) new_j = idx[t];
      }
      for (std::size_t t = 0; t < idx.size(); ++t) {
        if (!(*verdicts)[t].failed && idx[t] < new_j) new_i = std::max(new_i, idx[t]);
      }
      i = new_i;
      j = new_j;
    }
    return true;
  };
  // Down from the lowest failure in the walk's steps until a probe holds, the floor last; false
  // when a probe was unstable. A failure early in its demand jumps the walk to its doubling steps
  // (walk_step(3) is the first double one); the next late failure after such a jump starts the
  // single steps again, as the limit is likely near. Every step is the precision times a power of
  // two, as the bisection grid needs.
  auto walk_down = [&]() -> bool {
    bool hastened = false;
    auto next = [&](int n) {
      if (last_failed_at < kEarlyFailure) {
        hastened = true;
        return std::max(n + 1, 3);
      }
      if (hastened) {
        hastened = false;
        return 0;
      }
      return n + 1;
    };
    int n = next(-1);
    for (; !safe && *fail - walk_step(n) > min_; n = next(n)) {
      if (!test(*fail - walk_step(n))) return false;
    }
    // Where the next step would pass the floor, the longest step that stays above it is taken
    // once before the floor: a load that holds there is bracketed by a power of two of the
    // precision (an 80-carton random pallet's curve: its walk failed down to 0.155 g, and the
    // floor at 0.01 g left a bracket of 0.145 g to bisect in five probes; from 0.075 g, four).
    if (!safe) {
      while (n > 0 && *fail - walk_step(n) <= min_) --n;
      const double above = *fail - walk_step(n);
      if (above > min_ && !test(above)) return false;
    }
    return safe || *fail <= min_ || test(min_).has_value();
  };
  // Halve the bracket while it is wider than the precision; false when a probe was unstable.
  auto bisect = [&]() -> bool {
    while (safe && fail && *fail - *safe > finest()) {
      if (!test(0.5 * (*safe + *fail))) return false;
    }
    return true;
  };
  const bool sectioned = batch_ && k_ > 1;
  if (!seeded_) {  // the reference's plain bisection over the whole range
    double lo = min_, hi = max_;
    if (sectioned && !k_section(lo, hi, precision_)) return std::nullopt;
    while (!sectioned && hi - lo > precision_) {
      const double mid = 0.5 * (lo + hi);
      auto r = test(mid);
      if (!r) return std::nullopt;
      (*r ? hi : lo) = mid;
    }
    // The ends are only tried when the bisection never left them (a floor or ceiling answer).
    if (!safe && !test(min_)) return std::nullopt;
    if (!fail && !test(max_)) return std::nullopt;
    return finish(out, safe, fail, fail_mode);
  }
  const double first = std::clamp(seed, min_, max_);
  auto r = test(first);
  if (!r) return std::nullopt;
  const double seed_ratio = last_ratio;
  // Where the seed sits just above the load's weakest onset (vouch_), a safe seed that came
  // near failing (kNearFailure) does not vouch for what lies below it: the load is in the band
  // where its fate can hang on round-off, and nothing below the seed was probed. So the search
  // probes down from it (the down walk's steps) until a probe is safe by a margin or fails; a
  // failure below the seed means failure is not monotone there, and the search goes on down
  // from that failure, forgetting the safe verdicts above it. (u2048's curve: safe at its seed,
  // 0.298 g, peak 0.74, failing at 0.288; the reference configuration fails at 0.290.)
  if (vouch_ && !*r && last_ratio >= kNearFailure) {
    int n = 0;
    for (double x = first - walk_step(n); x > min_; x -= walk_step(++n)) {
      const auto below = test(x);
      if (!below) return std::nullopt;
      if (*below) {
        safe.reset();
        r = true;
        break;
      }
      if (last_ratio < kNearFailure) break;
    }
  }

  int walked = 0;
  double step = walk_step(walked);
  if (sectioned) {
    // The walk in rounds of the next k points the serial walk would probe (the range's end
    // last, when the walk reaches it): under monotone failure the first failing (walking up)
    // or safe (walking down) one is where the serial walk stops, so the bracket is the same.
    const bool up = !*r;
    while (up ? !fail : !safe) {
      std::vector<double> xs;
      bool last = false;
      for (double from = up ? *safe : *fail; int(xs.size()) < k_;) {
        const double x = up ? from + step : from - step;
        if (up ? x < max_ : x > min_) {
          xs.push_back(x);
          from = x;
          step = walk_step(++walked);
        } else {
          if (up ? first < max_ : first > min_) xs.push_back(up ? max_ : min_);
          last = true;
          break;
        }
      }
      if (!xs.empty() && !round(xs)) return std::nullopt;
      if (last) break;
    }
  } else if (*r) {  // failed: walk down
    if (!walk_down()) return std::nullopt;
  } else {  // safe: walk up, one step at a time while the load comes near failing, else doubling
    if (seed_ratio >= kAtFailure && first + 0.5 * precision_ < max_) {
      if (!test(first + 0.5 * precision_)) return std::nullopt;
    }
    for (double x = *safe + step; !fail && x < max_; x = *safe + step) {
      if (!test(x)) return std::nullopt;
      step = step == precision_ && last_ratio >= kNearFailure ? precision_ : 2.0 * step;
    }
    if (!fail && first < max_ && !test(max_)) return std::nullopt;
  }
  if (sectioned && safe && fail && *fail - *safe > finest()) {
    if (!k_section(*safe, *fail, finest())) return std::nullopt;
  }
  if (!sectioned && !bisect()) return std::nullopt;
  // A load whose items can move may fail and hold by turns over a band of demands (an item held
  // between its kinetic and static onsets slides when its carrier's rocking breaks it loose), and
  // the bracket's probes sample that band at a few points. Where asked (band_checks_), the answer
  // is probed once more a step below (unless that point was probed already); a failure there
  // restarts the walk down from it, at most band_checks_ times.
  for (int checks = 0; checks < band_checks_ && safe && fail; ++checks) {
    const double x = *safe - precision_;
    if (x <= min_) break;
    const auto seen = std::find_if(probed.begin(), probed.end(),
                                   [&](const auto& p) { return std::abs(p.first - x) < 1e-12; });
    const auto below = seen != probed.end() ? std::optional<bool>(seen->second) : test(x);
    if (!below) return std::nullopt;
    if (!*below) break;
    safe.reset();
    if (seen != probed.end()) fail = std::min(*fail, x);
    if (!walk_down() || !bisect()) return std::nullopt;
  }
  return finish(out, safe, fail, fail_mode);
}

}  // namespace pb
