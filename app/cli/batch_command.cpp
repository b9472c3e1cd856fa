// SPDX-License-Identifier: MIT
// `palletballet-cli batch --n N --seed S [--threads T] [--out FILE]`: the batch study of random
// pallets (core/batch_study.hpp). The full study (per pallet) goes to FILE or, without --out, to
// stdout; with --out, stdout gets the summary only.
#include <fstream>
#include <iostream>

#include "app/cli/commands.hpp"
#include "core/batch_study.hpp"

namespace pb::cli {

namespace {

Json distribution_json(const Distribution& d) {
  return {{"count", d.count}, {"min", d.min}, {"p10", d.p10},  {"median", d.median},
          {"p90", d.p90},     {"max", d.max}, {"mean", d.mean}};
}

Json summary_json(const BatchStudyOptions& o, const BatchStudy& s) {
  return {{"n", o.n},
          {"seed", o.seed},
          {"anomaly_rate", o.pallet.anomaly_rate},
          {"wrap", o.pallet.wrap ? std::string(to_string(*o.pallet.wrap)) : "mixed"},
          {"confidence_samples", o.analyzer.confidence.samples},
          {"threads", s.threads},
          {"analysed", s.analysed},
          {"errors", s.errors},
          {"cache_hits", s.cache_hits},
          {"sims_run", s.sims},
          {"wall_s", s.wall_s},
          {"pallets_per_s", s.pallets_per_s},
          {"rejects", s.rejects},
          {"reject_modes", s.reject_modes},
          {"dominant_modes", s.dominant_modes},
          {"speed_governed_by", s.speed_governed_by},
          {"limits",
           {{"max_speed_mps", distribution_json(s.max_speed_mps)},
            {"max_accel_mps2", distribution_json(s.max_accel_mps2)},
            {"max_decel_mps2", distribution_json(s.max_decel_mps2)},
            {"max_lateral_g", distribution_json(s.max_lateral_g)}}}};
}

int run_batch(const Args& args) {
  BatchStudyOptions o;
  if (auto n = args.integer("n")) o.n = int(std::clamp<std::int64_t>(*n, -1, 1000000));
  if (auto seed = args.integer("seed")) {
    if (*seed < 0) throw UsageError{"batch: --seed must be 0 or more"};
    o.seed = std::uint64_t(*seed);
  }
  if (auto t = args.integer("threads")) o.threads = int(std::clamp<std::int64_t>(*t, -1, 100000));
  if (auto r = args.number("anomaly-rate")) o.pallet.anomaly_rate = *r;
  o.pallet.wrap = random_wrap_option(args, "batch", o.pallet.wrap);
  if (auto m = args.integer("confidence")) {
    if (*m < 0 || *m > 10000) throw UsageError{"batch: --confidence must be 0 to 10000 samples"};
    o.analyzer.confidence.samples = int(*m);
  }
  std::ofstream out;
  const auto path = args.text("out");
  if (path) {
    out.open(*path, std::ios::binary | std::ios::trunc);
    if (!out) throw UsageError{"batch: cannot write '" + *path + "'; check that its folder exists"};
  }
  auto study = run_batch_study(o);
  if (!study) {
    for (const auto& d : errors_of(study.diagnostics)) {
      const std::string option =
          d.pointer == "/anomaly_rate" ? "anomaly-rate" : d.pointer.substr(1);
      std::cerr << "palletballet-cli batch: --" << option << ": " << d.message << "\n";
    }
    return kExitBadInput;
  }
  Json summary = summary_json(o, *study);
  Json full = summary;
  Json pallets = Json::array();
  for (const StudyEntry& e : study->pallets) {
    Json p = {{"seed", e.seed},      {"pallet_id", e.pallet_id},     {"notes", e.notes},
              {"items", e.items},    {"config_hash", e.fingerprint}, {"cached", e.cached},
              {"wall_ms", e.wall_ms}};
    if (e.result) {
      p["result"] = safety_result_to_json(*e.result);
    } else {
      p["error"] = e.error;
    }
    pallets.push_back(std::move(p));
  }
  full["pallets"] = std::move(pallets);
  if (path) {
    out << full.dump(2) << "\n";
    if (!out.flush()) {
      std::cerr << "palletballet-cli batch: could not write all of '" << *path << "'\n";
      return kExitFailure;
    }
    summary["out"] = *path;
    print_json(summary);
  } else {
    print_json(full);
  }
  if (study->errors > 0) {
    std::cerr << "palletballet-cli batch: " << study->errors
              << " pallet(s) could not be analysed (see their \"error\")\n";
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

Command batch_command() {
  return {{"batch",
           "batch [--n N] [--seed S] [--threads T] [--anomaly-rate R] [--wrap W] [--confidence M] "
           "[--out FILE]",
           "the batch study: N random pallets analysed in parallel, limits and modes summarised",
           {{"n", "N", "pallets, seeds S .. S+N-1 (default 400)"},
            {"seed", "S", "first seed (default 0)"},
            {"threads", "T", "analysing threads, each its own analyzer; 0 = every CPU (default 0)"},
            {"anomaly-rate", "R", "scanner anomaly rate of the random pallets (default 0.08)"},
            {"wrap", "W", "none, shrink, stretch, banded or mixed (per pallet; default stretch)"},
            {"confidence", "M", "samples for each result's confidence (default 0: not estimated)"},
            {"out", "FILE", "write the full study there; stdout gets the summary"}},
           0,
           0},
          run_batch};
}

}  // namespace pb::cli
