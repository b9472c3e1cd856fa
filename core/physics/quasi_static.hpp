// SPDX-License-Identifier: MIT
// Closed-form quasi-static bounds: the acceleration at which each interface would start to slip
// (mu g) and each sub-stack would start to tip (g (b/2) / h), along and across the belt. The
// cheapest rung of the fidelity ladder, and the seed of every envelope search.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "core/base/enums.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/friction.hpp"

namespace pb {

inline constexpr double kGravity = 9.81;

/// What gives way: a Coulomb slip (onset mu g) or a tip (onset g (b/2) / h).
enum class Mechanism { pallet_slip, load_tip, item_slip_on_deck, item_slip_on_item, stack_tip };

struct QuasiStaticLimit {
  double accel_mps2 = 0.0;
  FailureMode mode = FailureMode::no_failure;
  Mechanism mechanism = Mechanism::pallet_slip;
  std::string what;  ///< "item 7 slips on item 3 (mu 0.34)"
  int item = -1;     ///< the item concerned, -1 for the pallet
  /// A slip's deceleration once it slides, mu_d g (kinetic friction; step.hpp): how far it slides
  /// past the onset. 0 for a tip, and wherever it is the onset itself.
  double sliding_mps2 = 0.0;
  /// Where the mass it moves has its centre, from the pallet's centre (X, Y), m: the pallet's and
  /// the whole load's, the load's; an item's slip and its sub-stack's tip, that sub-stack's. A
  /// curve turns the load about its centre, adding to the demand there (curve_demand_factor).
  double offset_x_m = 0.0, offset_y_m = 0.0;
};

/// Whether `m` moves the whole load (the pallet's slip, the loaded pallet's tip), not an item or
/// a sub-stack on it.
inline bool of_the_whole_load(const QuasiStaticLimit& m) {
  return m.mechanism == Mechanism::pallet_slip || m.mechanism == Mechanism::load_tip;
}

/// How much more than the centre line's v^2 / r a curve of `radius_m` demands of mechanism `m`
/// (turning_frame.hpp): omega^2 d on top of it at its mass's offset d, outboard in the turn that
/// pushes it towards its nearer side. A slip is pushed by the whole horizontal demand,
/// |(r + |y|, x)| / r (the friction pyramids are turned along it: step.hpp's DemandField); a tip
/// across the belt by its lateral part, (r + |y|) / r.
double curve_demand_factor(const QuasiStaticLimit& m, double radius_m);

/// The onset of the pallet's slip on its belt among `mechanisms` (m/s^2), 0 if none.
double belt_onset_mps2(const std::vector<QuasiStaticLimit>& mechanisms);

struct QuasiStaticBounds {
  std::vector<QuasiStaticLimit> along;   ///< every mechanism along the belt (X)
  std::vector<QuasiStaticLimit> across;  ///< every mechanism across it (Y)
  QuasiStaticLimit weakest_along() const;
  QuasiStaticLimit weakest_across() const;
  /// The load moves as one body: its only mechanisms are the pallet slipping and the whole load
  /// tipping (a wrapped load).
  bool one_body() const;
};

/// Mechanisms: the pallet slipping on the belt; the whole load tipping over the pallet's edge;
/// and, for unwrapped loads (a wrap holds its items), every item slipping on what carries it and
/// every sub-stack (an item and all it carries) tipping over that item's bottom edge. Frictions
/// are the effective (frost-penalised) static values.
QuasiStaticBounds quasi_static_bounds(const PalletConfig& config, const ContactFriction& friction);

/// How far (m) a load held by friction slides on what carries it when that is pushed at `a` (m/s^2)
/// for `duration_s` and then runs steady, under step.hpp's friction law: nothing at or below the
/// static onset `onset` (mu_s g); above it the load slips on its static cone, lagging at a - onset,
/// until it has slipped `break_loose_m` (kBreakLooseM in the simulation), then breaks loose and
/// lags at a - `sliding` (mu_d g) until the push ends, and then catches up at `sliding` (at `onset`
/// while it has not yet slipped that far). For an e-stop from v at a the push lasts v / a. With
/// break_loose_m 0 this is Coulomb's slide, breaking loose at once: the longest any such load
/// slides, 2-13 % longer than the simulation's (step_test). 1e9 where the load slides and nothing
/// stops it
/// (`sliding` 0).
double breakaway_slide_m(double onset, double sliding, double a, double duration_s,
                         double break_loose_m);

/// The speed from which a stop at `decel` makes that slide `distance` long (breakaway_slide_m over
/// v / decel, which grows with v); 1e9 where the stop is at or below the onset.
double breakaway_slide_speed_mps(double onset, double sliding, double decel, double distance,
                                 double break_loose_m);

/// A mechanism's deceleration once it moves: a slip's kinetic mu_d g (no more than its onset), a
/// tip's onset.
inline double sliding_decel_mps2(const QuasiStaticLimit& m) {
  return m.sliding_mps2 > 0.0 ? std::min(m.sliding_mps2, m.accel_mps2) : m.accel_mps2;
}

}  // namespace pb
