// SPDX-License-Identifier: MIT
// The failure map of one pallet: every cell of a speed x start-up-acceleration grid simulated in
// one batched call (Batch, one ProbeRun per simulation), each cell with its verdict, failure mode
// and failure time, the envelope the map implies, and the cells that break monotonicity.
//
// What one cell (v, a) means, so that the map's envelope is comparable with the bisection
// envelope (envelope.hpp): the pallet survives cell (v, a) when it survives
//   - the start-up: from rest, ramp at a to v (for at most SearchConfig::max_ramp_s, exactly as
//     the bisection's start-up probe, which is the cell in the top speed column), then hold;
//   - the line's curve at v (lateral v^2 / r, lateral_probe_profile) and
//   - the line's e-stop from v (stop_probe_profile).
// The curve and the e-stop depend on v only: they are simulated once per column. A cell's mode and
// failure time are those of the first of the three (in that order) that fails. Each probe runs
// until the load rides with the belt again (fail-fast, early stop), as in the bisection.
//
// The map's envelope: max_accel_mps2 is the highest grid acceleration at and below which every
// start-up cell is safe; max_speed_mps the highest grid speed at and below which every column's
// curve and e-stop are safe (0 when the lowest already fails). Against the bisection (precision p)
// these agree within one grid step plus p.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/analysis/envelope.hpp"
#include "core/base/diagnostic.hpp"
#include "core/physics/probe_batch.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/simulate.hpp"

namespace pb {

/// Which probe of a cell decided it.
enum class MapProbe { none, startup, curve, estop };
std::string_view to_string(MapProbe probe);

struct MapCell {
  Outcome outcome = Outcome::safe;  ///< unstable: no verdict (see reason)
  FailureMode mode = FailureMode::no_failure;
  double failure_time_s = 0.0;  ///< within the deciding probe
  bool non_monotone = false;    ///< safe although a cell at lower-or-equal speed and accel fails
  MapProbe decided_by = MapProbe::none;
  std::string reason;  ///< why the cell is unstable (empty otherwise)
};

struct FailureMap {
  std::vector<double> speeds_mps;   ///< columns (x), ascending
  std::vector<double> accels_mps2;  ///< rows (y), ascending
  std::vector<MapCell> cells;       ///< cells[accel_index * speeds.size() + speed_index]
  /// Per speed column: the line's curve and e-stop at that speed (decided_by curve or estop).
  std::vector<MapCell> line_cells;
  const MapCell& at(int speed_index, int accel_index) const;
  MapCell& at(int speed_index, int accel_index);

  double max_speed_mps = 0, max_accel_mps2 = 0;      ///< the envelope derived from the map
  FailureMode speed_mode = FailureMode::no_failure;  ///< what fails one column above max_speed
  FailureMode accel_mode = FailureMode::no_failure;  ///< what fails one row above max_accel
  bool reject = false;     ///< the gentlest cell (lowest speed and accel) fails
  int unstable_cells = 0;  ///< cells without a verdict
  int non_monotone_cells = 0;
  int sims = 0;
  int threads = 0;
  double wall_ms = 0;
};

struct MapOptions {
  /// Explicit grids (ascending, positive); empty: `n_speeds` / `n_accels` values evenly spaced
  /// over the SearchConfig's speed and acceleration ranges, ends included.
  std::vector<double> speeds_mps, accels_mps2;
  int n_speeds = 16, n_accels = 12;
  int threads = 0;  ///< 0: every logical CPU
};

/// The grids' ranges: a map's speeds in (0, kMapMaxSpeedMps], its start-ups in (0,
/// kMapMaxAccelMps2].
constexpr double kMapMaxSpeedMps = 5.0;
constexpr double kMapMaxAccelMps2 = 10.0;
enum class MapGrid { speeds, accels };

/// Every problem of an explicit grid (MapOptions::speeds_mps or accels_mps2) sent at `pointer`:
/// empty, more than 256 values, each value outside its range, each not above the one before it
/// (at `pointer`/k). `index`, where given, is each value's place in the array sent, when some of
/// its members (not numbers) were left out.
Diagnostics map_grid_problems(MapGrid grid, const std::vector<double>& values,
                              const std::string& pointer,
                              const std::vector<std::size_t>& index = {});

/// `n` values from lo to hi inclusive (n >= 2; n == 1 gives {hi}).
std::vector<double> linear_grid(double lo, double hi, int n);

/// Runs the map on a settled scene. Fails (with the field to change) on a bad grid; an engine
/// failure that stops the whole batch fails the map; an unstable cell is reported in the map.
Result<FailureMap> run_failure_map(const Scene& scene, const RestState& rest,
                                   const MapOptions& options, const LineDescription& line = {},
                                   const SearchConfig& search = {}, const SimOptions& sim = {});

/// Derives the envelope and the non-monotone flags from the cells (run_failure_map calls it; a test
/// can call it on a constructed map).
void summarise_map(FailureMap& map);

}  // namespace pb
