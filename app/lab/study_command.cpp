// SPDX-License-Identifier: MIT
// study speed-accuracy | stability | convergence: the numerical studies of issue 6. Every
// configuration's envelope against the slow reference configuration (CSV + PNG chart + table),
// where numerical methods fail (a classified table), and the reference's own convergence.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "app/lab/lab_commands.hpp"
#include "core/base/text.hpp"
#include "core/contract/fingerprint.hpp"
#include "core/lab/breakaway_study.hpp"
#include "core/lab/stability_study.hpp"
#include "core/lab/study.hpp"

#ifdef PB_HAVE_STUDY_CHART
#include "app/lab/chart/study_chart.hpp"
#endif

namespace pb::cli {

namespace {

namespace fs = std::filesystem;

// Bumped whenever the physics the reference runs changes, so that no cached envelope of the old
// physics is judged against: 2 = Coulomb friction (core/physics/step.hpp, 2026-11-26); 3 = curves
// turn the load (core/physics/turning_frame.hpp, session 15); 4 = a sliding pair slides by
// explicit Coulomb friction, not in MuJoCo's cone (core/physics/step.hpp, session 17).
constexpr const char* kReferenceCacheVersion = "reference-cache-4";

std::string cell(const std::string& text, int width, bool left) {
  std::ostringstream out;
  out << (left ? std::left : std::right) << std::setw(width) << text;
  return out.str();
}

void print_line(std::string line) {
  line.erase(line.find_last_not_of(' ') + 1);
  std::cout << line << "\n";
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string number_text(double v, int decimals) {
  return std::isfinite(v) ? fixed(v, decimals) : std::string("inf");
}

// The pallets of a study: --pallets (files or slugs) or the curated scenarios, then --corpus random
// pallets from --seed.
std::optional<std::vector<CorpusPallet>> corpus_from(const Args& args, int default_random) {
  const std::int64_t n = args.integer("corpus").value_or(default_random);
  if (n < 0 || n > 100000) throw UsageError{"study: --corpus must be between 0 and 100000"};
  const std::int64_t seed = args.integer("seed").value_or(1000);
  if (seed < 0) throw UsageError{"study: --seed must be 0 or more"};
  std::vector<CorpusPallet> corpus;
  if (auto list = args.text("pallets")) {
    std::stringstream in(*list);
    std::string arg;
    while (std::getline(in, arg, ',')) {
      if (arg.empty() || arg == "none") continue;
      auto input = read_pallet_source(arg);
      print_diagnostics(input.diagnostics);
      if (!input) return std::nullopt;
      corpus.push_back({arg, std::move(input->pallet)});
    }
  } else {
    corpus = study_corpus(0);
  }
  for (auto& p : study_corpus(static_cast<int>(n), static_cast<std::uint64_t>(seed), false)) {
    corpus.push_back(std::move(p));
  }
  if (corpus.empty()) throw UsageError{"study: the corpus is empty; give --pallets or --corpus N"};
  return corpus;
}

// ---- the reference cache: DIR/reference-cache/<key>.json, key = pallet x reference options ----

fs::path cache_path(const fs::path& dir, const StudyConfig& config, const PalletConfig& pallet) {
  const std::string key = fingerprint_json({{"version", kReferenceCacheVersion},
                                            {"pallet", config_fingerprint(pallet)},
                                            {"options", options_fingerprint(config.options)}});
  return dir / "reference-cache" / (key + ".json");
}

std::optional<StudySample> read_cached(const fs::path& path, const StudyConfig& config,
                                       const CorpusPallet& pallet) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::stringstream text;
  text << in.rdbuf();
  auto json = parse_json(text.str());
  if (!json || !json->is_object() || !json->contains("result")) return std::nullopt;
  StudySample s;
  s.config = config.name;
  s.pallet = pallet.label;
  s.wall_ms = json->value("wall_ms", 0.0);
  s.cpu_ms = json->value("cpu_ms", 0.0);
  s.sims = json->value("sims", 0);
  if ((*json)["result"].is_null()) {
    s.error = json->value("error", std::string("no result"));
    return s;
  }
  auto result = safety_result_from_json((*json)["result"]);
  if (!result) return std::nullopt;
  s.result = std::move(*result.value);
  return s;
}

void write_cached(const fs::path& path, const StudySample& s) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::ofstream out(path, std::ios::trunc);
  const Json json = {{"version", kReferenceCacheVersion},
                     {"pallet", s.pallet},
                     {"wall_ms", s.wall_ms},
                     {"cpu_ms", s.cpu_ms},
                     {"sims", s.sims},
                     {"error", s.error},
                     {"result", s.result ? safety_result_to_json(*s.result) : Json(nullptr)}};
  out << json.dump(2) << "\n";
}

// The envelope of `config` on `pallet`, from the cache when `cache` is set and it holds one.
StudySample envelope_sample(const StudyConfig& config, const CorpusPallet& pallet, bool cache,
                            const fs::path& dir, int* cache_hits) {
  const fs::path path = cache_path(dir, config, pallet.pallet);
  if (cache) {
    if (auto cached = read_cached(path, config, pallet)) {
      ++*cache_hits;
      return *cached;
    }
  }
  StudySample s = measure_envelope(config, pallet);
  if (cache) write_cached(path, s);
  return s;
}

void progress(std::size_t i, std::size_t n, const StudySample& s, bool cached) {
  std::cerr << "study: [" << i << "/" << n << "] " << s.pallet << " " << s.config << ": "
            << (s.result ? fixed(s.wall_ms, 0) + " ms" : "error: " + s.error)
            << (cached ? " (cached)" : "") << "\n";
}

// ---- speed-accuracy ----

void write_summary_csv(const fs::path& path, const std::vector<StudySummary>& rows) {
  std::ofstream out(path, std::ios::trunc);
  out << "config,description,fidelity,is_default,is_reference_equivalent,is_reference,pallets,"
         "errors,median_ms,median_cpu_ms,within_one_step,worst_error_steps,worst_pallet,"
         "worst_axis,mode_pallets,mode_agreement,pareto,limits_within_one_step,limits_above,"
         "worst_above_steps\n";
  for (const auto& r : rows) {
    out << csv_field(r.config) << "," << csv_field(r.description) << "," << csv_field(r.fidelity)
        << "," << r.is_default << "," << r.is_reference_equivalent << "," << r.is_reference << ","
        << r.pallets << "," << r.errors << "," << fixed(r.median_ms, 3) << ","
        << fixed(r.median_cpu_ms, 3) << "," << fixed(r.within_one_step, 4) << ","
        << number_text(r.worst_error_steps, 3) << "," << csv_field(r.worst_pallet) << ","
        << csv_field(r.worst_axis) << "," << r.mode_pallets << "," << fixed(r.mode_agreement, 4)
        << "," << r.pareto << "," << fixed(r.limits_within_one_step, 4) << "," << r.limits_above
        << "," << fixed(r.worst_above_steps, 3) << "\n";
  }
}

void write_samples_csv(const fs::path& path, const std::vector<StudySample>& samples) {
  std::ofstream out(path, std::ios::trunc);
  out << "pallet,config,fidelity,wall_ms,cpu_ms,sims,verdict,max_accel_mps2,max_decel_mps2,"
         "max_lateral_g,max_speed_mps,accel_mode,decel_mode,lateral_mode,speed_mode,"
         "err_accel_steps,err_decel_steps,err_lateral_steps,err_speed_steps,within_one_step,"
         "modes_compared,modes_agreeing,error\n";
  for (const auto& s : samples) {
    out << csv_field(s.pallet) << "," << csv_field(s.config) << ",";
    if (s.result) {
      const SafetyResult& r = *s.result;
      out << to_string(r.fidelity) << "," << fixed(s.wall_ms, 3) << "," << fixed(s.cpu_ms, 3) << ","
          << s.sims << "," << to_string(r.verdict) << "," << fixed(r.max_accel_mps2, 4) << ","
          << fixed(r.max_decel_mps2, 4) << "," << fixed(r.max_lateral_g, 4) << ","
          << fixed(r.max_speed_mps, 4) << "," << to_string(r.accel_mode) << ","
          << to_string(r.decel_mode) << "," << to_string(r.lateral_mode) << ","
          << to_string(r.speed_mode) << ",";
    } else {
      out << "," << fixed(s.wall_ms, 3) << "," << fixed(s.cpu_ms, 3) << "," << s.sims
          << ",,,,,,,,,,";
    }
    if (s.comparison) {
      for (double e : s.comparison->error_steps) out << fixed(e, 3) << ",";
      out << s.comparison->within_one_step << "," << s.comparison->modes_compared << ","
          << s.comparison->modes_agreeing << ",";
    } else {
      out << ",,,,,,,";
    }
    out << csv_field(s.error) << "\n";
  }
}

void print_summary_table(const std::vector<StudySummary>& rows) {
  print_line(cell("config", 22, true) + " " + cell("fidelity", 13, true) + " " +
             cell("n", 4, false) + " " + cell("median_ms", 10, false) + " " +
             cell("cpu_ms", 10, false) + " " + cell("within_1", 8, false) + " " +
             cell("limits_1", 8, false) + " " + cell("above", 5, false) + " " +
             cell("worst", 7, false) + " " + cell("modes", 6, false) + " " +
             cell("pareto", 6, true) + " " + cell("worst pallet (axis)", 20, true));
  for (const auto& r : rows) {
    std::string name = r.config;
    if (r.is_default) name += " (D)";
    if (r.is_reference_equivalent) name += " (RE)";
    if (r.is_reference) name += " (R)";
    print_line(cell(name, 22, true) + " " + cell(r.fidelity, 13, true) + " " +
               cell(std::to_string(r.pallets), 4, false) + " " +
               cell(fixed(r.median_ms, 1), 10, false) + " " +
               cell(fixed(r.median_cpu_ms, 1), 10, false) + " " +
               cell(fixed(r.within_one_step * 100.0, 1) + "%", 8, false) + " " +
               cell(fixed(r.limits_within_one_step * 100.0, 1) + "%", 8, false) + " " +
               cell(std::to_string(r.limits_above), 5, false) + " " +
               cell(number_text(r.worst_error_steps, 2), 7, false) + " " +
               cell(r.mode_pallets > 0 ? fixed(r.mode_agreement * 100.0, 0) + "%" : "-", 6, false) +
               " " + cell(r.pareto ? "*" : "", 6, true) + " " +
               (r.worst_pallet.empty() ? "" : r.worst_pallet + " (" + r.worst_axis + ")"));
  }
  std::cout
      << "(D) shipped default, (RE) reference-equivalent, (R) the reference; within_1 = share "
         "of pallets within one search step (0.1 m/s^2, 0.01 g, 0.05 m/s) of the reference "
         "on every limit; limits_1 = share of limits within one step; above = limits more than "
         "one step above the reference (unsafe); worst in steps; modes = governing-mode "
         "agreement where the "
         "reference fails more than one step below the ceiling; * = Pareto front\n";
}

int run_speed_accuracy(const Args& args) {
  auto configs = select_study_configs(args.text("configs").value_or(""), "--configs");
  if (!args.text("configs")) configs = Result<std::vector<StudyConfig>>{study_configs(), {}};
  if (!configs) {
    throw UsageError{"study speed-accuracy: --configs: " + configs.diagnostics.front().message};
  }
  const fs::path dir = args.text("out").value_or("study-speed-accuracy");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw UsageError{"study speed-accuracy: cannot create the folder '" + dir.string() + "'"};
  }
  auto corpus = corpus_from(args, 200);
  if (!corpus) return kExitBadInput;
  std::vector<StudySample> samples;
  int cache_hits = 0;
  const std::size_t total = corpus->size() * configs->size();
  std::size_t done = 0;
  for (const CorpusPallet& pallet : *corpus) {
    // The reference first: it judges the others.
    const int hits_before = cache_hits;
    StudySample ref = envelope_sample(configs->front(), pallet, true, dir, &cache_hits);
    progress(++done, total, ref, cache_hits > hits_before);
    if (ref.result) {
      ref.comparison = compare_envelopes(*ref.result, *ref.result);
      ref.reference_ok = true;
    }
    const std::optional<SafetyResult> reference = ref.result;
    samples.push_back(ref);
    for (std::size_t c = 1; c < configs->size(); ++c) {
      StudySample s = measure_envelope((*configs)[c], pallet);
      progress(++done, total, s, false);
      s.reference_ok = reference.has_value();
      if (reference && s.result) s.comparison = compare_envelopes(*reference, *s.result);
      samples.push_back(std::move(s));
    }
  }
  const std::vector<StudySummary> summary = summarize_study(*configs, samples);
  write_summary_csv(dir / "speed_accuracy.csv", summary);
  write_samples_csv(dir / "speed_accuracy_samples.csv", samples);
  std::cerr << "study: " << corpus->size() << " pallets, " << configs->size()
            << " configurations; reference envelopes from the cache: " << cache_hits << "\n"
            << "study: wrote " << (dir / "speed_accuracy.csv").string() << " and "
            << (dir / "speed_accuracy_samples.csv").string() << "\n";
#ifdef PB_HAVE_STUDY_CHART
  std::vector<StudyChartPoint> points;
  for (const auto& r : summary) {
    if (r.pallets == 0 || r.errors == r.pallets) continue;
    points.push_back({r.config, r.median_ms, r.within_one_step, r.worst_error_steps, r.pareto,
                      r.is_default, r.is_reference_equivalent, r.is_reference});
  }
  const std::string png = (dir / "speed_accuracy.png").string();
  const std::string chart_error =
      render_study_chart(points,
                         "Envelope: speed against accuracy (" + std::to_string(corpus->size()) +
                             " pallets, judged by the reference configuration)",
                         png);
  if (chart_error.empty()) {
    std::cerr << "study: wrote " << png << "\n";
  } else {
    std::cerr << "study: no chart: " << chart_error << "\n";
  }
#else
  std::cerr << "study: no chart: this palletballet-lab was built without Qt Charts "
               "(PB_BUILD_UI=OFF)\n";
#endif
  if (args.flag("json")) {
    Json out = Json::array();
    for (const auto& r : summary) out.push_back(study_summary_to_json(r));
    print_json(out);
  } else {
    print_summary_table(summary);
  }
  return kExitOk;
}

// ---- breakaway ----

// One axis's band on one line: each share's outcome (F failed, s safe, U unstable) and peak ratio.
std::string band_line(const char* axis, const std::vector<BandPoint>& points) {
  std::string line = std::string("  ") + axis + ":";
  for (const BandPoint& p : points) {
    const char* outcome = p.outcome == Outcome::failed ? "F"
                          : p.outcome == Outcome::safe ? "s"
                                                       : "U";
    line += " " + fixed(p.share, 3) + ":" + outcome + fixed(p.peak_ratio, 2);
  }
  return line;
}

int run_breakaway(const Args& args) {
  auto corpus = corpus_from(args, 0);
  if (!corpus) return kExitBadInput;
  auto configs = select_study_configs(args.text("configs").value_or("default"), "--configs");
  print_diagnostics(configs.diagnostics);
  if (!configs) return kExitBadInput;
  std::vector<int> windows(configs->size(), 0);
  for (const CorpusPallet& pallet : *corpus) {
    for (std::size_t c = 0; c < configs->size(); ++c) {
      const StudyConfig& config = (*configs)[c];
      auto band = breakaway_band(pallet.pallet, config.options);
      std::cout << pallet.label << " " << config.name;
      if (!band) {
        std::cout << ": " << (band.diagnostics.empty() ? "" : band.diagnostics[0].message) << "\n";
        continue;
      }
      std::cout << ": the pallet slips at " << fixed(band->onset_mps2, 3) << " m/s^2"
                << (band->reduced ? " (the searches' reduced model)" : "") << "\n"
                << band_line("start-up", band->start_up) << "\n"
                << band_line("stop", band->stop) << "\n";
      if (fails_below_a_hold(band->start_up) || fails_below_a_hold(band->stop)) ++windows[c];
    }
  }
  for (std::size_t c = 0; c < configs->size(); ++c) {
    std::cout << (*configs)[c].name << ": " << windows[c] << " of " << corpus->size()
              << " pallets fail at a share of the onset and hold at a higher one\n";
  }
  return kExitOk;
}

// ---- convergence ----

int run_convergence(const Args& args) {
  auto corpus = corpus_from(args, 0);
  if (!corpus) return kExitBadInput;
  const std::optional<std::string> out_dir = args.text("out");
  StudyConfig ref = study_configs().front();
  StudyConfig half = ref;
  half.name = "reference-0.25ms";
  half.options = reference_half_step_options();
  const SearchSteps steps = SearchSteps::of(ref.options.search);
  Json rows = Json::array();
  int hits = 0;
  bool all_within = true;
  for (const CorpusPallet& pallet : *corpus) {
    const fs::path dir = out_dir.value_or("");
    StudySample a = envelope_sample(ref, pallet, out_dir.has_value(), dir, &hits);
    progress(rows.size() * 2 + 1, corpus->size() * 2, a, false);
    StudySample b = envelope_sample(half, pallet, out_dir.has_value(), dir, &hits);
    progress(rows.size() * 2 + 2, corpus->size() * 2, b, false);
    Json row = {{"pallet", pallet.label}, {"ms_0_5", a.wall_ms}, {"ms_0_25", b.wall_ms}};
    if (a.result && b.result) {
      const EnvelopeComparison c =
          compare_envelopes(*a.result, *b.result, steps, ref.options.search);
      all_within = all_within && c.within_one_step;
      row["within_one_step"] = c.within_one_step;
      row["worst_steps"] = c.worst_steps;
      row["worst_axis"] = to_string(c.worst_axis);
      Json limits = Json::object();
      for (std::size_t i = 0; i < kStudyAxes.size(); ++i) {
        limits[std::string(to_string(kStudyAxes[i]))] = c.error_steps[i];
      }
      row["error_steps"] = limits;
      row["reference_0_5ms"] = safety_result_to_json(*a.result);
      row["reference_0_25ms"] = safety_result_to_json(*b.result);
    } else {
      all_within = false;
      row["error"] = a.result ? b.error : a.error;
    }
    rows.push_back(row);
  }
  if (args.flag("json")) {
    print_json(rows);
  } else {
    print_line(cell("pallet", 26, true) + " " + cell("ms@0.5", 9, false) + " " +
               cell("ms@0.25", 9, false) + " " + cell("accel", 6, false) + " " +
               cell("decel", 6, false) + " " + cell("lateral", 7, false) + " " +
               cell("speed", 6, false) + "  within one step");
    for (const auto& r : rows) {
      if (r.contains("error")) {
        print_line(cell(r["pallet"].get<std::string>(), 26, true) +
                   " error: " + r["error"].get<std::string>());
        continue;
      }
      const Json& e = r["error_steps"];
      print_line(cell(r["pallet"].get<std::string>(), 26, true) + " " +
                 cell(fixed(r["ms_0_5"].get<double>(), 0), 9, false) + " " +
                 cell(fixed(r["ms_0_25"].get<double>(), 0), 9, false) + " " +
                 cell(fixed(e["accel"].get<double>(), 2), 6, false) + " " +
                 cell(fixed(e["decel"].get<double>(), 2), 6, false) + " " +
                 cell(fixed(e["lateral"].get<double>(), 2), 7, false) + " " +
                 cell(fixed(e["speed"].get<double>(), 2), 6, false) + "  " +
                 (r["within_one_step"].get<bool>() ? "yes" : "NO"));
    }
    std::cout << "differences between the reference at 0.5 ms and at 0.25 ms, in the reference's "
                 "search steps (0.05 m/s^2, 0.005 g, 0.025 m/s)\n";
  }
  return all_within ? kExitOk : kExitFailure;
}

// ---- stability ----

int run_stability(const Args& args) {
  std::vector<StabilityCase> cases = stability_cases();
  if (auto only = args.text("cases")) {
    std::vector<StabilityCase> chosen;
    std::stringstream in(*only);
    std::string name;
    while (std::getline(in, name, ',')) {
      auto it = std::find_if(cases.begin(), cases.end(),
                             [&](const StabilityCase& c) { return c.name == name; });
      if (it == cases.end()) {
        std::string known;
        for (const auto& c : cases) known += (known.empty() ? "" : ", ") + c.name;
        throw UsageError{"study stability: --cases: unknown case '" + name + "'; choose from " +
                         known};
      }
      chosen.push_back(*it);
    }
    cases = std::move(chosen);
  }
  const std::vector<StabilityRow> rows = run_stability_study(cases);
  int missing = 0;
  for (const auto& r : rows) missing += r.missing_guard() ? 1 : 0;
  if (args.flag("json")) {
    Json out = Json::array();
    for (const auto& r : rows) out.push_back(stability_row_to_json(r));
    print_json(out);
  } else {
    print_line(cell("case", 28, true) + " " + cell("group", 22, true) + " " +
               cell("broken", 6, true) + " " + cell("classification", 18, true) + " detail");
    for (const auto& r : rows) {
      std::string detail = r.detail;
      if (detail.size() > 110) detail = detail.substr(0, 107) + "...";
      print_line(cell(r.c.name, 28, true) + " " + cell(r.c.group, 22, true) + " " +
                 cell(r.c.broken ? "yes" : "no", 6, true) + " " +
                 cell(std::string(to_string(r.got)) + (r.missing_guard() ? " (!)" : ""), 18, true) +
                 " " + detail);
    }
    std::cout
        << "probes at 0.8x and 1.3x of each pallet's closed-form bound (curves for the carton, "
           "start-ups for the slender carton), judged by the reference configuration; broken = "
           "numerically broken settings, which must "
           "come out detected unstable; (!) = a missing guard\n";
  }
  if (missing > 0) {
    std::cerr << "study stability: " << missing
              << " numerically broken case(s) gave a verdict: a guard is missing\n";
    return kExitFailure;
  }
  return kExitOk;
}

int run_study(const Args& args) {
  const std::string what = args.positionals().front();
  if (what == "speed-accuracy") return run_speed_accuracy(args);
  if (what == "stability") return run_stability(args);
  if (what == "convergence") return run_convergence(args);
  if (what == "standing") return run_study_standing(args);
  if (what == "breakaway") return run_breakaway(args);
  throw UsageError{"study: unknown study '" + what +
                   "'; choose speed-accuracy, stability, convergence, standing or breakaway"};
}

}  // namespace

std::vector<Command> study_commands() {
  std::vector<Command> out = {
      {{"study",
        "study speed-accuracy|stability|convergence|standing|breakaway [--corpus N] [--seed S] "
        "[--pallets LIST] [--configs LIST] [--out DIR] [--cases LIST] [--json] [--wrap W] "
        "[--min-layers A --max-layers B] [--hold S] [--threads T]",
        "Numerical studies. speed-accuracy: every configuration's envelope (fidelity x timestep "
        "x cone/solver, the shipped default, the reference-equivalent mode) against the reference "
        "configuration over the curated scenarios and N random pallets; writes CSV and a PNG "
        "chart to DIR, prints the table. stability: where numerical methods fail, each case "
        "classified correct / wrong verdict / detected unstable (exit 1 if a broken case gave a "
        "verdict). convergence: the reference at 0.5 ms against 0.25 ms (exit 1 if a limit moves "
        "more than one of its search steps). standing: N random pallets judged by validation's "
        "standing rule and, with the rule off, settled and held S seconds on a still belt; "
        "prints the 2x2 table, writes a CSV to --out FILE (exit 1 if a pallet the rule passes "
        "cannot stand). breakaway: start-ups and stops at 0.95-1.0 of each pallet's slip onset, "
        "in each of --configs (default: default and the reference), on the searches' model; "
        "counts the pallets that fail there and hold higher up.",
        {{"corpus", "N",
          "random pallets after the curated ones (speed-accuracy default 200, "
          "convergence default 0; standing: the pallets, default 200)"},
         {"seed", "S", "seed of the first random pallet (default 1000; standing 0)"},
         {"pallets", "LIST",
          "comma-separated pallet files or slugs instead of the curated "
          "scenarios ('none' for only random pallets)"},
         {"configs", "LIST",
          "comma-separated configurations (default all; the reference is "
          "always run): reference, default, reference-equivalent, closed-form, "
          "reduced-2ms, reduced-5ms, full-1ms, full-2ms, full-5ms, "
          "full-2ms-pyramidal, full-2ms-soft, full-2ms-implicit, full-2ms-newton, "
          "full-2ms-pgs, "
          "default-coarse"},
         {"out", "DIR",
          "folder for the CSV, the PNG and the reference cache (speed-accuracy "
          "default ./study-speed-accuracy; convergence caches there when given)"},
         {"cases", "LIST", "stability: only these cases"},
         {"wrap", "W", "standing: the random pallets' wrap, or mixed (default none)"},
         {"min-layers", "A", "standing: fewest layers (default 2)"},
         {"max-layers", "B", "standing: most layers (default 7)"},
         {"hold", "S", "standing: seconds on a still belt after the settle (default 2)"},
         {"threads", "T", "standing: pallets judged at once (default 0: every CPU)"},
         {"json", "", "print JSON instead of the table"}},
        1,
        1},
       run_study},
  };
  for (Command& c : out) c.spec.program = kLabProgram;
  return out;
}

}  // namespace pb::cli
