// SPDX-License-Identifier: MIT
// Where numerical methods fail: each case is a small pallet under numerical settings known to be
// fine or known to break (Euler with a stiff belt actuator, implicit creep, timesteps 0.25-20 ms,
// PGS/CG against Newton, contact buffers too small, elliptic against pyramidal), run on a probe
// just below and one just above the pallet's threshold, and classified against the reference
// configuration: correct, wrong verdict, or detected unstable. A numerically broken case must come
// out detected unstable, never as a verdict. What `palletballet-lab study stability` runs.
#pragma once

#include <string>
#include <vector>

#include "core/base/enums.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/simulate.hpp"

namespace pb {

enum class StabilityClass { correct, wrong_verdict, detected_unstable };
std::string_view to_string(StabilityClass c);

struct StabilityCase {
  std::string name;   ///< "euler-kv-2.5"
  std::string group;  ///< "belt actuator (Euler)", "timestep", ...
  std::string description;
  std::string pallet;  ///< one of stability_pallet_names()
  SceneOptions scene;
  /// The settings are numerically broken (divergence, dropped contacts, a step too large to hold
  /// the load up): the only acceptable outcome is detected_unstable.
  bool broken = false;
  /// What this case gives today (the test pins it). Broken cases must expect detected_unstable.
  StabilityClass expected = StabilityClass::correct;
};

/// The small pallets of the study: "carton" (one 10 kg carton that slides on the deck) and
/// "slender" (a 0.2 x 0.2 x 1.0 m, 20 kg carton that tips before it slides).
std::vector<std::string> stability_pallet_names();
PalletConfig stability_pallet(const std::string& name);
/// Whether a pallet's probes are curves (the carton: its pallet slips sideways on the belt well
/// inside the range, while its start-up probes are safe up to the 5 m/s^2 ceiling) rather than
/// start-ups (the slender carton).
bool stability_probes_lateral(const std::string& pallet);

/// Every case, grouped as the issue lists them.
std::vector<StabilityCase> stability_cases();

/// One probe of a case (or of the reference).
struct StabilityProbe {
  double accel_mps2 = 0.0;          ///< of the start-up, or lateral (v^2 / r) for a curve probe
  Outcome outcome = Outcome::safe;  ///< unstable also when the scene could not be prepared
  FailureMode mode = FailureMode::no_failure;
  std::string reason;  ///< why it is unstable
};

struct StabilityRow {
  StabilityCase c;
  std::vector<StabilityProbe> reference;  ///< the reference configuration on the same probes
  std::vector<StabilityProbe> probes;
  StabilityClass got = StabilityClass::correct;
  std::string detail;  ///< the first disagreement or the instability reason
  double wall_ms = 0.0;
  /// A broken case that gave a verdict: a guard is missing.
  bool missing_guard() const { return c.broken && got != StabilityClass::detected_unstable; }
};

/// Runs `cases` (each pallet's reference probes once, shared by its cases).
std::vector<StabilityRow> run_stability_study(const std::vector<StabilityCase>& cases);

Json stability_row_to_json(const StabilityRow& row);

}  // namespace pb
