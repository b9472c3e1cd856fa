// SPDX-License-Identifier: MIT
#include "core/analysis/failure_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "core/base/text.hpp"
#include "core/physics/probe_batch.hpp"

namespace pb {

std::string_view to_string(MapProbe probe) {
  switch (probe) {
    case MapProbe::none:
      return "none";
    case MapProbe::startup:
      return "startup";
    case MapProbe::curve:
      return "curve";
    case MapProbe::estop:
      return "estop";
  }
  return "?";
}

const MapCell& FailureMap::at(int speed_index, int accel_index) const {
  return cells.at(std::size_t(accel_index) * speeds_mps.size() + std::size_t(speed_index));
}

MapCell& FailureMap::at(int speed_index, int accel_index) {
  return cells.at(std::size_t(accel_index) * speeds_mps.size() + std::size_t(speed_index));
}

std::vector<double> linear_grid(double lo, double hi, int n) {
  if (n <= 1) return {hi};
  std::vector<double> out(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) out[std::size_t(k)] = lo + (hi - lo) * k / (n - 1);
  out.back() = hi;
  return out;
}

Diagnostics map_grid_problems(MapGrid grid, const std::vector<double>& values,
                              const std::string& pointer, const std::vector<std::size_t>& index) {
  const double max = grid == MapGrid::speeds ? kMapMaxSpeedMps : kMapMaxAccelMps2;
  const char* unit = grid == MapGrid::speeds ? "m/s" : "m/s^2";
  if (values.empty()) {
    return {{pointer, "the grid is empty: give at least one value", Severity::error}};
  }
  if (values.size() > 256) {
    return {{pointer, "the grid has " + std::to_string(values.size()) + " values: give at most 256",
             Severity::error}};
  }
  Diagnostics out;
  for (std::size_t k = 0; k < values.size(); ++k) {
    const double x = values[k];
    const std::string at = pointer + "/" + std::to_string(k < index.size() ? index[k] : k);
    if (!std::isfinite(x) || x <= 0.0 || x > max) {
      out.push_back({at, "value " + fixed(x, 3) + " is outside (0, " + fixed(max, 1) + "] " + unit,
                     Severity::error});
    } else if (k > 0 && x <= values[k - 1]) {
      out.push_back({at,
                     "values must be strictly ascending (" + fixed(values[k - 1], 3) + " then " +
                         fixed(x, 3) + ")",
                     Severity::error});
    }
  }
  return out;
}

namespace {

struct Job {
  ConveyorProfile profile;
  MapProbe kind = MapProbe::startup;
  int speed = 0, accel = 0;  // grid indices (accel unused for line probes)
};

MapCell cell_of(const SimResult& r, MapProbe kind, const std::string& what) {
  MapCell c;
  c.outcome = r.outcome;
  if (r.outcome == Outcome::unstable) {
    c.decided_by = kind;
    c.reason = what + ": " + r.reason;
  } else if (r.outcome == Outcome::failed && r.failure) {
    c.decided_by = kind;
    c.mode = r.failure->mode;
    c.failure_time_s = r.failure->time_s;
  }
  return c;
}

}  // namespace

Result<FailureMap> run_failure_map(const Scene& scene, const RestState& rest,
                                   const MapOptions& options, const LineDescription& line,
                                   const SearchConfig& search, const SimOptions& sim_options) {
  const auto wall_start = std::chrono::steady_clock::now();
  FailureMap map;
  map.speeds_mps = options.speeds_mps.empty()
                       ? linear_grid(search.speed_min_mps, search.speed_max_mps, options.n_speeds)
                       : options.speeds_mps;
  map.accels_mps2 =
      options.accels_mps2.empty()
          ? linear_grid(search.accel_min_mps2, search.accel_max_mps2, options.n_accels)
          : options.accels_mps2;
  Diagnostics problems;
  if (options.speeds_mps.empty() && (options.n_speeds < 1 || options.n_speeds > 256)) {
    problems.push_back({"/n_speeds", "give 1 to 256 speeds", Severity::error});
  } else {
    for (Diagnostic& p : map_grid_problems(MapGrid::speeds, map.speeds_mps, "/speeds_mps")) {
      problems.push_back(std::move(p));
    }
  }
  if (options.accels_mps2.empty() && (options.n_accels < 1 || options.n_accels > 256)) {
    problems.push_back({"/n_accels", "give 1 to 256 accelerations", Severity::error});
  } else {
    for (Diagnostic& p : map_grid_problems(MapGrid::accels, map.accels_mps2, "/accels_mps2")) {
      problems.push_back(std::move(p));
    }
  }
  if (options.threads < 0) {
    problems.push_back(
        {"/threads", "give 0 (every CPU) or a positive thread count", Severity::error});
  }
  if (!problems.empty()) return Result<FailureMap>::failure(std::move(problems));

  SimOptions o = sim_options;
  o.record_trace = false;
  o.fail_fast = true;
  o.project_pallet_slip = false;  // each cell tells when its load failed, not when it was certain
  const int ns = int(map.speeds_mps.size()), na = int(map.accels_mps2.size());
  std::vector<Job> jobs;
  jobs.reserve(std::size_t(ns * na + 3 * ns));
  for (int j = 0; j < na; ++j) {
    for (int i = 0; i < ns; ++i) {
      SearchConfig s = search;
      s.speed_max_mps = map.speeds_mps[std::size_t(i)];  // ramp to v (max_ramp_s at most)
      jobs.push_back(
          {accel_probe_profile(map.accels_mps2[std::size_t(j)], s), MapProbe::startup, i, j});
    }
  }
  // The line's curve turns both ways: a load that is not its own mirror image across the belt
  // is run in each (search_envelope does the same), and the column takes the worse.
  const std::vector<CurveTurn> turns = curve_turns(scene.config);
  const std::size_t per_column = turns.size() + 1;
  for (int i = 0; i < ns; ++i) {
    const double v = map.speeds_mps[std::size_t(i)];
    const double lateral_g = v * v / (line.curve_radius_m * kGravity);
    for (CurveTurn turn : turns) {
      jobs.push_back({lateral_probe_profile(lateral_g, line, search, turn), MapProbe::curve, i, 0});
    }
    jobs.push_back({stop_probe_profile(v, line, search), MapProbe::estop, i, 0});
  }

  std::vector<ConveyorProfile> profiles;
  profiles.reserve(jobs.size());
  for (const Job& job : jobs) profiles.push_back(job.profile);
  int threads = 0;
  if (o.progress != nullptr) o.progress->plan(int(profiles.size()));
  auto sims = run_probes_batched(scene, rest, profiles, o, options.threads, {}, &threads);
  if (!sims) return Result<FailureMap>::failure(std::move(sims.diagnostics));

  // Assemble: the line probes per column, then each cell.
  auto describe = [&](const Job& job) {
    const double v = map.speeds_mps[std::size_t(job.speed)];
    switch (job.kind) {
      case MapProbe::startup:
        return "start-up at " + fixed(map.accels_mps2[std::size_t(job.accel)], 2) + " m/s^2 to " +
               fixed(v, 2) + " m/s";
      case MapProbe::curve:
        return std::string(to_string(job.profile.curve_turn)) + " curve of " +
               fixed(line.curve_radius_m, 1) + " m at " + fixed(v, 2) + " m/s";
      default:
        return "e-stop at " + fixed(line.estop_decel_mps2, 1) + " m/s^2 from " + fixed(v, 2) +
               " m/s";
    }
  };
  std::vector<MapCell> results(jobs.size());
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    results[k] = cell_of((*sims.value)[k], jobs[k].kind, describe(jobs[k]));
  }
  const std::size_t line_base = std::size_t(ns * na);
  map.line_cells.resize(std::size_t(ns));
  for (int i = 0; i < ns; ++i) {
    // The first curve that does not hold (left before right), else the e-stop.
    const std::size_t first = line_base + per_column * std::size_t(i);
    std::size_t decides = first + turns.size();
    for (std::size_t t = first; t < first + turns.size(); ++t) {
      if (results[t].outcome != Outcome::safe) {
        decides = t;
        break;
      }
    }
    map.line_cells[std::size_t(i)] = results[decides];
  }
  map.cells.resize(std::size_t(ns * na));
  for (std::size_t k = 0; k < line_base; ++k) {
    const MapCell& startup = results[k];
    map.cells[k] =
        startup.outcome != Outcome::safe ? startup : map.line_cells[std::size_t(jobs[k].speed)];
  }
  map.sims = int(jobs.size());
  map.threads = threads;
  summarise_map(map);
  map.wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start)
          .count();
  return Result<FailureMap>{std::move(map), {}};
}

void summarise_map(FailureMap& map) {
  const int ns = int(map.speeds_mps.size()), na = int(map.accels_mps2.size());
  // Non-monotone: safe although some cell at lower-or-equal speed and acceleration fails.
  std::vector<char> below(std::size_t(ns * na), 0);  // a failing cell at <= (i, j), inclusive
  map.non_monotone_cells = 0;
  map.unstable_cells = 0;
  for (int j = 0; j < na; ++j) {
    for (int i = 0; i < ns; ++i) {
      MapCell& c = map.at(i, j);
      const bool left = i > 0 && below[std::size_t(j * ns + i - 1)];
      const bool under = j > 0 && below[std::size_t((j - 1) * ns + i)];
      c.non_monotone = c.outcome == Outcome::safe && (left || under);
      if (c.non_monotone) ++map.non_monotone_cells;
      if (c.outcome == Outcome::unstable) ++map.unstable_cells;
      below[std::size_t(j * ns + i)] = c.outcome == Outcome::failed || left || under;
    }
  }
  // Start-up: a row passes when none of its cells fails (or is unstable) in the start-up.
  auto startup_bad = [](const MapCell& c) {
    return c.outcome != Outcome::safe && c.decided_by == MapProbe::startup;
  };
  map.max_accel_mps2 = 0.0;
  map.accel_mode = FailureMode::no_failure;
  for (int j = 0; j < na; ++j) {
    const MapCell* bad = nullptr;
    for (int i = ns - 1; i >= 0 && bad == nullptr; --i) {
      if (startup_bad(map.at(i, j))) bad = &map.at(i, j);
    }
    if (bad != nullptr) {
      map.accel_mode = bad->mode;
      break;
    }
    map.max_accel_mps2 = map.accels_mps2[std::size_t(j)];
  }
  // Speed: a column passes when the line's curve and e-stop at its speed are survived.
  auto line_bad = [&](int i) {
    if (!map.line_cells.empty()) return map.line_cells[std::size_t(i)].outcome != Outcome::safe;
    for (int j = 0; j < na; ++j) {
      const MapCell& c = map.at(i, j);
      if (c.outcome != Outcome::safe && c.decided_by != MapProbe::startup) return true;
    }
    return false;
  };
  auto line_mode = [&](int i) {
    if (!map.line_cells.empty()) return map.line_cells[std::size_t(i)].mode;
    for (int j = 0; j < na; ++j) {
      const MapCell& c = map.at(i, j);
      if (c.outcome != Outcome::safe && c.decided_by != MapProbe::startup) return c.mode;
    }
    return FailureMode::no_failure;
  };
  map.max_speed_mps = 0.0;
  map.speed_mode = FailureMode::no_failure;
  for (int i = 0; i < ns; ++i) {
    if (line_bad(i)) {
      map.speed_mode = line_mode(i);
      break;
    }
    map.max_speed_mps = map.speeds_mps[std::size_t(i)];
  }
  map.reject = ns > 0 && na > 0 && map.at(0, 0).outcome == Outcome::failed;
}

}  // namespace pb
