// SPDX-License-Identifier: MIT
// study standing: validate()'s standing rule against the simulation. Random pallets (any wrap,
// any layer range) are judged by the rule and, with the rule off, settled and held on a still belt
// for a while (SettleOptions::hold_s): does the rule refuse exactly the loads that cannot stand?
#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <thread>

#include "app/lab/lab_commands.hpp"
#include "core/analysis/analyzer.hpp"
#include "core/base/text.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/static_stability.hpp"

namespace pb::cli {

namespace {

struct StandingRow {
  std::uint64_t seed = 0;
  std::string notes;
  int items = 0;
  bool made = false;
  bool other_errors = false;  ///< refused by another rule (not judged)
  bool rule_stands = true;
  double min_margin_m = 0.0;
  bool simulated = false;
  bool sim_stands = true;
  std::string why;  ///< the rule's first standing error, the simulation's sentence, or an error
};

StandingRow judge(std::uint64_t seed, const RandomPalletOptions& base, double hold_s) {
  StandingRow row;
  row.seed = seed;
  RandomPalletOptions o = base;
  o.seed = seed;
  auto pallet = random_pallet(o, Catalog::builtin());
  if (!pallet) {
    row.why = "not made: " + pallet.diagnostics.front().message;
    return row;
  }
  row.made = true;
  row.notes = pallet->notes;
  row.items = int(pallet->items.size());
  ValidationLimits without;
  without.check_standing = false;
  if (has_errors(validate(*pallet, without))) {
    row.other_errors = true;
    return row;
  }
  for (const Diagnostic& d : errors_of(validate(*pallet))) {
    row.rule_stands = false;
    if (row.why.empty()) row.why = "rule: " + d.pointer + ": " + d.message;
  }
  row.min_margin_m = 1e9;
  for (const ItemStanding& s : standing(*pallet)) {
    if (s.supported()) row.min_margin_m = std::min(row.min_margin_m, s.margin_m);
  }
  AnalyzerOptions options;
  options.scene.require_standing = false;
  options.settle.hold_s = hold_s;
  options.settle.max_time_s = std::max(options.settle.max_time_s, hold_s + 1.0);
  Analyzer analyzer(options);
  auto prepared = analyzer.prepare(*pallet);
  if (!prepared) {
    row.why += (row.why.empty() ? "" : " | ") + std::string("simulation: ") +
               prepared.diagnostics.front().message;
    return row;
  }
  row.simulated = true;
  if (const auto& defect = (*prepared.value)->rest.cannot_stand) {
    row.sim_stands = false;
    row.why += (row.why.empty() ? "" : " | ") + std::string("simulation: ") + defect->sentence;
  }
  return row;
}

}  // namespace

int run_study_standing(const Args& args) {
  const std::int64_t n = args.integer("corpus").value_or(200);
  if (n < 1 || n > 100000) throw UsageError{"study standing: --corpus must be 1 to 100000"};
  const std::int64_t seed = args.integer("seed").value_or(0);
  if (seed < 0) throw UsageError{"study standing: --seed must be 0 or more"};
  RandomPalletOptions base;
  base.wrap = random_wrap_option(args, "study standing", WrapType::none);
  base.min_layers = int(std::clamp<std::int64_t>(args.integer("min-layers").value_or(2), -1, 1000));
  base.max_layers = int(std::clamp<std::int64_t>(args.integer("max-layers").value_or(7), -1, 1000));
  if (Diagnostics bad = validate_random_options(base); has_errors(bad)) {
    throw UsageError{"study standing: --" + bad.front().pointer.substr(1) + ": " +
                     bad.front().message};
  }
  const double hold_s = args.number("hold").value_or(2.0);
  if (!(hold_s >= 0.0 && hold_s <= 30.0)) {
    throw UsageError{"study standing: --hold must be 0 to 30 seconds"};
  }
  const std::int64_t threads_wanted = args.integer("threads").value_or(0);
  if (threads_wanted < 0 || threads_wanted > 256) {
    throw UsageError{"study standing: --threads must be 0 (every CPU) to 256"};
  }
  const int threads = int(std::min<std::int64_t>(
      n, threads_wanted > 0 ? threads_wanted : std::max(1u, std::thread::hardware_concurrency())));

  std::vector<StandingRow> rows(static_cast<std::size_t>(n));
  std::atomic<std::int64_t> next{0};
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&] {
      for (std::int64_t i; (i = next++) < n;) {
        rows[std::size_t(i)] = judge(std::uint64_t(seed + i), base, hold_s);
      }
    });
  }
  for (auto& t : pool) t.join();

  int made = 0, other = 0, judged = 0, refused = 0, refused_falls = 0, passed = 0, passed_falls = 0,
      unsimulated = 0;
  for (const StandingRow& r : rows) {
    made += r.made;
    if (!r.made) continue;
    if (r.other_errors) {
      ++other;
      continue;
    }
    if (!r.simulated) {
      ++unsimulated;
      continue;
    }
    ++judged;
    if (r.rule_stands) {
      ++passed;
      passed_falls += !r.sim_stands;
    } else {
      ++refused;
      refused_falls += !r.sim_stands;
    }
  }
  std::cout << "study standing: " << n << " random pallets from seed " << seed << ", wrap "
            << (base.wrap ? std::string(to_string(*base.wrap)) : std::string("mixed")) << ", "
            << base.min_layers << "-" << base.max_layers << " layers; held " << fixed(hold_s, 1)
            << " s on a still belt\n"
            << "  made " << made << ", refused by another rule " << other
            << ", not simulated (engine error) " << unsimulated << ", judged " << judged << "\n"
            << "                     stands in simulation   cannot stand\n"
            << "  rule: stands       " << std::setw(20) << passed - passed_falls << "   "
            << std::setw(12) << passed_falls << "\n"
            << "  rule: cannot stand " << std::setw(20) << refused - refused_falls << "   "
            << std::setw(12) << refused_falls << "\n";
  if (const auto path = args.text("out")) {
    std::ofstream out(*path, std::ios::binary | std::ios::trunc);
    if (!out) throw UsageError{"study standing: cannot write '" + *path + "'"};
    out << "seed,items,rule_stands,min_margin_mm,simulated,sim_stands,notes,why\n";
    for (const StandingRow& r : rows) {
      auto quoted = [](std::string text) {
        std::replace(text.begin(), text.end(), '"', '\'');
        return "\"" + text + "\"";
      };
      out << r.seed << "," << r.items << "," << r.rule_stands << ","
          << fixed(1000.0 * r.min_margin_m, 1) << "," << r.simulated << "," << r.sim_stands << ","
          << quoted(r.notes) << "," << quoted(r.why) << "\n";
    }
  }
  for (const StandingRow& r : rows) {
    if (r.simulated && r.rule_stands && !r.sim_stands) {
      std::cerr << "study standing: seed " << r.seed
                << " passes the rule but cannot stand: " << r.why << "\n";
    }
  }
  return passed_falls > 0 ? kExitFailure : kExitOk;
}

}  // namespace pb::cli
