// SPDX-License-Identifier: MIT
#include "core/analysis/envelope.hpp"
#include "core/analysis/axis_search.hpp"
#include "core/analysis/fidelity.hpp"
#include "core/base/text.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/physics/probe_batch.hpp"
#include "core/physics/step.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>

namespace pb {

std::string_view governor_words(SpeedGovernor by) {
  switch (by) {
    case SpeedGovernor::estop:
      return "the line's e-stop";
    case SpeedGovernor::curve:
      return "the tightest curve";
    case SpeedGovernor::ceiling:
      return "the top of the search range";
    case SpeedGovernor::reject:
      return "a pallet unsafe at any motion";
    case SpeedGovernor::build_defect:
      return "a load that cannot stand";
    case SpeedGovernor::unset:
      break;
  }
  return "nothing yet (not analysed)";
}

std::string_view to_string(Axis axis) {
  switch (axis) {
    case Axis::accel:
      return "accel";
    case Axis::decel:
      return "decel";
    case Axis::lateral:
      return "lateral";
    case Axis::speed:
      return "speed";
  }
  return "?";
}

namespace {

constexpr double kSettleLead = 0.05;  // s at steady speed before a stop or a curve begins
constexpr int kProbesPerSearch = 4;   // what a search plans, for progress (an estimate)

// How far up its search range a limit sits, in [0, 1].
double normalised(const AxisLimit& a, double lo, double hi) {
  if (a.at_ceiling) return 1.0;
  return std::clamp((a.limit - lo) / (hi - lo), 0.0, 1.0);
}

// How far a mechanism's slip may travel before its detector fires; 0 for a tip.
double slide_allowance_m(Mechanism m, const DetectorThresholds& t) {
  switch (m) {
    case Mechanism::pallet_slip:
      return t.pallet_slip_m;
    case Mechanism::item_slip_on_deck:
      return t.item_slide_m;
    case Mechanism::item_slip_on_item:  // its distance to the item below changes as it slides
      return std::min(t.item_slide_m, t.load_shift_m);
    case Mechanism::load_tip:
    case Mechanism::stack_tip:
      return 0.0;
  }
  return 0.0;
}

// The speed from which the line's e-stop makes `along`, the weakest slip along the belt, slide
// what its detector allows (the pallet on its belt, an item on the deck).
double estop_slide_speed_mps(const QuasiStaticLimit& along, const LineDescription& line,
                             const DetectorThresholds& t) {
  return breakaway_slide_speed_mps(
      along.accel_mps2, sliding_decel_mps2(along), line.estop_decel_mps2,
      along.mode == FailureMode::pallet_slip ? t.pallet_slip_m : t.item_slide_m, kBreakLooseM);
}

}  // namespace

AxisPrediction predict_axis(const std::vector<QuasiStaticLimit>& mechanisms, double unit, double lo,
                            double hi, const std::function<double(double)>& step_duration_s,
                            const DetectorThresholds& thresholds, double break_loose_m) {
  AxisPrediction out{hi, FailureMode::no_failure};
  for (const QuasiStaticLimit& m : mechanisms) {
    const double onset = m.accel_mps2 / unit;
    double at = onset;
    if (const double allowance = slide_allowance_m(m.mechanism, thresholds); allowance > 0.0) {
      // The slide grows with the demand for every probe shape (d/da of a ramp to v's slide is
      // 2 / a^2 > 0; a curve's and a stop's likewise), so bisection finds where it reaches the
      // allowance.
      auto slide = [&](double x) {
        return breakaway_slide_m(m.accel_mps2, sliding_decel_mps2(m), x * unit, step_duration_s(x),
                                 break_loose_m);
      };
      if (onset >= hi || slide(hi) < allowance) continue;
      double a = std::max(onset, lo), b = hi;
      for (int i = 0; i < 60 && b - a > 1e-9 * hi; ++i) {
        const double mid = 0.5 * (a + b);
        (slide(mid) < allowance ? a : b) = mid;
      }
      at = b;
    }
    if (at < out.value) out = {at, m.mode};
  }
  return out;
}

ConveyorProfile accel_probe_profile(double accel, const SearchConfig& s) {
  ConveyorProfile p;
  p.shape = ProfileShape::accel_hold;
  p.accel_mps2 = accel;
  p.target_speed_mps = std::min(s.speed_max_mps, accel * s.max_ramp_s);
  p.duration_s = p.target_speed_mps / accel + s.hold_s;
  return p;
}

ConveyorProfile decel_probe_profile(double decel, double speed, const SearchConfig& s) {
  ConveyorProfile p;
  p.shape = ProfileShape::estop;
  p.target_speed_mps = speed;
  p.decel_mps2 = decel;
  p.decel_start_s = kSettleLead;
  p.duration_s = kSettleLead + speed / decel + s.hold_s;
  return p;
}

ConveyorProfile stop_probe_profile(double speed, const LineDescription& line,
                                   const SearchConfig& s) {
  return decel_probe_profile(line.estop_decel_mps2, speed, s);
}

std::vector<CurveTurn> curve_turns(const PalletConfig& config) {
  if (mirror_symmetric_across(config)) return {CurveTurn::left};
  return {CurveTurn::left, CurveTurn::right};
}

ConveyorProfile lateral_probe_profile(double lateral_g, const LineDescription& line,
                                      const SearchConfig& s, CurveTurn turn) {
  ConveyorProfile p;
  p.shape = ProfileShape::curve;
  p.curve_turn = turn;
  p.curve_radius_m = line.curve_radius_m;
  p.target_speed_mps = std::min(5.0, std::sqrt(lateral_g * kGravity * line.curve_radius_m));
  // The lateral acceleration is what matters; a long arc at a low speed is capped at max_ramp_s.
  const double arc_s =
      line.curve_radius_m * line.curve_angle_deg * std::numbers::pi / 180.0 / p.target_speed_mps;
  const double t = std::min(arc_s, s.max_ramp_s);
  p.curve_angle_deg = line.curve_angle_deg * t / arc_s;
  p.curve_start_s = kSettleLead;
  p.duration_s = kSettleLead + t + s.hold_s;
  return p;
}

namespace {

// The mechanisms across the belt, their onsets in the centre line's v^2 / r: a curve of `radius_m`
// demands more of a mass off the centre (curve_demand_factor).
std::vector<QuasiStaticLimit> in_a_curve(std::vector<QuasiStaticLimit> across, double radius_m) {
  for (QuasiStaticLimit& m : across) {
    const double f = curve_demand_factor(m, radius_m);
    m.accel_mps2 /= f;
    m.sliding_mps2 /= f;
  }
  return across;
}

// The mechanisms that can act: friction cannot push the pallet harder than its belt holds it, so
// a mechanism of the load (an item's slip, a sub-stack's tip) whose onset is above the pallet's
// slip onset is carried by the slipping pallet instead, quasi-statically (search_envelope checks
// the load below the pallet's onset, where it is not).
std::vector<QuasiStaticLimit> carried(std::vector<QuasiStaticLimit> mechanisms) {
  const double belt = belt_onset_mps2(mechanisms);
  if (belt <= 0.0) return mechanisms;
  std::erase_if(mechanisms, [&](const QuasiStaticLimit& m) {
    return !of_the_whole_load(m) && m.accel_mps2 >= belt;
  });
  return mechanisms;
}

// How long a curve probe at `lateral_g` holds its demand (its arc), s.
double arc_s(double lateral_g, const LineDescription& line, const SearchConfig& s) {
  return lateral_probe_profile(lateral_g, line, s).duration_s - kSettleLead - s.hold_s;
}

// Every mechanism's failure as if the load moved as one body (predict_axis on each axis's probe),
// its slips breaking loose after `break_loose_m` on their static cones.
AxisPredictions rigid_predictions(const QuasiStaticBounds& bounds, const LineDescription& line,
                                  const SearchConfig& s, const DetectorThresholds& thresholds,
                                  double break_loose_m = kBreakLooseM) {
  AxisPredictions p;
  p.accel = predict_axis(
      carried(bounds.along), 1.0, s.accel_min_mps2, s.accel_max_mps2,
      [&](double a) { return accel_probe_profile(a, s).target_speed_mps / a; }, thresholds,
      break_loose_m);
  p.decel = predict_axis(
      carried(bounds.along), 1.0, s.decel_min_mps2, s.decel_max_mps2,
      [&](double d) { return s.speed_max_mps / d; }, thresholds, break_loose_m);
  p.lateral = predict_axis(
      carried(in_a_curve(bounds.across, line.curve_radius_m)), kGravity, s.lateral_min_g,
      s.lateral_max_g, [&](double g) { return arc_s(g, line, s); }, thresholds, break_loose_m);
  return p;
}

// The curve (g) at which a pallet broken loose at the arc's entry slides its allowance by the
// arc's end, sliding at mu_d g from the start; the top of the range where nothing slips. A rigid
// load holds its pallet on its static cone up to mu_s g, but a wrapped one sways into its wrap as
// the curve's demand steps on, and the friction it asks of its pallet overshoots the steady v^2/r
// and breaks the pallet loose below that (core/README "The reduced level in a curve").
double loose_at_entry_g(const QuasiStaticBounds& bounds, const LineDescription& line,
                        const SearchConfig& s, const DetectorThresholds& thresholds) {
  std::vector<QuasiStaticLimit> slips;
  for (QuasiStaticLimit m : in_a_curve(bounds.across, line.curve_radius_m)) {
    if (m.mechanism != Mechanism::pallet_slip) continue;
    m.accel_mps2 = sliding_decel_mps2(m);
    slips.push_back(m);
  }
  return predict_axis(
             slips, kGravity, s.lateral_min_g, s.lateral_max_g,
             [&](double g) { return arc_s(g, line, s); }, thresholds, 0.0)
      .value;
}

}  // namespace

AxisPredictions predict_envelope(const QuasiStaticBounds& bounds, const LineDescription& line,
                                 const SearchConfig& s, const DetectorThresholds& thresholds) {
  if (bounds.one_body()) return rigid_predictions(bounds, line, s, thresholds);
  // Items can slide and rock: the onsets (see the header).
  AxisPredictions p;
  QuasiStaticBounds curve{{}, in_a_curve(bounds.across, line.curve_radius_m)};
  const QuasiStaticLimit along = bounds.weakest_along(), across = curve.weakest_across();
  p.accel = p.decel = {along.accel_mps2, along.mode};
  p.lateral = {across.accel_mps2 / kGravity, across.mode};
  return p;
}

namespace {
// The SafetyResult from the four axes, its reason in the words of `thresholds`' detectors;
// `predicted`: no simulation ran (the closed-form level).
void summarise(Envelope& env, const LineDescription& line, const SearchConfig& s,
               const DetectorThresholds& thresholds, bool predicted = false);
void stamp_sims_and_time(Envelope& env, std::chrono::steady_clock::time_point start);
}  // namespace

namespace {

class Lookahead;

// One axis's search, independent of the others: what it found, the probes it ran, and why it
// stopped if a probe was unstable or the batched probes could not run.
struct AxisTask {
  Axis axis = Axis::accel;
  double lo = 0.0, hi = 0.0, precision = 0.0;
  double seed = 0.0;
  double closed_form = 0.0;  ///< the prediction the seed came from
  std::function<ConveyorProfile(double)> profile;
  /// Verdicts already known (from an earlier search of the same probes): not simulated again.
  std::map<double, ProbeVerdict> known;
  /// A safe seed that came near failing is checked below (AxisSearch): a load whose items can
  /// move, seeded from its onsets.
  bool vouch = false;
  /// Verdicts say how far into its demand a probe failed (ProbeVerdict::failed_at), which speeds
  /// the walk down from a seed far above the limit (SearchConfig::hasten_walk).
  bool hasten = false;
  /// Where the axis's probes are one experiment cut at different times: the lowest value whose
  /// probe runs as every higher one does up to time t (empty: none). The e-stop speed axis: a stop
  /// at the line's deceleration d from v lasts v / d, so every stop from at least d (t - its
  /// start) runs as any faster one up to t. A probe that fails at t within its demand then says
  /// every value from there up fails too: the same run, up to round-off (search_axis).
  std::function<double(double)> same_until;
  /// Where the pallet breaks loose on its belt (the axis's unit; 0: not checked). A load whose
  /// items can move may fail below it and hold above it (search_envelope): a limit above it is
  /// checked just below it.
  double belt_onset = 0.0;
  /// The probe that follows this search at its limit (a left turn's limit, probed in a right
  /// turn), as `follow_up_profile` says: run ahead on a spare core beside the search's last probe
  /// (the one whose outcome ends the search), into `follow_up`.
  Lookahead* follow_up = nullptr;
  std::function<ConveyorProfile(double)> follow_up_profile = {};
  /// Probes run for this search before it asked (another search's follow_up): taken, not run.
  Lookahead* ran_before = nullptr;
};

struct AxisOutcome {
  std::optional<AxisLimit> limit;
  std::vector<Probe> probes;
  int ran_ahead = 0;    ///< probes run ahead on a spare core
  int speculative = 0;  ///< of those, the ones the search never needed
  std::optional<std::string> unstable;
  std::optional<std::string> batch_error;
  std::optional<std::string> error;  ///< an exception ended the search (out of memory, say)
};

// A failure at `time_s` placed in `profile`'s demand, from its first breakpoint (or the start) to
// its last (ProbeVerdict::failed_at).
double share_of_demand(const ConveyorProfile& profile, double time_s) {
  const std::vector<double> b = profile.breakpoints();
  const double begin = b.size() >= 2 ? b.front() : 0.0;
  const double end = b.empty() ? profile.duration_s : b.back();
  return end > begin ? std::max(0.0, (time_s - begin) / (end - begin)) : 1.0;
}

// What a search needs of a run: failed or not, the mode, how near it came.
// `profile`, where given: the probe's, whose demand a failure is placed in.
ProbeVerdict verdict_of(const SimResult& r, const ConveyorProfile* profile = nullptr) {
  ProbeVerdict v{r.outcome == Outcome::failed,
                 r.failure ? r.failure->mode : FailureMode::no_failure, r.peak_ratio};
  if (r.failure && profile != nullptr) v.failed_at = share_of_demand(*profile, r.failure->time_s);
  v.load_peak_ratio = r.load_peak_ratio;
  return v;
}

// `config`: the pallet the probe simulated (a symmetry-reduced one for a reduced model), whose
// items the failure's indices name.
Probe make_probe(Axis axis, double x, const SimResult& r, const PalletConfig& config) {
  Probe p{axis,
          x,
          r.outcome,
          r.failure ? r.failure->mode : FailureMode::no_failure,
          r.failure ? r.failure->time_s : 0.0,
          r.wall_ms,
          r.steps - r.steps_skipped,
          r.sim_time_s,
          r.peak_ratio};
  p.load_peak_ratio = r.load_peak_ratio;
  p.projected = r.failure && r.failure->projected;
  if (r.failure) p.slide = slide_kind(*r.failure, config);
  return p;
}

// Cores the searches of one envelope share, for speculative probes (SearchConfig::speculate): a
// search that would leave a core idle runs, beside its probe, the probe it takes next on one
// outcome of it. The search itself consumes probes exactly as the serial search does (its path,
// its limits and its probe list are the serial ones: each probe loads the whole rest state, so a
// probe is bitwise the same on any mjData); only the wall time depends on what ran ahead.
struct Cores {
  int total = 1;
  std::atomic<int> busy{0};  ///< axis searches running + speculative probes running
  /// What the memory budget (SearchConfig::axis_memory_bytes) leaves for more mjData: an axis
  /// thread's own simulator of a model, or a probe run ahead's.
  std::atomic<std::int64_t> spare_bytes{0};
  std::atomic<double> last_probe_ms{0.0};  ///< the wall time of the probe any search ended last

  // Takes `bytes` of the budget if they are left.
  bool reserve(std::int64_t bytes) {
    std::int64_t left = spare_bytes.load();
    while (left >= bytes) {
      if (spare_bytes.compare_exchange_weak(left, left - bytes)) return true;
    }
    return false;
  }
  void release(std::int64_t bytes) { spare_bytes += bytes; }
};

// The bytes an mjData of `simulator`'s model takes, as the memory budget counts them.
std::int64_t budget_bytes(const Simulator& simulator) {
  return std::int64_t(std::ceil(simulator.data_bytes()));
}

// Probes one search runs ahead of its path on spare cores (one axis thread uses it).
class Lookahead {
 public:
  /// `bytes`: what one more mjData of `scene` takes from the memory budget.
  Lookahead(Cores& cores, const Scene& scene, std::int64_t bytes, const RestState& rest,
            const SimOptions& o)
      : cores_(cores), scene_(scene), bytes_(bytes), rest_(rest), o_(o) {}
  ~Lookahead() {
    drain();
    const auto held = std::int64_t(idle_.size());
    idle_.clear();
    cores_.release(bytes_ * held);
  }
  Lookahead(const Lookahead&) = delete;
  Lookahead& operator=(const Lookahead&) = delete;

  // The result of the probe at x if it ran ahead (waiting for it if it is still running).
  std::optional<SimResult> take(double x) {
    if (auto f = flying_.find(x); f != flying_.end()) land(f);
    auto it = done_.find(x);
    if (it == done_.end()) return std::nullopt;
    SimResult r = std::move(it->second);
    done_.erase(it);
    ++used_;
    return r;
  }
  // Starts the probe at y (its profile `p`) on a spare core, beside the path's probe at x, for x
  // ending `failed`; false when no core or no mjData is to be had. A probe at y already run or
  // running is not started again. A probe the search will surely take (`needed`) starts on a busy
  // machine too: it only runs sooner.
  bool start(double x, bool failed, double y, const ConveyorProfile& p, bool needed = false) {
    if (!needed && cores_.total - cores_.busy.load() <= 0) return false;
    if (done_.contains(y) || flying_.contains(y)) return true;
    std::unique_ptr<Simulator> sim = simulator();
    if (!sim) return false;
    auto f = std::make_unique<Flight>();
    f->x = x;
    f->failed = failed;
    f->sim = std::move(sim);
    Flight* raw = f.get();
    SimOptions o = o_;
    o.abandon = &raw->abandon;
    ++cores_.busy;
    try {
      raw->thread = std::thread([this, raw, o, p] {
        try {
          raw->result = raw->sim->run(rest_, p, o);
        } catch (...) {  // the path runs it again if it needs it
          raw->result.reset();
        }
        --cores_.busy;
      });
    } catch (const std::system_error&) {  // no thread to be had: the path runs it
      --cores_.busy;
      idle_.push_back(std::move(f->sim));
      return false;
    }
    flying_.emplace(y, std::move(f));
    return true;
  }
  // The path's probe at x ended (failed or not): what ran ahead for the other outcome is dropped.
  void decided(double x, bool failed) {
    for (auto& [y, f] : flying_) {
      if (f->x == x && f->failed != failed) f->abandon = true;
    }
  }
  // Probes that ran ahead, and of those the ones never taken (after drain()).
  int started() const { return started_; }
  int wasted() const { return started_ - used_; }
  void drain() {
    for (auto& [y, f] : flying_) f->abandon = true;
    while (!flying_.empty()) land(flying_.begin());
  }

 private:
  struct Flight {
    double x = 0.0;       ///< the path's probe it ran beside
    bool failed = false;  ///< the outcome of that probe it assumed
    std::unique_ptr<Simulator> sim;
    CancelFlag abandon{false};
    std::optional<SimResult> result;
    std::thread thread;
  };
  using Flights = std::map<double, std::unique_ptr<Flight>>;

  std::unique_ptr<Simulator> simulator() {
    if (!idle_.empty()) {
      auto sim = std::move(idle_.back());
      idle_.pop_back();
      return sim;
    }
    if (!cores_.reserve(bytes_)) return nullptr;
    auto created = Simulator::create(scene_);
    if (!created) {
      cores_.release(bytes_);
      return nullptr;
    }
    return std::make_unique<Simulator>(std::move(*created.value));
  }
  // Joins a flight; keeps its result unless it was abandoned (a cancelled run has no verdict).
  void land(Flights::iterator f) {
    Flight& flight = *f->second;
    flight.thread.join();
    ++started_;
    if (flight.result && !flight.abandon) done_.emplace(f->first, std::move(*flight.result));
    idle_.push_back(std::move(flight.sim));
    flying_.erase(f);
  }

  Cores& cores_;
  const Scene& scene_;
  std::int64_t bytes_;
  const RestState& rest_;
  SimOptions o_;
  Flights flying_;
  std::map<double, SimResult> done_;
  std::vector<std::unique_ptr<Simulator>> idle_;
  int started_ = 0, used_ = 0;
};

// Runs one axis on `simulator` (serial probes) or, for k > 1, k probes a round in one batched call.
// With `cores` (k = 1 only), probes run ahead on spare cores (Lookahead).
// How the lowest failure above the outcome's limit (its mode is the limit's) went, among the
// outcome's probes: an item tipping over, the load sliding as one (Probe::slide).
void mark_slide(AxisOutcome& out) {
  const Probe* above = nullptr;
  for (const Probe& p : out.probes) {
    if (p.outcome == Outcome::failed && p.value > out.limit->limit &&
        (above == nullptr || p.value < above->value)) {
      above = &p;
    }
  }
  out.limit->slide = above != nullptr ? above->slide : SlideKind::item_slid;
}

// How near the probe at `x` came to failing: by any detector, and by the load's own.
struct Peaks {
  double any = 0.0, load = 0.0;
};

// The peaks of the probe at `x`: the last of `probes` there (confirmations aside), else as
// `known`; 0 where neither says.
Peaks peaks_at(const std::vector<Probe>& probes, const std::map<double, ProbeVerdict>& known,
               double x) {
  for (auto p = probes.rbegin(); p != probes.rend(); ++p) {
    if (p->value == x && !p->confirmation) return {p->peak_ratio, p->load_peak_ratio};
  }
  const auto it = known.find(x);
  if (it == known.end()) return {};
  return {it->second.peak_ratio, it->second.load_peak_ratio};
}

// A probe of `t` as the verdict a later search of the axis knows it by: where the walk hastens
// (AxisTask::hasten), with how far into its demand it failed.
ProbeVerdict known_verdict(const AxisTask& t, const Probe& p) {
  ProbeVerdict v{p.outcome == Outcome::failed, p.mode, p.peak_ratio};
  if (v.failed && t.hasten) v.failed_at = share_of_demand(t.profile(p.value), p.failure_time_s);
  v.load_peak_ratio = p.load_peak_ratio;
  return v;
}

// `x`, where a search of the axis failed (its own probe, or one along the other numerical path
// where the probe itself held): failed in `known`, keeping the probe's verdict where it failed.
void mark_failed(std::map<double, ProbeVerdict>& known, double x, FailureMode mode) {
  ProbeVerdict& v = known[x];
  if (!v.failed) v = ProbeVerdict{true, mode, 1.0};
}

AxisOutcome search_axis(const AxisTask& t, Simulator& simulator, const RestState& rest,
                        const SimOptions& o, const SearchConfig& s, int k, Cores* cores) {
  const bool seeded = s.seed_with_closed_form;
  AxisOutcome out;
  auto unstable_at = [&](double x, const SimResult& r) {
    if (!out.unstable) {
      out.unstable = std::string(to_string(t.axis)) + " probe at " + fixed(x, 3) + ": " + r.reason;
    }
  };
  // This search holds a core while it runs (cores->busy); what it ran ahead ends with it.
  struct Holding {
    Cores* cores;
    explicit Holding(Cores* c) : cores(c) {
      if (cores) ++cores->busy;
    }
    ~Holding() {
      if (cores) --cores->busy;
    }
    Holding(const Holding&) = delete;
    Holding& operator=(const Holding&) = delete;
  } holding(k == 1 ? cores : nullptr);
  std::unique_ptr<Lookahead> ahead;
  if (holding.cores) {
    ahead =
        std::make_unique<Lookahead>(*cores, simulator.scene(), budget_bytes(simulator), rest, o);
  }
  // Results that exist (ran ahead and finished, or given), for the search's dry runs.
  std::map<double, ProbeVerdict> known = t.known;
  // The run that failed earliest into the axis (AxisTask::same_until), and the lowest value from
  // which every probe is that run up to its failure: each fails as it did, unsimulated.
  // A run's verdict at x, its failure placed in x's demand where the walk hastens.
  auto verdict_at = [&](double x, const SimResult& r) {
    if (!t.hasten) return verdict_of(r);
    const ConveyorProfile profile = t.profile(x);
    return verdict_of(r, &profile);
  };
  std::optional<SimResult> implying;
  double implied_from = std::numeric_limits<double>::infinity();
  auto note_failure = [&](double x, const SimResult& r) {
    if (!t.same_until || !r.failure) return;
    const double from = t.same_until(r.failure->time_s);
    if (from > x || from >= implied_from) return;  // failed after its demand: no same run above
    implied_from = from;
    implying = r;
  };
  auto implied = [&](double y) -> std::optional<ProbeVerdict> {
    if (!implying || y < implied_from) return std::nullopt;
    return verdict_at(y, *implying);
  };
  // The axis's search on verdicts from `probe` (and `batch`, k at a time).
  auto searching = [&](AxisSearch::ProbeFn probe_fn, AxisSearch::BatchFn batch_fn = {},
                       int per_round = 1) {
    return AxisSearch(t.lo, t.hi, t.precision, std::move(probe_fn), seeded, t.vouch,
                      std::move(batch_fn), per_round, s.band_checks);
  };
  // The search run again without simulating, on what is known and x ending `failed`: the first
  // probe it does not know (`next`), or, where it knows every probe it takes, its limit.
  struct DryRun {
    std::optional<double> next;
    std::optional<AxisLimit> limit;
  };
  auto dry_run = [&](double x, bool failed) {
    DryRun dry;
    auto oracle = [&](double y) -> std::optional<ProbeVerdict> {
      if (y == x) return ProbeVerdict{failed, FailureMode::no_failure, 1.0};
      if (auto it = known.find(y); it != known.end()) return it->second;
      if (auto v = implied(y)) return v;
      dry.next = y;
      return std::nullopt;
    };
    auto limit = searching(oracle).run(t.seed);
    if (!dry.next) dry.limit = limit;
    return dry;
  };
  // Before the path's probe at x: on spare cores, the probe the search takes next on each outcome
  // of x (failed first), or, where that outcome ends the search with a limit, the probe that
  // follows the search there (AxisTask::follow_up).
  auto run_ahead = [&](double x) {
    for (const bool failed : {true, false}) {
      const DryRun dry = dry_run(x, failed);
      if (dry.next) {
        if (*dry.next != x && !ahead->start(x, failed, *dry.next, t.profile(*dry.next))) return;
      } else if (t.follow_up && dry.limit && !dry.limit->at_floor) {
        const double y = dry.limit->at_ceiling ? t.hi : dry.limit->limit;
        if (!t.follow_up->start(x, failed, y, t.follow_up_profile(y))) return;
      }
    }
  };
  auto probe = [&](double x) -> std::optional<ProbeVerdict> {
    std::optional<SimResult> ran = ahead ? ahead->take(x) : std::nullopt;
    if (!ran && t.ran_before) ran = t.ran_before->take(x);
    if (!ran) {
      // Only where a probe costs more than a thread and an mjData for it: the last probe of any
      // axis tells (SearchConfig::speculate_after_ms).
      if (ahead && cores->last_probe_ms.load() >= s.speculate_after_ms) {
        run_ahead(x);
      }
      ran = simulator.run(rest, t.profile(x), o);
      if (ahead) {
        ahead->decided(x, ran->outcome == Outcome::failed);
        if (t.follow_up) t.follow_up->decided(x, ran->outcome == Outcome::failed);
        cores->last_probe_ms = ran->wall_ms;
      }
    }
    const SimResult& r = *ran;
    if (o.progress != nullptr) o.progress->finished();
    const ProbeVerdict verdict = verdict_at(x, r);
    if (r.outcome != Outcome::unstable) known[x] = verdict;
    note_failure(x, r);
    out.probes.push_back(make_probe(t.axis, x, r, simulator.scene().config));
    if (r.outcome == Outcome::unstable) {
      unstable_at(x, r);
      return std::nullopt;
    }
    return verdict;
  };
  auto batch = [&](const std::vector<double>& xs) -> std::optional<std::vector<ProbeVerdict>> {
    std::vector<ConveyorProfile> profiles;
    for (double x : xs) profiles.push_back(t.profile(x));
    auto runs = run_probes_batched(simulator.scene(), rest, profiles, o, k);
    if (!runs) {
      out.batch_error =
          std::string(to_string(t.axis)) + " probes: " +
          (runs.diagnostics.empty() ? std::string("unknown error") : runs.diagnostics[0].message);
      return std::nullopt;
    }
    std::vector<ProbeVerdict> verdicts;
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const SimResult& r = (*runs.value)[i];
      out.probes.push_back(make_probe(t.axis, xs[i], r, simulator.scene().config));
      if (r.outcome == Outcome::unstable) unstable_at(xs[i], r);
      verdicts.push_back(verdict_at(xs[i], r));
      note_failure(xs[i], r);
    }
    if (out.unstable) return std::nullopt;
    return verdicts;
  };
  // The path's verdicts (`known`), for a search that goes on below a limit that did not hold
  // along another numerical path (`failing` then holds that limit).
  std::map<double, ProbeVerdict> failing;
  auto remembered = [&](double x) -> std::optional<ProbeVerdict> {
    if (auto it = failing.find(x); it != failing.end()) return it->second;
    if (auto it = known.find(x); it != known.end()) return it->second;
    if (auto v = implied(x)) return v;
    return probe(x);
  };
  out.limit = searching(remembered, batch, k).run(t.seed);
  if (ahead) {
    ahead->drain();
    out.ran_ahead = ahead->started();
    out.speculative = ahead->wasted();
    ahead.reset();  // the confirmation's probes run on the path
  }
  SimOptions twin = o;
  twin.extrapolate_warmstart = true;
  // Every limit (SearchConfig::confirm_limits), or that of a load whose items can move (t.vouch)
  // whose own probe came near failing.
  auto confirmed = [&](double x) {
    return s.confirm_limits ||
           (t.vouch && peaks_at(out.probes, known, x).any >= s.confirm_from_peak);
  };
  bool confirming = false;
  while (out.limit && !out.limit->at_floor && confirmed(out.limit->limit)) {
    confirming = true;
    const double x = out.limit->limit;
    const SimResult r = simulator.run(rest, t.profile(x), twin);
    if (o.progress != nullptr) o.progress->finished();
    out.probes.push_back(make_probe(t.axis, x, r, simulator.scene().config));
    out.probes.back().confirmation = true;
    if (r.outcome == Outcome::unstable) {
      unstable_at(x, r);
      out.limit.reset();
      break;
    }
    if (r.outcome != Outcome::failed) break;
    failing[x] = verdict_at(x, r);
    out.limit = searching(remembered).run(x);
  }
  // A search after a confirmation counts what it looked up again: the axis's simulations are
  // this search's runs.
  if (out.limit && confirming) out.limit->probes = int(out.probes.size());
  if (out.limit) {
    out.limit->closed_form = t.closed_form;
    mark_slide(out);
  }
  return out;
}

int resolved_threads(int requested) {
  return requested == 0 ? std::max(1, int(std::thread::hardware_concurrency())) : requested;
}

}  // namespace

namespace {

// Adds the probes and counters of `more` (run after `into`'s) to `into`.
void add_probes(AxisOutcome& into, const AxisOutcome& more) {
  into.probes.insert(into.probes.end(), more.probes.begin(), more.probes.end());
  into.ran_ahead += more.ran_ahead;
  into.speculative += more.speculative;
}

// `into` followed by `next`, a search run after it: next's probes added, and its answer (its
// limit, or why it has none) taken.
void continue_with(AxisOutcome& into, const AxisOutcome& next) {
  add_probes(into, next);
  into.limit = next.limit;
  into.unstable = next.unstable;
  into.batch_error = next.batch_error;
  into.error = next.error;
}

// Where the axis searched as `t` is checked below its pallet's slip onset (0.98 of it, above the
// axis's floor), or nullopt.
std::optional<double> belt_check(const AxisTask& t) {
  const double check = kConeSaturated * t.belt_onset;
  if (t.belt_onset <= 0.0 || check <= t.lo) return std::nullopt;
  return check;
}

// The one probe of `t` at `x`, as a search of its own.
template <typename Run>
AxisOutcome probe_at(const AxisTask& t, double x, const Run& run) {
  AxisTask at = t;
  at.lo = at.hi = at.seed = x;
  at.follow_up = nullptr;  // a check's limit is not the axis's
  return run(at);
}

// The band a check that held but came near failing is followed up in, as shares of the pallet's
// onset: above the check, up to the breakaway. While the pallet holds its load feels nearly the
// most the pallet passes on, for as long as the demand lasts; a load that came near failing there
// fails and holds by turns across the band (docs/studies/unwrapped-holdout: two columns of six
// cartons hold at 0.98 and 0.99 of their pallet's onset with peak ratios 0.54 and 0.55, and fail at
// 0.985, 0.995 and 1.0; on 45 pallets, each of the five checks that held near failing has a failure
// there, and two that held by a margin fail at a single point of it: core/README). Near failing
// by the load's own detectors (SimResult::load_peak_ratio): a pallet that came near slipping its
// allowance slips more above the check, where the search finds it.
constexpr double kBreakawayBand[] = {0.985, 0.99, 0.995};

// The failure a check's follow-up found in the breakaway band.
struct BandFailure {
  double at;
  FailureMode mode;
};

// `a` holding at the check of `t` (belt_check) with its load's peak ratio `peak`, for an answer
// `limit` above it (infinite: not known yet): where the load came near failing (kNearFailure), the
// band above it below `limit` (kBreakawayBand) is probed, in order, until a probe fails; each probe
// is added to `a`. The first failure, or nullopt (the band held, or no follow-up was due, or a
// probe was unstable: `a` then has no limit).
template <typename Run>
std::optional<BandFailure> probe_breakaway_band(const AxisTask& t, double peak, double limit,
                                                AxisOutcome& a, const Run& run) {
  if (peak < kNearFailure) return std::nullopt;
  for (const double share : kBreakawayBand) {
    const double x = share * t.belt_onset;
    if (x >= limit || x > t.hi) break;
    const AxisOutcome b = probe_at(t, x, run);
    if (!b.limit) {
      continue_with(a, b);
      return std::nullopt;
    }
    add_probes(a, b);
    if (b.limit->at_floor) return BandFailure{x, b.limit->mode};
  }
  return std::nullopt;
}

// `a`, the outcome of the axis searched as `t` (its whole range, its seed, its turn), checked below
// the pallet's slip onset on its belt (search_envelope): a limit above 0.98 of the onset
// (kConeSaturated: there the pallet holds, or has barely begun to slip, and its load feels nearly
// the most the pallet can pass on) stands if the load holds there; where it fails there, the axis
// is searched below it, on what the first search learnt. `run` runs a search.
template <typename Run>
AxisOutcome guard_below_belt_onset(const AxisTask& t, AxisOutcome a, const Run& run) {
  const std::optional<double> checked_at = belt_check(t);
  if (!a.limit || !checked_at || a.limit->limit <= *checked_at) return a;
  const double check = *checked_at;
  const AxisLimit above = *a.limit;
  const std::size_t first = a.probes.size();
  const AxisOutcome c = probe_at(t, check, run);
  BandFailure failure{check, FailureMode::no_failure};
  if (c.limit && !c.limit->at_floor) {  // it holds there: the limit above stands, band permitting
    add_probes(a, c);
    const auto band =
        probe_breakaway_band(t, peaks_at(c.probes, t.known, check).load, above.limit, a, run);
    if (!a.limit) return a;  // unstable, or an error: the axis has no limit
    if (!band) {
      a.limit->probes = above.probes + int(a.probes.size() - first);
      return a;
    }
    failure = *band;
  } else {
    continue_with(a, c);
    if (!a.limit) return a;
    failure.mode = c.limit->mode;
  }
  AxisTask below = t;
  below.hi = failure.at;
  below.seed = std::min(t.seed, failure.at);
  for (const Probe& p : a.probes) {  // what the searches and checks found up to the failure
    if (p.value <= failure.at && !p.confirmation) below.known[p.value] = known_verdict(t, p);
  }
  mark_failed(below.known, failure.at, failure.mode);
  continue_with(a, run(below));
  if (a.limit) {
    a.limit->closed_form = above.closed_form;
    a.limit->probes = above.probes + int(a.probes.size() - first);
    mark_slide(a);
  }
  return a;
}

// The axis searched as `t` and checked below the pallet's slip onset (guard_below_belt_onset).
// Where its search starts above that check (a load its pallet carries: seeded from the pallet's
// slide), the check runs first, so a load that fails there (a tall brick that shifts long before
// its pallet slips) is searched below it at once, not after a search above it whose answer would
// not stand; one that holds there is searched from its seed knowing so. Elsewhere, and in the
// reference's plain bisection (`seeded` false: the judge's search is its own), the search runs
// first and is checked after, only if it ends above the check. `on_check`, where given, hears
// whether the load held at a check run first, as soon as it is known.
template <typename Run>
AxisOutcome checked_below_belt_onset(const AxisTask& t, bool seeded, const Run& run,
                                     const std::function<void(bool)>& on_check = {}) {
  const std::optional<double> checked_at = belt_check(t);
  if (!seeded || !checked_at || t.seed <= *checked_at || t.known.count(*checked_at) > 0) {
    return guard_below_belt_onset(t, run(t), run);
  }
  const double check = *checked_at;
  AxisOutcome a = probe_at(t, check, run);
  if (!a.limit) return a;  // unstable, or an error: the axis has no limit
  std::optional<BandFailure> failure;
  if (a.limit->at_floor) {
    failure = BandFailure{check, a.limit->mode};
  } else {
    failure = probe_breakaway_band(t, peaks_at(a.probes, t.known, check).load,
                                   std::numeric_limits<double>::infinity(), a, run);
    if (!a.limit) return a;
  }
  const int checked = int(a.probes.size());
  if (on_check) on_check(!failure);
  AxisTask then = t;
  for (const Probe& p : a.probes) {  // the check and the band: known
    if (!p.confirmation) then.known[p.value] = known_verdict(t, p);
  }
  if (failure) {  // it fails there: the axis is searched below
    then.hi = then.seed = failure->at;
    mark_failed(then.known, failure->at, failure->mode);
  } else if (t.seed - check <= 0.5 * t.precision) {
    // A seed within half a step above the check starts there: the check is its probe (a curve's
    // seed for a load its pallet carries sits a hair above 0.98 of the onset: top-heavy-surprise's
    // 0.3259 g over its check's 0.3241).
    then.seed = check;
  }
  continue_with(a, run(then));
  if (a.limit) {
    a.limit->probes += checked;
    mark_slide(a);
  }
  return a;
}

}  // namespace

Result<Envelope> search_envelope(Simulator& simulator, const RestState& rest,
                                 const QuasiStaticBounds& bounds, const LineDescription& line,
                                 const SearchConfig& s, const SimOptions& sim_options) {
  const ProbeModel model{&simulator, &rest};
  return search_envelope(model, model, simulator.scene().config, bounds, line, s, sim_options);
}

Result<Envelope> search_envelope(const ProbeModel& along_model, const ProbeModel& across_model,
                                 const PalletConfig& config, const QuasiStaticBounds& bounds,
                                 const LineDescription& line, const SearchConfig& s,
                                 const SimOptions& sim_options, const AxisFound& found) {
  const auto start = std::chrono::steady_clock::now();
  Envelope env;
  env.rest = *along_model.rest;
  auto model_of = [&](Axis axis) { return axis == Axis::lateral ? across_model : along_model; };
  SimOptions o = sim_options;
  o.record_trace = false;
  o.fail_fast = true;
  if (s.parallel_probes < 0) {
    return Result<Envelope>::failure(
        "/search/parallel_probes",
        "must be 0 (one per free core), 1 (serial bisection) or more, not " +
            std::to_string(s.parallel_probes));
  }
  if (s.axis_threads < 0) {
    return Result<Envelope>::failure(
        "/search/axis_threads",
        "must be 0 (one per axis), 1 (one axis after another) or more, not " +
            std::to_string(s.axis_threads));
  }
  const int k = resolved_threads(s.parallel_probes);

  const QuasiStaticLimit along = bounds.weakest_along();
  // Speed: the fastest speed from which the line's e-stop is survived. Below the quasi-static
  // bound nothing slides and any speed is safe; above it the slide grows with v^2.
  double speed_seed = s.speed_max_mps;
  if (line.estop_decel_mps2 > along.accel_mps2) {
    speed_seed = along.mode == FailureMode::tip_over
                     ? s.speed_min_mps
                     : estop_slide_speed_mps(along, line, o.thresholds);
  }
  // Each axis is searched on its own. A load that moves as one body (a wrapped load: its only
  // mechanisms are the pallet slipping and the whole load tipping) fails monotonically, so its
  // search starts where the closed form predicts the probe fails (half a step below, so that an
  // exact prediction brackets the limit in two probes; at the ceiling when nothing is predicted to
  // fail in range). A load whose items can slide and rock may fail in bands (tall-unwrapped and
  // top-heavy loads do): its search walks up from just above the weakest onset, so the first
  // failure above the onset is the one it finds.
  //
  // The walk up starts one step above the weakest onset, or where the rigid-body prediction of
  // any mechanism says the probe fails if that is lower: a curve holds its demand for the whole
  // arc, so a Coulomb slide reaches its allowance there a thousandth of a g above the onset, and a
  // search from one step above it would first walk down. That prediction is the earliest any
  // rigid body could fail (Coulomb's slide, breaking loose at once), so the walk starts low;
  // a search from a prediction (the pallet's slide) starts at the simulation's own friction law's,
  // where its probes bracket the limit soonest.
  const AxisPredictions predicted = predict_envelope(bounds, line, s, o.thresholds);
  const AxisPredictions rigid = rigid_predictions(bounds, line, s, o.thresholds);
  const AxisPredictions earliest = rigid_predictions(bounds, line, s, o.thresholds, 0.0);
  const bool one_body = bounds.one_body();
  // Where no mechanism of the load can act below the pallet's slip (carried), the pallet's slide
  // fails it as it does a load that moves as one body, monotonically: searched from its
  // prediction, with no check below a safe seed (the load below the pallet's onset is checked
  // once, guard_below_belt_onset).
  auto walks = [&](const AxisPrediction& p) {
    return !one_body && p.mode != FailureMode::pallet_slip;
  };
  auto seed = [&](const AxisPrediction& p, const AxisPrediction& r, const AxisPrediction& e,
                  double hi, double precision) {
    if (walks(p)) return std::min(p.value + precision, e.value);
    const double at = one_body ? p.value : r.value;
    return at >= hi ? hi : at - 0.5 * precision;
  };
  // The e-stop speed axis is one experiment cut at different times (AxisTask::same_until); taken
  // where axes may be answered from the physics (derive_axes), while the judge simulates them.
  std::function<double(double)> estop_same_until;
  if (s.derive_axes) {
    estop_same_until = [&](double t) {
      return line.estop_decel_mps2 * std::max(0.0, t - kSettleLead);
    };
  }
  // A load whose items can move is carried by its pallet, and friction cannot push the pallet
  // harder than its belt holds it: past the pallet's slip onset the load feels at most that onset
  // while the pallet breaks loose and mu_d g while it slides. So an item that fails at a demand
  // between its own onset and the pallet's may hold at any demand above the pallet's: a limit the
  // search finds above that onset is checked just below it (guard_below_belt_onset). A load that
  // moves as one body is searched from its closed form, which names its lowest failure.
  const double along_onset = one_body ? 0.0 : belt_onset_mps2(bounds.along);
  const double across_onset =
      one_body ? 0.0 : belt_onset_mps2(in_a_curve(bounds.across, line.curve_radius_m)) / kGravity;
  std::vector<AxisTask> tasks{
      {Axis::accel,
       s.accel_min_mps2,
       s.accel_max_mps2,
       s.accel_precision_mps2,
       seed(predicted.accel, rigid.accel, earliest.accel, s.accel_max_mps2, s.accel_precision_mps2),
       predicted.accel.value,
       [&](double a) { return accel_probe_profile(a, s); },
       {},
       walks(predicted.accel),
       s.hasten_walk,
       {},
       along_onset},
      {Axis::decel,
       s.decel_min_mps2,
       s.decel_max_mps2,
       s.decel_precision_mps2,
       seed(predicted.decel, rigid.decel, earliest.decel, s.decel_max_mps2, s.decel_precision_mps2),
       predicted.decel.value,
       [&](double d) { return decel_probe_profile(d, s.speed_max_mps, s); },
       {},
       walks(predicted.decel),
       s.hasten_walk,
       {},
       along_onset},
      {Axis::lateral,
       s.lateral_min_g,
       s.lateral_max_g,
       s.lateral_precision_g,
       seed(predicted.lateral, rigid.lateral, earliest.lateral, s.lateral_max_g,
            s.lateral_precision_g),
       predicted.lateral.value,
       [&](double g) { return lateral_probe_profile(g, line, s); },
       {},
       walks(predicted.lateral),
       s.hasten_walk,
       {},
       across_onset},
      {Axis::speed,
       s.speed_min_mps,
       s.speed_max_mps,
       s.speed_precision_mps,
       speed_seed,
       speed_seed,
       [&](double v) { return stop_probe_profile(v, line, s); },
       {},
       false,  // one experiment cut at different times (same_until): failure is monotone in v
       s.hasten_walk,
       estop_same_until,
       0.0},  // the e-stop's deceleration is the line's: no higher demand is probed
  };
  // The reduced level merges a wrapped load rigidly into its pallet, which then holds on its static
  // cone up to mu_s g in a curve; the real load sways into its wrap as the curve's demand steps
  // on, which breaks the pallet loose lower (the full model and the reference do). So its curve is
  // searched no higher than where a pallet loose from the arc's entry slides its allowance
  // (loose_at_entry_g), and a limit held there fails above it by that slip.
  bool lateral_capped = false;
  if (config.wrap != WrapType::none && across_model.simulator->scene().layout.merged) {
    if (const double cap = loose_at_entry_g(bounds, line, s, o.thresholds); cap < tasks[2].hi) {
      tasks[2].hi = std::max(cap, tasks[2].lo);
      tasks[2].seed = std::min(tasks[2].seed, tasks[2].hi);
      lateral_capped = true;
    }
  }
  // An axis's outcome as the envelope takes it: the capped curve's limit held at its cap fails
  // above it.
  auto capped = [&](std::size_t i, AxisOutcome a) {
    if (tasks[i].axis == Axis::lateral && lateral_capped && a.limit && a.limit->at_ceiling) {
      a.limit->at_ceiling = false;
      a.limit->mode = FailureMode::pallet_slip;
      a.limit->loose_at_entry = true;
    }
    return a;
  };
  std::vector<AxisOutcome> outcomes(tasks.size());
  // Derived axes (see the header): the stop of a mirror-symmetric load waits for the start-up
  // search and the e-stop speed for the stop search; each is searched only if it cannot be taken.
  const bool mirror = s.derive_axes && s.accel_min_mps2 == s.decel_min_mps2 &&
                      s.accel_max_mps2 == s.decel_max_mps2 &&
                      s.accel_precision_mps2 == s.decel_precision_mps2 &&
                      mirror_symmetric_along(config);
  // A load whose items its pallet carries past the pallet's slip onset both ways (no mechanism of
  // an item below that onset along the belt, `carried`) fails a start-up and a stop alike once its
  // pallet slips: one body sliding on isotropic Coulomb friction, under the same pulse mirrored.
  // Its stop is taken from a start-up limit whose pallet slipped, on the same thread right after
  // it, and checked only below the pallet's onset, where an item of a load that is not its own
  // mirror image may fail one way and not the other (guard_below_belt_onset).
  const bool slips_both_ways =
      s.derive_axes && !mirror && along_onset > 0.0 && s.accel_min_mps2 == s.decel_min_mps2 &&
      s.accel_max_mps2 == s.decel_max_mps2 && s.accel_precision_mps2 == s.decel_precision_mps2 &&
      !walks(predicted.accel) && !walks(predicted.decel);
  const bool from_stop = s.derive_axes && line.estop_decel_mps2 >= s.decel_min_mps2 &&
                         line.estop_decel_mps2 <= s.decel_max_mps2;
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const bool after_start_up = (mirror || slips_both_ways) && tasks[i].axis == Axis::decel;
    if (!after_start_up && !(from_stop && tasks[i].axis == Axis::speed)) order.push_back(i);
  }
  // Progress: a search plans kProbesPerSearch (the curated and corpus searches take 3-5).
  if (o.progress != nullptr) o.progress->plan(kProbesPerSearch * int(order.size()));
  // The stop of a load that slips both ways follows its start-up (stop_after) unless the
  // start-up fails its check below the pallet's onset: then it cannot end in the pallet's slip, and
  // the stop is searched in full, beside it, by a thread of its own (a 96-carton brick shifts below
  // its pallet's onset both ways: its start-up takes 7 probes and its stop 9).
  const int axes = int(order.size()) + (slips_both_ways ? 1 : 0);
  const int threads = s.axis_threads == 0 ? axes : std::min(s.axis_threads, axes);
  // Memory: an axis thread other than the calling one, and a probe run ahead, each need an mjData
  // of their own for their model, and a large load's is tens of MB resident (hundreds before
  // make_data shared MuJoCo 2.2's njmax x njmax matrix). Every mjData the searches hold counts
  // against axis_memory_bytes, the models' own included (the calling thread searches on those): a
  // thread takes an axis whose model it has, or whose mjData the budget still holds, and the
  // calling thread takes any. So a 96-carton brick, whose whole model's mjData took 466 MB (77 MB
  // now) and its third along the belt 37 MB, searched its curve on the calling thread while
  // another thread searched along the belt, where it took one axis after another when every
  // thread was counted at the largest model.
  Cores cores;
  cores.total = resolved_threads(0);
  cores.spare_bytes =
      std::int64_t(s.axis_memory_bytes) - budget_bytes(*along_model.simulator) -
      (across_model.simulator == along_model.simulator ? 0 : budget_bytes(*across_model.simulator));
  // Probes run ahead on spare cores, with as many more mjData as the memory budget holds.
  Cores* ahead = s.speculate && k == 1 && s.axis_threads != 1 && cores.total > 1 ? &cores : nullptr;
  // The calling thread, which alone holds the models' own mjData, takes the axes of the largest
  // model first: the budget may hold no other mjData of it (a 96-carton load's curve), and had the
  // caller taken the start-up first, the curve would wait for it.
  std::vector<std::size_t> by_size(order.size());
  std::iota(by_size.begin(), by_size.end(), std::size_t{0});
  auto bytes_of = [&](Axis axis) { return budget_bytes(*model_of(axis).simulator); };
  std::stable_sort(by_size.begin(), by_size.end(), [&](std::size_t a, std::size_t b) {
    return bytes_of(tasks[order[a]].axis) > bytes_of(tasks[order[b]].axis);
  });
  // What the other axis threads take from the budget: an mjData for each axis but the caller's
  // first, and one for the stop of a load that slips both ways. A probe run from the start takes
  // only what is left after them: until session 24 the stop's check took its mjData first, and a
  // 70-carton random pallet (one 234 MB model) left no room for a second axis thread: 99 s on one
  // core.
  std::int64_t for_threads = slips_both_ways ? bytes_of(Axis::decel) : 0;
  for (std::size_t pos = 1; pos < by_size.size(); ++pos) {
    for_threads += bytes_of(tasks[order[by_size[pos]]].axis);
  }
  // The stop of a load that slips both ways is checked below its pallet's onset whatever its
  // start-up finds (mirrored from it, or searched from the check up or down): that probe runs from
  // the start, beside the searches, for the stop's search to take.
  std::optional<Lookahead> stop_check;
  if (const std::optional<double> check = belt_check(tasks[1]);
      slips_both_ways && ahead != nullptr && check && s.seed_with_closed_form &&
      cores.spare_bytes.load() - for_threads >= bytes_of(Axis::decel)) {
    const ProbeModel m = model_of(Axis::decel);
    stop_check.emplace(cores, m.simulator->scene(), budget_bytes(*m.simulator), *m.rest, o);
    stop_check->start(*check, false, *check, tasks[1].profile(*check), true);
    tasks[1].ran_before = &*stop_check;
  }
  // Tells `found` of a start-up, stop or curve limit as soon as it is known.
  auto tell = [&](Axis axis, const AxisOutcome& a) {
    if (found && a.limit && axis != Axis::speed) found(axis, *a.limit);
  };
  // A curve turning left pushes the load towards -Y, one turning right towards +Y: a load that is
  // not its own mirror image across the belt (a column off the centre line, a heavier side) may
  // go over in one turn and not the other, and the line turns both ways. Its lateral search runs
  // in a left turn, then in a right one from the left limit down (one probe when the right turn
  // holds there); the limit is the lower, with the mode and turn of the one that fails above it.
  const bool both_turns = curve_turns(config).size() > 1;
  // A search of one task on `simulator` from `rest`.
  auto searcher = [&](Simulator& simulator, const RestState& rest) {
    return [&, sim = &simulator, from = &rest](const AxisTask& task) {
      return search_axis(task, *sim, *from, o, s, k, ahead);
    };
  };
  // Where the stop of a load that slips both ways stands (stop_after, and the threads' claims).
  struct StopAfterStartUp {
    std::mutex mutex;  ///< also the threads' claims on axes
    std::condition_variable changed;
    bool released = false;  ///< the start-up failed its check: the stop is searched in full
    bool taken = false;     ///< a thread has the stop
    bool start_up_done = false;
  } stop;
  std::function<void(bool)> on_start_up_check;
  if (slips_both_ways) {
    on_start_up_check = [&](bool held) {
      if (held) return;
      {
        const std::lock_guard lock(stop.mutex);
        stop.released = true;
      }
      stop.changed.notify_all();
    };
  }
  auto run_task = [&](std::size_t i, Simulator& simulator, const RestState& rest) {
    const auto run = searcher(simulator, rest);
    const bool turns = tasks[i].axis == Axis::lateral && both_turns;
    auto right_profile = [&](double g) {
      return lateral_probe_profile(g, line, s, CurveTurn::right);
    };
    // The right turn's first probe, at the left limit, runs on a spare core beside the left
    // search's last probe.
    std::optional<Lookahead> follow_up;
    AxisTask left = tasks[i];
    if (turns && ahead != nullptr) {
      follow_up.emplace(*ahead, simulator.scene(), budget_bytes(simulator), rest, o);
      left.follow_up = &*follow_up;
      left.follow_up_profile = right_profile;
    }
    // What ran ahead for the right turn, counted with the left turn's probes run ahead.
    auto counted = [&](AxisOutcome& out) -> AxisOutcome& {
      if (follow_up) {
        follow_up->drain();
        out.ran_ahead += follow_up->started();
        out.speculative += follow_up->wasted();
        follow_up.reset();
      }
      return out;
    };
    AxisOutcome a =
        checked_below_belt_onset(left, s.seed_with_closed_form, run,
                                 tasks[i].axis == Axis::accel ? on_start_up_check : nullptr);
    if (!turns || !a.limit || a.limit->at_floor) return counted(a);
    // First the left limit itself; where the right turn fails there, a search below it from the
    // closed-form seed, as the left one started (the right turn's verdict at the top known).
    AxisTask right = tasks[i];
    right.hi = a.limit->at_ceiling ? right.hi : a.limit->limit;
    right.lo = right.seed = right.hi;
    right.profile = right_profile;
    if (follow_up) right.ran_before = &*follow_up;
    auto search_right = [&](const AxisTask& task) {
      AxisOutcome r = run(task);
      for (Probe& p : r.probes) p.turn = CurveTurn::right;
      return r;
    };
    AxisOutcome b = search_right(right);
    if (b.limit && b.limit->at_floor && right.hi > tasks[i].lo) {
      for (const Probe& p : b.probes) {
        if (!p.confirmation) right.known[p.value] = known_verdict(right, p);
      }
      mark_failed(right.known, right.hi, b.limit->mode);
      right.lo = tasks[i].lo;
      right.seed = std::min(tasks[i].seed, right.hi);
      continue_with(b, search_right(right));
    }
    // The right turn checked below the pallet's onset too, over the axis's whole range.
    AxisTask right_axis = tasks[i];
    right_axis.profile = right.profile;
    b = guard_below_belt_onset(right_axis, std::move(b), search_right);
    counted(b);
    if (!b.limit) {  // unstable, or an error: the axis has no limit
      continue_with(a, b);
      return a;
    }
    add_probes(a, b);
    const int probes = a.limit->probes + int(b.probes.size());  // the right turn's simulations
    if (!b.limit->at_ceiling) {  // the right turn fails below the left's limit: it governs
      const double closed_form = a.limit->closed_form;
      a.limit = b.limit;
      a.limit->closed_form = closed_form;
      a.limit->turn = CurveTurn::right;
    }
    a.limit->probes = probes;
    return a;
  };
  // Whether every start-up probe was a whole pulse (it reached speed_max within max_ramp_s), as
  // every stop probe is: only then is a start-up's outcome a stop's mirrored.
  auto pulses = [&](const AxisOutcome& up) {
    const double full_ramp = s.speed_max_mps / s.max_ramp_s;  // the slowest a ramp reaches speed
    return std::all_of(up.probes.begin(), up.probes.end(),
                       [&](const Probe& p) { return p.value >= full_ramp; });
  };
  // The stop as the start-up's mirror: its limit, not probed.
  auto mirrored = [&](const AxisOutcome& up) {
    AxisOutcome down;
    down.limit = up.limit;
    down.limit->closed_form = tasks[1].closed_form;
    down.limit->probes = 0;
    down.limit->derived = true;
    return down;
  };
  // The stop of a load that slips both ways, from the start-up's outcome `up` (which has a limit):
  // mirrored where the pallet's slip governs it, checked below the pallet's onset; searched
  // otherwise.
  auto stop_after_slip = [&](const AxisOutcome& up, Simulator& simulator, const RestState& rest) {
    if (up.limit->mode != FailureMode::pallet_slip || up.limit->at_floor || !pulses(up)) {
      if (o.progress != nullptr) o.progress->plan(kProbesPerSearch);
      return run_task(1, simulator, rest);
    }
    return guard_below_belt_onset(tasks[1], mirrored(up), searcher(simulator, rest));
  };
  // Searches axis task i on `simulator` (of its plane's model) from `rest` into outcomes[i], and
  // tells of its limit.
  auto search = [&](std::size_t i, Simulator& simulator, const RestState& rest) {
    outcomes[i] = capped(i, run_task(i, simulator, rest));
    tell(tasks[i].axis, outcomes[i]);
  };
  // The stop of a load that slips both ways follows its start-up on the same model and thread.
  // Where another thread took the stop once the start-up failed its check, nothing is left here.
  auto stop_after = [&](std::size_t i, Simulator& simulator, const RestState& rest) {
    if (!slips_both_ways || tasks[i].axis != Axis::accel) return false;
    bool mine = false;
    {
      const std::lock_guard lock(stop.mutex);
      // An unstable start-up fails the envelope: no stop is searched for it.
      mine = !stop.taken && outcomes[i].limit.has_value();
      stop.taken = stop.taken || mine;
    }
    if (!mine) return false;
    stop.changed.notify_all();  // no thread waits for the stop now
    outcomes[1] = stop_after_slip(outcomes[i], simulator, rest);
    tell(Axis::decel, outcomes[1]);
    return true;
  };
  // The axes derived from others (see the header), on the thread that found what they derive from,
  // as soon as it is known, while the other searches go on: the stop of a mirror-image load from
  // its start-up (task i), and the e-stop speed from the stop. Until session 24 both waited for
  // every search to end, and a 96-carton column searched its e-stop speed (7 s) after its curve.
  // `stop_here`: this thread has just found the stop (stop_after).
  auto derive_after = [&](std::size_t i, bool stop_here, Simulator& simulator,
                          const RestState& rest) {
    if (!outcomes[i].limit) return;  // unstable: the envelope fails; nothing derives from it
    if (mirror && tasks[i].axis == Axis::accel) {
      if (pulses(outcomes[i])) {
        outcomes[1] = mirrored(outcomes[i]);
        tell(Axis::decel, outcomes[1]);
      } else {
        if (o.progress != nullptr) o.progress->plan(kProbesPerSearch);
        search(1, simulator, rest);
      }
      stop_here = true;
    }
    stop_here = stop_here || tasks[i].axis == Axis::decel;
    if (!from_stop || !stop_here || !outcomes[1].limit) return;
    const AxisLimit& down = *outcomes[1].limit;
    AxisOutcome& estop = outcomes[3];
    if (down.at_ceiling || down.limit >= line.estop_decel_mps2) {
      estop.limit = AxisLimit{};
      estop.limit->limit = s.speed_max_mps;
      estop.limit->at_ceiling = true;
      estop.limit->closed_form = tasks[3].closed_form;
      estop.limit->derived = true;
    } else {
      if (o.progress != nullptr) o.progress->plan(kProbesPerSearch);
      search(3, simulator, rest);
    }
  };
  // After the start-up's thread is through with it (its stop searched, or the start-up unstable
  // or thrown), no thread may wait for the stop.
  auto start_up_ended = [&](std::size_t i) {
    if (!slips_both_ways || tasks[i].axis != Axis::accel) return;
    {
      const std::lock_guard lock(stop.mutex);
      stop.start_up_done = true;
    }
    stop.changed.notify_all();
  };
  if (threads <= 1) {
    for (std::size_t i : order) {
      const ProbeModel m = model_of(tasks[i].axis);
      search(i, *m.simulator, *m.rest);
      if (!outcomes[i].limit) break;  // unstable: the envelope fails; later axes would not help
      const bool stop_here = stop_after(i, *m.simulator, *m.rest);
      if (tasks[i].axis == Axis::accel && slips_both_ways && !outcomes[1].limit) break;
      derive_after(i, stop_here, *m.simulator, *m.rest);
    }
  } else {
    // Axes are independent: each thread takes the next axis it can on an mjData of its own for that
    // axis's model (a probe loads the whole rest state, so it is bitwise the probe the serial
    // search runs). The calling thread uses the models' simulators; the others make theirs within
    // the memory budget, and end when no axis is left that they can take.
    std::vector<bool> taken(order.size(), false);
    auto work = [&](bool caller) {
      std::map<const Scene*, std::unique_ptr<Simulator>> own;
      std::int64_t reserved = 0;
      // Whether this thread can search axis i: it has its model, or the budget has room for it.
      auto can_take = [&](std::size_t i) {
        const Simulator& model = *model_of(tasks[i].axis).simulator;
        if (caller || own.contains(&model.scene())) return true;
        const std::int64_t bytes = budget_bytes(model);
        if (!cores.reserve(bytes)) return false;
        reserved += bytes;
        own[&model.scene()];  // made when the search starts
        return true;
      };
      // The next axis this thread can take; it waits while the stop of a load that slips both ways
      // may still be released to it.
      auto claim = [&]() -> std::optional<std::size_t> {
        std::unique_lock lock(stop.mutex);
        for (;;) {
          for (std::size_t pos = 0; pos < order.size(); ++pos) {
            const std::size_t n = caller ? by_size[pos] : pos;
            if (taken[n] || !can_take(order[n])) continue;
            taken[n] = true;
            return order[n];
          }
          if (!slips_both_ways || stop.taken || stop.start_up_done) return std::nullopt;
          if (stop.released) {
            if (!can_take(1)) return std::nullopt;  // the start-up's thread searches it after
            stop.taken = true;
            if (o.progress != nullptr) o.progress->plan(kProbesPerSearch);
            return 1;
          }
          stop.changed.wait(lock);
        }
      };
      auto simulator_for = [&](Simulator& model) -> Simulator& {
        if (caller) return model;
        auto& mine = own.at(&model.scene());
        if (!mine) {
          auto created = Simulator::create(model.scene());
          if (!created) {
            throw std::runtime_error(created.diagnostics.empty()
                                         ? std::string("no simulation data")
                                         : created.diagnostics.front().message);
          }
          mine = std::make_unique<Simulator>(std::move(*created.value));
        }
        return *mine;
      };
      for (std::optional<std::size_t> next = claim(); next; next = claim()) {
        const std::size_t i = *next;
        try {  // an exception must not leave a thread (std::terminate): it fails its axis
          const ProbeModel m = model_of(tasks[i].axis);
          Simulator& simulator = simulator_for(*m.simulator);
          search(i, simulator, *m.rest);
          derive_after(i, stop_after(i, simulator, *m.rest), simulator, *m.rest);
        } catch (const std::exception& e) {
          // An axis that has its limit did not throw: what followed it did (derive_after), the
          // stop, or else the e-stop speed after it.
          const std::size_t failed = !outcomes[i].limit ? i : !outcomes[1].limit ? 1 : 3;
          outcomes[failed] = {};
          outcomes[failed].error =
              std::string(to_string(tasks[failed].axis)) + " search: " + e.what();
        }
        start_up_ended(i);
      }
      own.clear();
      cores.release(reserved);
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < threads; ++w) pool.emplace_back(work, false);
    work(true);
    for (auto& t : pool) t.join();
  }
  if (stop_check) {
    stop_check->drain();
    outcomes[1].ran_ahead += stop_check->started();
    outcomes[1].speculative += stop_check->wasted();
  }
  // Probes in axis order whatever the threads did; the first axis in that order that failed names
  // the reason.
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    AxisOutcome& a = outcomes[i];
    env.probes.insert(env.probes.end(), a.probes.begin(), a.probes.end());
    env.ran_ahead += a.ran_ahead;
    env.speculative += a.speculative;
    if (a.limit) continue;
    if (a.error) return Result<Envelope>::failure("", "the envelope search failed: " + *a.error);
    if (a.batch_error) {
      return Result<Envelope>::failure("", "the batched probes could not run: " + *a.batch_error);
    }
    return Result<Envelope>::failure(
        "", "the simulation became numerically unstable, so no verdict is given: " +
                a.unstable.value_or(std::string(to_string(tasks[i].axis)) + " search stopped"));
  }
  env.accel = *outcomes[0].limit;
  env.decel = *outcomes[1].limit;
  env.lateral = *outcomes[2].limit;
  env.speed = *outcomes[3].limit;
  summarise(env, line, s, o.thresholds);
  stamp_sims_and_time(env, start);
  return Result<Envelope>{std::move(env), {}};
}

namespace {

// What fails above a limit: mode_words, and for the pallet's slip the allowance it slid past (a
// pallet may slip a little at a limit: the detector fails it only past that slide).
std::string failure_words(FailureMode mode, SlideKind how, const DetectorThresholds& t) {
  if (mode == FailureMode::pallet_slip) {
    return "the pallet slides more than " + fixed(t.pallet_slip_m, 2) + " m on the belt";
  }
  return std::string(mode_words(mode, how));
}

void summarise(Envelope& env, const LineDescription& line, const SearchConfig& s,
               const DetectorThresholds& thresholds, bool predicted) {
  SafetyResult& r = env.result;
  r.line_estop_decel_mps2 = line.estop_decel_mps2;
  r.line_curve_radius_m = line.curve_radius_m;
  // An axis's mode, and how its top_item_slide went (the result's *_item_tipped, *_load_as_one).
  auto failing = [](const AxisLimit& a, FailureMode& mode, bool& tipped, bool& as_one) {
    mode = a.mode;
    tipped = a.slide == SlideKind::item_tipped;
    as_one = a.slide == SlideKind::load_as_one;
  };
  r.max_accel_mps2 = env.accel.limit;
  failing(env.accel, r.accel_mode, r.accel_item_tipped, r.accel_load_as_one);
  r.max_decel_mps2 = env.decel.limit;
  failing(env.decel, r.decel_mode, r.decel_item_tipped, r.decel_load_as_one);
  r.max_lateral_g = env.lateral.limit;
  failing(env.lateral, r.lateral_mode, r.lateral_item_tipped, r.lateral_load_as_one);
  // The speed the curve allows: v^2 / r within the measured lateral limit.
  const double curve_speed = std::sqrt(env.lateral.limit * kGravity * line.curve_radius_m);
  const double stop_speed = env.speed.at_ceiling ? s.speed_max_mps : env.speed.limit;
  const bool by_curve = !env.lateral.at_ceiling && curve_speed < stop_speed;
  failing(by_curve ? env.lateral : env.speed, r.speed_mode, r.speed_item_tipped,
          r.speed_load_as_one);
  if (by_curve) {
    r.max_speed_mps = std::floor(curve_speed / s.speed_precision_mps) * s.speed_precision_mps;
    r.speed_governed_by = SpeedGovernor::curve;
  } else {
    r.max_speed_mps = stop_speed;
    r.speed_governed_by = env.speed.at_ceiling ? SpeedGovernor::ceiling : SpeedGovernor::estop;
  }
  r.max_speed_mps = std::min(r.max_speed_mps, s.speed_max_mps);

  struct Tight {
    const char* name;
    const AxisLimit* axis;
    double margin;
  };
  const Tight tight[] = {
      {"start-up", &env.accel, normalised(env.accel, s.accel_min_mps2, s.accel_max_mps2)},
      {"stop", &env.decel, normalised(env.decel, s.decel_min_mps2, s.decel_max_mps2)},
      {"curve", &env.lateral, normalised(env.lateral, s.lateral_min_g, s.lateral_max_g)},
      {"line e-stop", &env.speed, normalised(env.speed, s.speed_min_mps, s.speed_max_mps)},
  };
  const Tight* weakest = &tight[0];
  for (const auto& t : tight) {
    if (t.margin < weakest->margin) weakest = &t;
  }
  r.margin_pct = 100.0 * weakest->margin;
  // How the tightest axis fails (dominant_slide: item_slid where that is not a top_item_slide).
  auto dominate = [&r](const AxisLimit& a) {
    r.dominant_failure_mode = a.at_ceiling ? FailureMode::no_failure : a.mode;
    r.dominant_slide =
        r.dominant_failure_mode == FailureMode::top_item_slide ? a.slide : SlideKind::item_slid;
  };
  dominate(*weakest->axis);

  const Tight* floor_axis = nullptr;
  for (const auto& t : tight) {
    if (t.axis->at_floor) {
      floor_axis = &t;
      break;
    }
  }
  if (floor_axis != nullptr) {
    r.verdict = Verdict::reject;
    r.speed_governed_by = SpeedGovernor::reject;
    // Unsafe at any motion: no limit of any axis holds (a curve limit beside a start-up that
    // always fails would read as a way to run it).
    r.max_speed_mps = r.max_accel_mps2 = r.max_decel_mps2 = r.max_lateral_g = 0.0;
    dominate(*floor_axis->axis);
    r.margin_pct = 0.0;
    r.reason = std::string("Reject: unsafe at any motion; it ") +
               (predicted ? "is predicted (closed form, not simulated) to fail" : "fails") +
               " at the gentlest " + floor_axis->name + " tried (" +
               failure_words(floor_axis->axis->mode, floor_axis->axis->slide, thresholds) +
               "). Re-stack or re-wrap before it enters the conveyor.";
  } else {
    r.verdict = Verdict::ok;
    std::ostringstream why;
    const std::string governed = (r.speed_governed_by == SpeedGovernor::ceiling ? "" : "set by ") +
                                 std::string(governor_words(r.speed_governed_by));
    // The accelerations were measured (or, at the closed-form level, predicted) on start-ups
    // to, and stops from, the top of the speed range (the probes); the speed limit is the
    // line's, after them. Each axis says what fails above it.
    auto above = [&](const AxisLimit& a) {
      if (a.at_ceiling) return std::string("the top of the range");
      std::string words = "above it, " + failure_words(a.mode, a.slide, thresholds);
      if (a.loose_at_entry) words += " once the load's sway at the curve's entry breaks it loose";
      return words;
    };
    // Limits are floored to their digits: "up to" never promises more than was measured.
    why << "Start-up at up to " << fixed_floor(r.max_accel_mps2, 2) << " m/s^2 ("
        << above(env.accel) << "; " << (predicted ? "predicted, not simulated, for" : "measured")
        << " ramping to " << fixed(s.speed_max_mps, 1) << " m/s); stops at up to "
        << fixed_floor(r.max_decel_mps2, 2) << " m/s^2 (from " << fixed(s.speed_max_mps, 1)
        << " m/s; " << above(env.decel) << "); curves up to " << fixed_floor(r.max_lateral_g, 3)
        << " g (on " << fixed(line.curve_radius_m, 1) << " m curves; " << above(env.lateral)
        << "). Top speed " << fixed_floor(r.max_speed_mps, 2) << " m/s (" << governed << ", with a "
        << fixed(line.estop_decel_mps2, 1) << " m/s^2 e-stop and " << fixed(line.curve_radius_m, 1)
        << " m curves).";
    r.reason = why.str();
  }
}

void stamp_sims_and_time(Envelope& env, std::chrono::steady_clock::time_point start) {
  env.result.sims_run = static_cast<int>(env.probes.size());
  env.result.sim_runtime_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The largest multiple of `step` above `lo` (from lo) not beyond `bound`, as an axis limit.
AxisLimit closed_form_axis(const AxisPrediction& prediction, double lo, double hi, double step) {
  AxisLimit a;
  const double b = prediction.value;
  a.closed_form = b;
  if (b >= hi) {
    a.limit = hi;
    a.at_ceiling = true;
    return a;
  }
  a.mode = prediction.mode;
  if (b < lo) {
    a.at_floor = true;
    return a;
  }
  a.limit = lo + std::floor((b - lo) / step + 1e-9) * step;
  return a;
}

}  // namespace

Envelope closed_form_envelope(const QuasiStaticBounds& bounds, const LineDescription& line,
                              const SearchConfig& s, const DetectorThresholds& thresholds) {
  const auto start = std::chrono::steady_clock::now();
  Envelope env;
  const QuasiStaticLimit along = bounds.weakest_along();
  const AxisPredictions p = predict_envelope(bounds, line, s, thresholds);
  env.accel = closed_form_axis(p.accel, s.accel_min_mps2, s.accel_max_mps2, s.accel_precision_mps2);
  env.decel = closed_form_axis(p.decel, s.decel_min_mps2, s.decel_max_mps2, s.decel_precision_mps2);
  // A wrapped load's curve as the reduced level takes it (search_envelope): its pallet is broken
  // loose at the arc's entry.
  AxisPrediction lateral = p.lateral;
  if (bounds.one_body()) {
    const double cap = loose_at_entry_g(bounds, line, s, thresholds);
    if (cap < lateral.value) lateral = {cap, FailureMode::pallet_slip};
  }
  env.lateral = closed_form_axis(lateral, s.lateral_min_g, s.lateral_max_g, s.lateral_precision_g);
  env.lateral.loose_at_entry = lateral.value < p.lateral.value && !env.lateral.at_ceiling;
  // The e-stop: nothing moves below the onset; above it a slide grows with v^2 (a tip is
  // assumed at any speed).
  QuasiStaticLimit stop{s.speed_max_mps, FailureMode::no_failure, Mechanism::pallet_slip, "", -1};
  if (line.estop_decel_mps2 > along.accel_mps2) {
    stop.mode = along.mode;
    stop.accel_mps2 =
        along.mode == FailureMode::tip_over ? 0.0 : estop_slide_speed_mps(along, line, thresholds);
  }
  env.speed = closed_form_axis({stop.accel_mps2, stop.mode}, s.speed_min_mps, s.speed_max_mps,
                               s.speed_precision_mps);
  summarise(env, line, s, thresholds, /*predicted=*/true);
  stamp_sims_and_time(env, start);
  env.result.fidelity = Fidelity::closed_form;
  return env;
}

}  // namespace pb
