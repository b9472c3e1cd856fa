// SPDX-License-Identifier: MIT
// `palletballet-cli map FILE`: the speed x start-up-acceleration failure map of one pallet, every
// cell simulated in one batched call (core/analysis/failure_map.hpp says what a cell means).
#include <cmath>
#include <iostream>
#include <sstream>

#include "app/cli/commands.hpp"
#include "core/analysis/analyzer.hpp"
#include "core/analysis/failure_map.hpp"
#include "core/analysis/result_json.hpp"
#include "core/base/text.hpp"

namespace pb::cli {

namespace {

// "--speeds 0.1:2:16" (from:to:count, ends included) or "--speeds 0.5,1,1.5"; empty when absent.
std::vector<double> grid_option(const Args& args, const std::string& name) {
  const auto text = args.text(name);
  if (!text) return {};
  const std::string bad = "map: --" + name + " takes FROM:TO:COUNT (e.g. 0.1:2:16) or a list " +
                          "(e.g. 0.5,1,1.5), got '" + *text + "'";
  if (text->find(':') != std::string::npos) {
    std::istringstream in(*text);
    double lo = 0, hi = 0;
    long n = 0;
    char c1 = 0, c2 = 0;
    if (!(in >> lo >> c1 >> hi >> c2 >> n) || c1 != ':' || c2 != ':' || !in.eof()) {
      throw UsageError{bad};
    }
    if (n < 1 || n > 256) throw UsageError{"map: --" + name + " COUNT must be 1 to 256"};
    if (!(hi > lo) && n > 1) throw UsageError{"map: --" + name + " TO must be above FROM"};
    return linear_grid(lo, hi, int(n));
  }
  auto values = args.numbers(name);
  if (!values || values->empty()) throw UsageError{bad};
  return *values;
}

int run_map(const Args& args) {
  MapOptions options;
  options.speeds_mps = grid_option(args, "speeds");
  options.accels_mps2 = grid_option(args, "accels");
  if (auto t = args.integer("threads")) {
    if (*t < 0 || *t > 1024) throw UsageError{"map: --threads must be 0 (every CPU) to 1024"};
    options.threads = int(*t);
  }
  AnalyzerOptions ao;
  if (auto d = args.number("estop-decel")) {
    if (!(*d > 0.0 && *d <= 20.0)) {
      throw UsageError{"map: --estop-decel must be above 0 and at most 20 m/s^2"};
    }
    ao.line.estop_decel_mps2 = *d;
  }
  if (auto r = args.number("curve-radius")) {
    if (!(*r > 0.0 && *r <= 1000.0)) {
      throw UsageError{"map: --curve-radius must be above 0 and at most 1000 m"};
    }
    ao.line.curve_radius_m = *r;
  }
  const std::string source = args.positionals()[0];
  auto input = read_pallet_source(source);
  print_diagnostics(input.diagnostics);
  if (!input) return kExitBadInput;
  Analyzer analyzer(ao);
  auto map = analyzer.failure_map(input->pallet, options);
  if (!map) {
    // Grid problems name the option; pallet problems point into the document read; an empty
    // pointer is the engine's (a run failure).
    bool input_fault = false;
    for (auto& d : map.diagnostics) {
      std::string option;
      for (const char* name : {"speeds", "accels", "threads"}) {
        if (d.pointer.find(name) == 1) option = name;
      }
      if (!option.empty()) {
        d.message = "--" + option + " (" + d.pointer + "): " + d.message;
        d.pointer.clear();
        input_fault = true;
      } else if (!d.pointer.empty()) {
        d.pointer = input->pointer_prefix + d.pointer;
        input_fault = true;
      }
    }
    for (const auto& d : condensed(map.diagnostics)) {
      std::cerr << "palletballet-cli map: " << (d.pointer.empty() ? d.message : to_string(d))
                << "\n";
    }
    return input_fault ? kExitBadInput : kExitFailure;
  }
  Json out = failure_map_to_json(*map);
  out["source"] = source;
  out["pallet_id"] = input->pallet.pallet_id;
  out["line"] = line_to_json(ao.line, ao.search);
  out["cell_definition"] =
      "cell (v, a): start-up from rest at a up to v (at most " +
      short_number(ao.search.max_ramp_s) +
      " s of ramp), then the line's curve at v and its e-stop from v; mode and failure time of "
      "the first that fails";
  print_json(out);
  if (map->unstable_cells > 0) {
    std::cerr << "palletballet-cli map: " << map->unstable_cells
              << " cell(s) became numerically unstable and have no verdict (see their reason)\n";
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

Command map_command() {
  return {{"map",
           "map FILE [--speeds FROM:TO:COUNT | V,V,...] [--accels FROM:TO:COUNT | A,A,...] "
           "[--threads T] [--estop-decel D] [--curve-radius R]",
           "the speed x start-up-acceleration failure map of a pallet (one batched call)",
           {{"speeds", "GRID", "speed columns, m/s (default 0.1:2:16)"},
            {"accels", "GRID", "start-up acceleration rows, m/s^2 (default 0.1:5:12)"},
            {"threads", "T", "worker threads, 0 = every CPU (default 0)"},
            {"estop-decel", "D", "emergency-stop deceleration of the line, m/s^2 (default 2)"},
            {"curve-radius", "R", "tightest curve of the line, m (default 3)"}},
           1,
           1},
          run_map};
}

}  // namespace pb::cli
