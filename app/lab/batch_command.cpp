// SPDX-License-Identifier: MIT
// `palletballet-lab batch --n N --seed S [--threads T] [--out FILE]`: the batch study of random
// pallets (core/lab/batch_study.hpp). The full study (per pallet) goes to FILE or, without --out,
// to stdout; with --out, stdout gets the summary only.
#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "app/lab/lab_commands.hpp"
#include "core/inputs/pallet_source.hpp"
#include "core/lab/batch_study.hpp"

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

// "--shard I/N": the I-th (from 0) of N contiguous blocks of the study's seeds.
struct Shard {
  int index = 0, count = 1;
};

std::optional<Shard> shard_option(const Args& args) {
  const auto text = args.text("shard");
  if (!text) return std::nullopt;
  Shard s;
  char slash = 0;
  std::istringstream in(*text);
  if (!(in >> s.index >> slash >> s.count) || slash != '/' || !in.eof() || s.count < 1 ||
      s.count > 100000 || s.index < 0 || s.index >= s.count) {
    throw UsageError{
        "batch: --shard takes I/N with 0 <= I < N (e.g. 3/8: the fourth of eight "
        "blocks of seeds), got '" +
        *text + "'"};
  }
  return s;
}

Json entry_json(const StudyEntry& e) {
  Json p = {{"seed", e.seed},      {"pallet_id", e.pallet_id},     {"notes", e.notes},
            {"items", e.items},    {"config_hash", e.fingerprint}, {"cached", e.cached},
            {"wall_ms", e.wall_ms}};
  if (e.result) {
    p["result"] = safety_result_to_json(*e.result);
  } else {
    p["error"] = e.error;
  }
  return p;
}

// A study written by `batch --out`, read back; an error names the file and what is wrong.
Result<Json> read_study(const std::string& path) {
  auto text = read_document_text(path);  // the error is ours, under the lab's name
  if (!text) return Result<Json>::failure("", "cannot open '" + path + "'; check the path");
  auto json = parse_json(*text);
  if (!json) return Result<Json>::failure("", path + ": " + to_string(json.diagnostics[0]));
  if (!json->is_object() || !(*json)["pallets"].is_array()) {
    return Result<Json>::failure(
        "", path + ": not a study written by 'batch --out' (no \"pallets\" list)");
  }
  return json;
}

// `batch --merge FILE...`: shards of one study joined: the same per-pallet results, summarised
// as one study. The shards must agree on what they analysed (anomaly rate, wrap, confidence).
int run_merge(const Args& args) {
  BatchStudy study;
  BatchStudyOptions o;
  std::map<std::uint64_t, std::string> seen;  // seed -> file
  double wall_max = 0.0, wall_sum = 0.0;
  Json first;
  for (const auto& path : args.positionals()) {
    auto json = read_study(path);
    if (!json) {
      std::cerr << "palletballet-lab batch --merge: " << json.diagnostics[0].message << "\n";
      return kExitBadInput;
    }
    if (first.is_null()) first = *json;
    for (const char* key : {"anomaly_rate", "wrap", "confidence_samples"}) {
      if ((*json)[key] != first[key]) {
        std::cerr << "palletballet-lab batch --merge: " << path << " has " << key << " "
                  << (*json)[key].dump() << " but " << args.positionals()[0] << " has "
                  << first[key].dump() << "; merge only shards of one study\n";
        return kExitBadInput;
      }
    }
    wall_max = std::max(wall_max, (*json)["wall_s"].get<double>());
    wall_sum += (*json)["wall_s"].get<double>();
    study.threads += (*json)["threads"].get<int>();
    for (std::size_t i = 0; i < (*json)["pallets"].size(); ++i) {
      const Json& p = (*json)["pallets"][i];
      StudyEntry e;
      e.seed = p.value("seed", std::uint64_t(0));
      if (auto [it, fresh] = seen.emplace(e.seed, path); !fresh) {
        std::cerr << "palletballet-lab batch --merge: seed " << e.seed << " is in both "
                  << it->second << " and " << path << "; give each shard once\n";
        return kExitBadInput;
      }
      e.pallet_id = p.value("pallet_id", "");
      e.notes = p.value("notes", "");
      e.items = p.value("items", 0);
      e.fingerprint = p.value("config_hash", "");
      e.cached = p.value("cached", false);
      e.wall_ms = p.value("wall_ms", 0.0);
      if (p.contains("result")) {
        auto r = safety_result_from_json(p["result"], "/pallets/" + std::to_string(i) + "/result");
        if (!r) {
          std::cerr << "palletballet-lab batch --merge: " << path << ": "
                    << to_string(r.diagnostics[0]) << "\n";
          return kExitBadInput;
        }
        e.result = std::move(*r.value);
      } else {
        e.error = p.value("error", "no result");
      }
      study.pallets.push_back(std::move(e));
    }
  }
  std::sort(study.pallets.begin(), study.pallets.end(),
            [](const StudyEntry& a, const StudyEntry& b) { return a.seed < b.seed; });
  summarise(study);
  study.wall_s = wall_max;  // the shards ran side by side
  study.pallets_per_s = wall_max > 0.0 ? double(study.pallets.size()) / wall_max : 0.0;
  o.n = int(study.pallets.size());
  o.seed = study.pallets.empty() ? 0 : study.pallets.front().seed;
  o.pallet.anomaly_rate = first.value("anomaly_rate", o.pallet.anomaly_rate);
  const std::string wrap = first.value("wrap", "mixed");
  o.pallet.wrap = enum_from_string<WrapType>(wrap);
  o.analyzer.confidence.samples = first.value("confidence_samples", 0);
  Json out = summary_json(o, study);
  out["shards"] = args.positionals().size();
  out["wall_s_sum"] = wall_sum;
  const bool contiguous =
      study.pallets.empty() ||
      study.pallets.back().seed - study.pallets.front().seed + 1 == study.pallets.size();
  if (!contiguous) {
    std::cerr << "palletballet-lab batch --merge: the shards' seeds have gaps (a shard is "
                 "missing?); the summary covers the seeds given\n";
  }
  Json pallets = Json::array();
  for (const StudyEntry& e : study.pallets) pallets.push_back(entry_json(e));
  out["pallets"] = std::move(pallets);
  print_json(out);
  return kExitOk;
}

int run_batch(const Args& args) {
  if (args.flag("merge")) {
    if (args.positionals().empty()) {
      throw UsageError{"batch: --merge needs the shards' study files (written by --out)"};
    }
    return run_merge(args);
  }
  if (!args.positionals().empty()) {
    throw UsageError{"batch: files are read only with --merge"};
  }
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
  const std::optional<Shard> shard = shard_option(args);
  if (shard) {
    if (shard->count > o.n) {
      throw UsageError{"batch: --shard " + std::to_string(shard->index) + "/" +
                       std::to_string(shard->count) + " asks for more shards than the " +
                       std::to_string(o.n) + " pallets of the study (--n)"};
    }
    // Contiguous blocks of seeds: [I n / N, (I + 1) n / N).
    const auto n = std::int64_t(o.n);
    const std::int64_t begin = shard->index * n / shard->count;
    const std::int64_t end = (shard->index + 1) * n / shard->count;
    o.seed += std::uint64_t(begin);
    o.n = int(end - begin);
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
      std::cerr << "palletballet-lab batch: --" << option << ": " << d.message << "\n";
    }
    return kExitBadInput;
  }
  Json summary = summary_json(o, *study);
  if (shard) summary["shard"] = std::to_string(shard->index) + "/" + std::to_string(shard->count);
  Json full = summary;
  Json pallets = Json::array();
  for (const StudyEntry& e : study->pallets) pallets.push_back(entry_json(e));
  full["pallets"] = std::move(pallets);
  if (path) {
    out << full.dump(2) << "\n";
    if (!out.flush()) {
      std::cerr << "palletballet-lab batch: could not write all of '" << *path << "'\n";
      return kExitFailure;
    }
    summary["out"] = *path;
    print_json(summary);
  } else {
    print_json(full);
  }
  if (study->errors > 0) {
    std::cerr << "palletballet-lab batch: " << study->errors
              << " pallet(s) could not be analysed (see their \"error\")\n";
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

Command batch_command() {
  Command c = {
      {"batch",
       "batch [--n N] [--seed S] [--threads T] [--anomaly-rate R] [--wrap W] [--confidence M] "
       "[--shard I/N] [--out FILE] | batch --merge FILE...",
       "the batch study: N random pallets analysed in parallel, limits and modes summarised; "
       "--shard runs one of N blocks of its seeds (one job of an array), --merge joins the "
       "shards' --out files into one study",
       {{"n", "N", "pallets, seeds S .. S+N-1 (default 400)"},
        {"seed", "S", "first seed (default 0)"},
        {"threads", "T", "analysing threads, each its own analyzer; 0 = every CPU (default 0)"},
        {"anomaly-rate", "R", "scanner anomaly rate of the random pallets (default 0.08)"},
        {"wrap", "W", "none, shrink, stretch, banded or mixed (per pallet; default stretch)"},
        {"confidence", "M", "samples for each result's confidence (default 0: not estimated)"},
        {"out", "FILE", "write the full study there; stdout gets the summary"},
        {"shard", "I/N",
         "analyse only the I-th (from 0) of N contiguous blocks of the seeds S .. S+N-1"},
        {"merge", "", "join study files written by --out (shards of one study) into one"}},
       0,
       100000},
      run_batch};
  c.spec.program = kLabProgram;
  return c;
}

}  // namespace pb::cli
