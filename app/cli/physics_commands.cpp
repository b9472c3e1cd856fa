// SPDX-License-Identifier: MIT
// Verbs over the physics core: mjcf, solve, analyze, bench.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "app/cli/commands.hpp"
#include "core/analysis/analyzer.hpp"
#include "core/analysis/fidelity.hpp"
#include "core/analysis/reference_search.hpp"
#include "core/analysis/result_json.hpp"
#include "core/base/text.hpp"
#include "core/inputs/scenario.hpp"
#include "core/inputs/validation.hpp"
#include "core/physics/scene.hpp"

namespace pb::cli {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// ---- shared ----

// The pallet a FILE argument names, or nullopt after printing why not. Warnings that come with
// the pallet are printed too.
std::optional<PalletSource> pallet_arg(const std::string& arg) {
  auto input = read_pallet_source(arg);
  print_diagnostics(input.diagnostics);
  if (!input) return std::nullopt;
  return std::move(*input.value);
}

// Diagnostics of the core about a pallet, with pointers into the document it was read from. An
// empty pointer is about no part of the input (the engine) and stays empty; the line's curve
// radius is the flag that sets it.
Diagnostics located(Diagnostics diagnostics, const PalletSource& input) {
  for (auto& d : diagnostics) {
    if (d.pointer == kLineRadiusPointer) {
      d.pointer = "--curve-radius";
    } else if (!d.pointer.empty()) {
      d.pointer = input.pointer_prefix + d.pointer;
    }
  }
  return diagnostics;
}

// A failure of the core is the input's fault when a diagnostic points into it (an invalid pallet,
// a load that will not come to rest) and the run's fault otherwise (the engine, instability).
int exit_code_for(const Diagnostics& diagnostics) {
  for (const auto& d : errors_of(diagnostics)) {
    if (!d.pointer.empty()) return kExitBadInput;
  }
  return kExitFailure;
}

// An output file opened before the work that fills it, so a bad path fails fast (exit 2).
std::ofstream open_output(const std::string& verb, const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw UsageError{verb + ": cannot write '" + path + "'; check that its folder exists"};
  return out;
}

Json messages_json(const Diagnostics& diagnostics) {
  Json out = Json::array();
  for (const auto& d : errors_of(diagnostics)) out.push_back(to_string(d));
  return out;
}

// ---- mjcf ----

int run_mjcf(const Args& args) {
  auto input = pallet_arg(args.positionals()[0]);
  if (!input) return kExitBadInput;
  auto scene = build_scene(input->pallet);
  if (!scene) {
    print_diagnostics(located(scene.diagnostics, *input));
    return exit_code_for(scene.diagnostics);
  }
  if (auto path = args.text("out")) {
    std::ofstream out = open_output("mjcf", *path);
    out << scene->mjcf;
    if (!out.flush()) throw UsageError{"mjcf: could not write all of '" + *path + "'"};
  } else {
    std::cout << scene->mjcf;
  }
  return kExitOk;
}

// ---- solve ----

// Shapes whose motion depends on accel_mps2 (the others start at speed or follow their own pulse).
bool uses_accel(ProfileShape shape) {
  return shape == ProfileShape::accel_hold || shape == ProfileShape::ramp_decel;
}

// The flags that set a profile's fields, and the fields they set.
constexpr std::pair<const char*, const char*> kProfileFlags[] = {
    {"speed", "target_speed_mps"},    {"accel", "accel_mps2"},      {"decel", "decel_mps2"},
    {"decel-start", "decel_start_s"}, {"radius", "curve_radius_m"}, {"angle", "curve_angle_deg"},
    {"eumos-g", "eumos_g"},           {"duration", "duration_s"}};

// Whether the scenario's suggested profile is the base the flags change: there is one, and
// --profile is absent or names its shape.
bool based_on_suggested(const Args& args, const std::optional<ConveyorProfile>& suggested) {
  if (!suggested) return false;
  const auto name = args.text("profile");
  return !name || enum_from_string<ProfileShape>(*name) == suggested->shape;
}

// The profile of the flags. A scenario's suggested profile is the base unless --profile names
// another shape, and every flag given overrides its field (so `solve SCENARIO --speed 2` runs the
// suggested motion at 2 m/s). Without a base --speed is required, and --accel for the shapes that
// use it. A changed motion runs default_duration_s, unless --duration says otherwise.
// Ranges are checked by validate_profile, not here.
ConveyorProfile profile_from(const Args& args, const std::optional<ConveyorProfile>& suggested) {
  std::optional<ProfileShape> shape;
  if (auto name = args.text("profile")) {
    shape = enum_from_string<ProfileShape>(*name);
    if (!shape) throw UsageError{"solve: --profile must be " + enum_choices<ProfileShape>()};
  }
  const bool based = based_on_suggested(args, suggested);
  ConveyorProfile p = based ? *suggested : ConveyorProfile{};
  if (shape) p.shape = *shape;
  const auto speed = args.number("speed");
  const auto accel = args.number("accel");
  if (!based && !speed) {
    throw UsageError{suggested ? "solve: --speed is required for a --profile other than the "
                                 "scenario's suggested " +
                                     std::string(to_string(suggested->shape))
                               : "solve: --speed is required (only a scenario brings a suggested "
                                 "profile)"};
  }
  if (!based && !accel && uses_accel(p.shape)) {
    throw UsageError{"solve: --accel is required for the " + std::string(to_string(p.shape)) +
                     " profile"};
  }
  p.target_speed_mps = speed.value_or(p.target_speed_mps);
  p.accel_mps2 = accel.value_or(p.accel_mps2);
  p.decel_mps2 = args.number("decel").value_or(p.decel_mps2);
  p.decel_start_s = args.number("decel-start").value_or(p.decel_start_s);
  p.curve_radius_m = args.number("radius").value_or(p.curve_radius_m);
  p.curve_angle_deg = args.number("angle").value_or(p.curve_angle_deg);
  p.eumos_g = args.number("eumos-g").value_or(p.eumos_g);
  if (auto way = args.text("turn")) {
    auto turn = enum_from_string<CurveTurn>(*way);
    if (!turn) throw UsageError{"solve: --turn must be " + enum_choices<CurveTurn>()};
    p.curve_turn = *turn;
  }
  const bool changed = !based || std::any_of(std::begin(kProfileFlags), std::end(kProfileFlags),
                                             [&](const auto& f) { return args.text(f.first); });
  if (auto duration = args.number("duration")) {
    p.duration_s = *duration;
  } else if (changed) {
    p.duration_s = based ? std::max(p.duration_s, default_duration_s(p)) : default_duration_s(p);
  }
  return p;
}

// A profile's diagnostics as its user can change them: at the field of the scenario's suggested
// profile where that set it, else at the flag that sets it ("--duration"), given or defaulted.
Diagnostics at_flags(Diagnostics diagnostics, const Args& args,
                     const std::optional<ConveyorProfile>& suggested) {
  const bool based = based_on_suggested(args, suggested);
  for (auto& d : diagnostics) {
    for (const auto& [flag, field] : kProfileFlags) {
      if (d.pointer == std::string("/profile/") + field) {
        d.pointer = args.text(flag) || !based ? std::string("--") + flag
                                              : "/suggested_profile/" + std::string(field);
      }
    }
  }
  return diagnostics;
}

// The levels a run simulates on (solve: closed_form has no simulation to run).
constexpr const char* kSimulatedLevels = "auto, reduced, clustered or full";

// --fidelity: which model answers (core/analysis/fidelity.hpp); automatic when absent. With
// `simulates`, only a level that simulates.
Fidelity fidelity_option(const Args& args, const std::string& verb, bool simulates = false) {
  const auto text = args.text("fidelity");
  if (!text) return Fidelity::automatic;
  const auto level = enum_from_string<Fidelity>(*text);
  if (!level) {
    throw UsageError{verb + ": --fidelity must be one of " +
                     (simulates ? std::string(kSimulatedLevels) : enum_choices<Fidelity>()) +
                     ", not '" + *text + "'"};
  }
  if (simulates && *level == Fidelity::closed_form) {
    throw UsageError{verb + ": --fidelity closed_form has no simulation to run; use " +
                     kSimulatedLevels};
  }
  return *level;
}

int run_solve(const Args& args) {
  AnalyzerOptions options;
  options.fidelity = fidelity_option(args, "solve", true);
  const double hz = option_in_range(args, "solve", "hz", 30.0, 0.0, 1000.0, "frames per second");
  auto input = pallet_arg(args.positionals()[0]);
  if (!input) return kExitBadInput;
  const ConveyorProfile profile = profile_from(args, input->suggested_profile);
  const Diagnostics problems =
      at_flags(validate_profile(profile, "/profile"), args, input->suggested_profile);
  // A bad profile is not run, so the pallet's errors are told with it (the run would refuse them
  // next): both are fixed at once.
  if (has_errors(problems)) print_diagnostics(located(errors_of(validate(input->pallet)), *input));
  print_diagnostics(problems);  // errors, and a warning when the run ends mid-motion
  if (has_errors(problems)) return kExitBadInput;
  std::optional<std::ofstream> replay_file;
  if (auto path = args.text("replay")) replay_file = open_output("solve", *path);

  Analyzer analyzer(options);
  auto solve = analyzer.solve(input->pallet, profile, hz);
  if (!solve) {
    print_diagnostics(located(solve.diagnostics, *input));
    return exit_code_for(solve.diagnostics);
  }
  if (replay_file) *replay_file << replay_to_json(solve->replay).dump() << "\n";
  Json out = sim_result_to_json(solve->sim, profile);
  if (auto prepared = analyzer.prepare(input->pallet)) {  // cached: the model that ran
    out["fidelity"] = to_string((*prepared.value)->fidelity.level);
    out["timestep_s"] = (*prepared.value)->scene->options.timestep_s;
  }
  print_json(out);
  if (solve->sim.outcome == Outcome::unstable) {
    std::cerr << "palletballet-cli solve: the simulation became numerically unstable, so there is "
                 "no verdict: "
              << solve->sim.reason << "\n";
    return kExitFailure;
  }
  return kExitOk;
}

// ---- analyze ----

AnalyzerOptions analyze_options(const Args& args) {
  AnalyzerOptions o;
  LineDescription& line = o.line;
  SearchConfig& search = o.search;
  line.estop_decel_mps2 =
      option_in_range(args, "analyze", "estop-decel", line.estop_decel_mps2, 0.0, 20.0, "m/s^2");
  line.curve_radius_m =
      option_in_range(args, "analyze", "curve-radius", line.curve_radius_m, 0.0, 1000.0, "m");
  search.speed_max_mps = option_in_range(args, "analyze", "speed-max", search.speed_max_mps,
                                         search.speed_min_mps, 5.0, "m/s");
  search.accel_max_mps2 = option_in_range(args, "analyze", "accel-max", search.accel_max_mps2,
                                          search.accel_min_mps2, 10.0, "m/s^2");
  if (auto k = args.integer("parallel-probes")) {
    if (*k < 0 || *k > 64) {
      throw UsageError{"analyze: --parallel-probes must be 0 (one per CPU) to 64"};
    }
    search.parallel_probes = int(*k);
  }
  search.confirm_limits = args.flag("confirm-limits");
  if (auto m = args.integer("confidence")) {
    if (*m < 1 || *m > 1000) throw UsageError{"analyze: --confidence must be 1 to 1000 samples"};
    o.confidence.samples = int(*m);
  }
  o.fidelity = fidelity_option(args, "analyze");
  return o;
}

struct FileAnalysis {
  Json entry;
  int exit_code = kExitOk;
};

// Each of `diagnostics` on stderr (many items' one problem told once: condensed), naming its
// file (analyze takes several).
void print_for(const std::string& source, const Diagnostics& diagnostics) {
  for (const auto& d : condensed(diagnostics)) {
    std::cerr << "palletballet-cli analyze: " << source << ": " << to_string(d) << "\n";
  }
}

FileAnalysis error_entry(const std::string& source, const Diagnostics& diagnostics, int code) {
  print_for(source, errors_of(diagnostics));
  return {{{"source", source}, {"error", messages_json(diagnostics)}}, code};
}

// One file's SafetyResult (from the analyzer's cache for a pallet seen before) or, with probes,
// its full envelope: every file's search is then run so that its probes can be listed.
FileAnalysis analyze_file(Analyzer& analyzer, const std::string& source, bool with_probes) {
  auto input = read_pallet_source(source);
  if (!input) return error_entry(source, input.diagnostics, kExitBadInput);
  print_for(source, input.diagnostics);
  // What validate warns of (a weight or size far from its SKU's, a low support), as validate
  // prints it: the analysis runs all the same.
  const Diagnostics warned = located(warnings_of(validate(input->pallet)), *input);
  print_for(source, warned);
  // The analysis's own warnings, less those just printed (the closed-form level returns
  // validate's).
  auto print_new_warnings = [&](const Diagnostics& diagnostics) {
    Diagnostics fresh;
    for (const Diagnostic& d : warnings_of(located(diagnostics, *input))) {
      if (std::find(warned.begin(), warned.end(), d) == warned.end()) fresh.push_back(d);
    }
    print_for(source, fresh);  // condensed together, as the others
  };
  Json entry;
  if (with_probes) {
    auto envelope = analyzer.envelope(input->pallet);
    if (!envelope) {
      const Diagnostics diags = located(envelope.diagnostics, *input);
      return error_entry(source, diags, exit_code_for(diags));
    }
    print_new_warnings(envelope.diagnostics);
    entry = safety_result_to_json(envelope->result);
    entry["probes"] = probes_to_json(envelope->probes);
    entry["speculative_sims"] = envelope->speculative;
  } else {
    auto result = analyzer.analyze(input->pallet);
    if (!result) {
      const Diagnostics diags = located(result.diagnostics, *input);
      return error_entry(source, diags, exit_code_for(diags));
    }
    print_new_warnings(result.diagnostics);
    entry = safety_result_to_json(*result);
  }
  entry["source"] = source;
  return {std::move(entry), kExitOk};
}

int run_analyze(const Args& args) {
  Analyzer analyzer(analyze_options(args));
  const bool with_probes = args.flag("probes");
  Json results = Json::array();
  int exit_code = kExitOk;
  for (const auto& source : args.positionals()) {
    FileAnalysis analysis = analyze_file(analyzer, source, with_probes);
    results.push_back(std::move(analysis.entry));
    exit_code = std::max(exit_code, analysis.exit_code);  // bad input (2) over a run failure (1)
  }
  print_json(results);
  return exit_code;
}

// ---- bench ----

struct BenchRun {
  double solve_ms = 0.0;
  double envelope_ms = 0.0;
  double prepare_ms = 0.0;
  int steps = 0;
  int steps_skipped = 0;  ///< of `steps`, jumped analytically (SimOptions::skip_comoving)
  Outcome outcome = Outcome::safe;
  SafetyResult result;
};

// One cold run: a fresh Analyzer (compile and settle included) searches the envelope, then
// solves the suggested profile on the settled scene.
Result<BenchRun> bench_once(const Scenario& scenario, Fidelity fidelity) {
  BenchRun run;
  AnalyzerOptions options;
  options.fidelity = fidelity;
  Analyzer analyzer(options);
  const auto start = std::chrono::steady_clock::now();
  auto envelope = analyzer.envelope(scenario.pallet);
  if (!envelope) return Result<BenchRun>::failure(std::move(envelope.diagnostics));
  run.envelope_ms = ms_since(start);
  run.result = envelope->result;
  auto prepared = analyzer.prepare(scenario.pallet);  // cached: reports its compile + settle
  if (!prepared) return Result<BenchRun>::failure(std::move(prepared.diagnostics));
  run.prepare_ms = (*prepared.value)->prepare_ms;
  auto solve = analyzer.solve(scenario.pallet, scenario.suggested_profile);
  if (!solve) return Result<BenchRun>::failure(std::move(solve.diagnostics));
  run.solve_ms = solve->sim.wall_ms;
  run.steps = solve->sim.steps;
  run.steps_skipped = solve->sim.steps_skipped;
  run.outcome = solve->sim.outcome;
  return Result<BenchRun>{std::move(run), {}};
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The medians of `runs` cold runs of one scenario; {"scenario", "error"} if one fails. With
// `reference`, each run is followed by a cold run of the reference system's search
// (reference_search.hpp) on the same pallet, so both see the same machine.
Json bench_scenario(const Scenario& scenario, int runs, Fidelity fidelity, bool reference) {
  std::vector<double> solve_ms, envelope_ms, prepare_ms, ref_ms;
  BenchRun last;
  int ref_sims = 0;
  for (int i = 0; i < runs; ++i) {
    std::cerr << "bench: " << scenario.slug << " run " << i + 1 << "/" << runs << "\n";
    auto run = bench_once(scenario, fidelity);
    if (!run) return {{"scenario", scenario.slug}, {"error", messages_json(run.diagnostics)}};
    solve_ms.push_back(run->solve_ms);
    envelope_ms.push_back(run->envelope_ms);
    prepare_ms.push_back(run->prepare_ms);
    last = std::move(*run.value);
    if (reference) {
      Analyzer cold(reference_search_options());
      auto ref = reference_search(cold, scenario.pallet);
      if (!ref) return {{"scenario", scenario.slug}, {"error", messages_json(ref.diagnostics)}};
      ref_ms.push_back(ref->wall_ms);
      ref_sims = ref->sims;
    }
  }
  const double solve = median(solve_ms);
  const int stepped = last.steps - last.steps_skipped;  // steps simulated
  const bool timed = stepped > 0 && solve > 0.0;
  return {{"scenario", scenario.slug},
          {"items", scenario.pallet.items.size()},
          {"runs", runs},
          {"solve_ms_median", solve},
          {"steps", last.steps},
          {"steps_skipped", last.steps_skipped},
          {"steps_per_s", timed ? stepped / (solve / 1000.0) : 0.0},
          {"us_per_step", timed ? solve * 1000.0 / stepped : 0.0},
          {"outcome", to_string(last.outcome)},
          {"prepare_ms_median", median(prepare_ms)},
          {"envelope_ms_median", median(envelope_ms)},
          {"sims_run", last.result.sims_run},
          {"max_speed_mps", last.result.max_speed_mps},
          {"max_accel_mps2", last.result.max_accel_mps2},
          {"verdict", to_string(last.result.verdict)},
          {"ref_ms", reference ? Json(median(ref_ms)) : Json(nullptr)},
          {"ref_sims", reference ? Json(ref_sims) : Json(nullptr)},
          {"ratio", reference ? Json(median(ref_ms) / median(envelope_ms)) : Json(nullptr)}};
}

// A cell padded to `width`: text to the left, numbers to the right.
std::string cell(const std::string& text, int width, bool left) {
  std::ostringstream out;
  out << (left ? std::left : std::right) << std::setw(width) << text;
  return out.str();
}

// One aligned row per scenario under a header.
void print_bench_table(const Json& rows) {
  struct Column {
    const char* key;
    const char* title;
    int width;
    int decimals;  // -1: text
  };
  const std::vector<Column> columns = {{"scenario", "scenario", 26, -1},
                                       {"items", "items", 5, 0},
                                       {"solve_ms_median", "solve_ms", 9, 1},
                                       {"steps", "steps", 6, 0},
                                       {"steps_skipped", "skipped", 7, 0},
                                       {"us_per_step", "us/step", 8, 1},
                                       {"steps_per_s", "steps/s", 8, 0},
                                       {"outcome", "outcome", 8, -1},
                                       {"prepare_ms_median", "prepare_ms", 10, 1},
                                       {"envelope_ms_median", "envelope_ms", 11, 1},
                                       {"sims_run", "sims", 5, 0},
                                       {"max_speed_mps", "speed", 6, 2},
                                       {"max_accel_mps2", "accel", 6, 2},
                                       {"verdict", "verdict", 7, -1},
                                       {"ref_ms", "ref_ms", 8, 1},
                                       {"ref_sims", "ref_sims", 8, 0},
                                       {"ratio", "ratio", 6, 1}};
  auto print_line = [](std::string line) {
    line.erase(line.find_last_not_of(' ') + 1);
    std::cout << line << "\n";
  };
  std::string header;
  for (const auto& c : columns) header += cell(c.title, c.width, c.decimals < 0) + " ";
  print_line(header);
  for (const auto& row : rows) {
    if (row.contains("error")) {
      print_line(cell(row["scenario"].get<std::string>(), 26, true) +
                 " error: " + row["error"].dump());
      continue;
    }
    std::string line;
    for (const auto& c : columns) {
      const Json& v = row[c.key];
      const std::string text = v.is_null()      ? std::string("-")
                               : c.decimals < 0 ? v.get<std::string>()
                                                : fixed(v.get<double>(), c.decimals);
      line += cell(text, c.width, c.decimals < 0) + " ";
    }
    print_line(line);
  }
}

int run_bench(const Args& args) {
  if (!args.positionals().empty()) {
    const std::string& what = args.positionals().front();
    if (what == "batch") return run_bench_batch(args);
    if (what == "scale") return run_bench_scale(args);
    throw UsageError{"bench: the sub-benchmarks are 'batch' and 'scale', not '" + what + "'"};
  }
  for (const char* scale_only : {"sizes", "patterns", "pallets"}) {
    if (args.flag(scale_only)) {
      throw UsageError{std::string("bench: --") + scale_only + " belongs to 'bench scale'"};
    }
  }
  for (const char* batch_only : {"sims", "threads", "nstep", "steps"}) {
    if (args.flag(batch_only)) {
      throw UsageError{std::string("bench: --") + batch_only + " belongs to 'bench batch'"};
    }
  }
  const std::int64_t runs = args.integer("runs").value_or(3);
  if (runs < 1 || runs > 1000) throw UsageError{"bench: --runs must be between 1 and 1000"};
  const Fidelity fidelity = fidelity_option(args, "bench");
  std::vector<Scenario> scenarios;
  if (auto slug = args.text("scenario")) {
    auto scenario = load_scenario(*slug);
    if (!scenario) {
      print_diagnostics(scenario.diagnostics);
      return kExitBadInput;
    }
    scenarios.push_back(std::move(*scenario.value));
  } else {
    scenarios = all_scenarios();
  }
  Json rows = Json::array();
  int exit_code = kExitOk;
  for (const auto& scenario : scenarios) {
    rows.push_back(
        bench_scenario(scenario, static_cast<int>(runs), fidelity, !args.flag("no-reference")));
    if (rows.back().contains("error")) exit_code = kExitFailure;
  }
  if (args.flag("json")) {
    print_json(rows);
  } else {
    print_bench_table(rows);
  }
  return exit_code;
}

}  // namespace

std::vector<Command> physics_commands() {
  const std::string file =
      "FILE is a PalletConfig file, a scenario file, - (stdin) or the slug of "
      "a curated scenario.";
  return {
      {{"mjcf",
        "mjcf FILE [--out PATH]",
        "The MuJoCo scene (MJCF) of a pallet on the belt, as the physics core simulates it; "
        "MuJoCo's viewer opens it. An invalid pallet exits 2 with every error as "
        "'pointer: message'. " +
            file,
        {{"out", "PATH", "write the MJCF to PATH instead of stdout"}},
        1,
        1},
       run_mjcf},
      {{"solve",
        "solve FILE --speed V --accel A [--profile SHAPE] [--duration S] [--decel D] "
        "[--decel-start S] [--radius R] [--angle DEG] [--eumos-g K] [--replay OUT.json] "
        "[--hz HZ]",
        "Simulate one conveyor profile from rest and print the outcome, the first failure and "
        "the run's statistics. A failed run is followed past its failure (the wreck, up to 3 s, "
        "until the load moves with the belt again), so its replay shows the pallet going over. "
        "A scenario's suggested profile is run unless --profile names another shape; each "
        "flag given overrides its field (--speed 2: the suggested motion at 2 m/s). Exit 0 for a "
        "safe or failed outcome, 2 for "
        "bad input, 1 when the simulation became unstable. " +
            file,
        {{"speed", "V", "target belt speed, m/s (required unless a scenario suggests a profile)"},
         {"accel", "A", "acceleration, m/s^2 (required for accel_hold and ramp_decel)"},
         {"profile", "SHAPE", enum_choices<ProfileShape>() + " (default accel_hold)"},
         {"duration", "S",
          "profile length, s (default: 5, or until the belt's motion last changes plus 1 s)"},
         {"decel", "D", "stop deceleration of estop, m/s^2 (default 2)"},
         {"decel-start", "S", "when ramp_decel and estop start to slow down, s (default 3)"},
         {"radius", "R", "curve radius, m (default 3)"},
         {"angle", "DEG", "curve angle, deg (default 90)"},
         {"turn", "WAY",
          "which way the curve turns: left (default; the load is pushed towards -Y) "
          "or right"},
         {"eumos-g", "K", "EUMOS 40509 test pulse, in g (default 0.5)"},
         {"replay", "OUT.json", "write the replay (poses at --hz) to OUT.json"},
         {"hz", "HZ", "replay frame rate (default 30)"},
         {"fidelity", "LEVEL",
          "auto, reduced, clustered or full: the model that runs (default auto; the level that "
          "ran is in the output's 'fidelity')"}},
        1,
        1},
       run_solve},
      {{"analyze",
        "analyze FILE... [--estop-decel D] [--curve-radius R] [--speed-max V] "
        "[--accel-max A] [--probes]",
        "The safe envelope of each pallet: a JSON array of SafetyResult, each with its 'source'. "
        "One analyzer serves every file, so a repeated pallet is answered from its cache (sims_run "
        "0). A file that cannot be analysed gets {\"source\", \"error\": [...]} and the others "
        "are still analysed; the exit code is then 2 if any input was bad, else 1. " +
            file,
        {{"estop-decel", "D", "emergency-stop deceleration of the line, m/s^2 (default 2)"},
         {"curve-radius", "R", "tightest curve of the line, m (default 3)"},
         {"speed-max", "V", "top of the speed search, m/s (default 2)"},
         {"accel-max", "A", "top of the start-up acceleration search, m/s^2 (default 5)"},
         {"probes", "",
          "list every probe of each search (axis, value, outcome, mode, failure_time_s, "
          "sim_time_s, steps, peak_ratio: how near it came to failing, load_peak_ratio: as near "
          "by the load's own detectors, confirmation, wall_ms) and "
          "speculative_sims (probes run ahead on spare cores and not needed); every file's search "
          "is then run, repeated pallets included"},
         {"fidelity", "LEVEL",
          enum_choices<Fidelity>() +
              ": the model that answers (default auto: the cheapest whose agreement with the "
              "full model is established). closed_form is an estimate, not simulated, that can be "
              "tenths above the simulated limits: auto never answers with it"},
         {"parallel-probes", "K",
          "probes per search round (k-section, batched on K threads; the same limits where "
          "failure is monotone in the demand, which a load that rocks near its limit need not "
          "be); 1 = serial bisection (default), 0 = one per CPU"},
         {"confirm-limits", "",
          "run each limit found safe once more along another numerical path (the constraint "
          "solve warm-started differently); where that run fails, the load's fate hangs on "
          "round-off there and the search goes on below it (probes then list confirmation: "
          "true; about a third more simulations on unwrapped loads)"},
         {"confidence", "M",
          "estimate each result's confidence from M samples (friction x lognormal 10 %, masses "
          "x N(1, 5 %)): the probability it survives all four limits; 4-5 x M more simulations (a "
          "curve in each "
          "turn for a load that is not its own mirror image across the belt). "
          "Without it confidence is null (not estimated)"}},
        1,
        1000000},
       run_analyze},
      {{"bench",
        "bench [batch|scale] [--runs N] [--json] [--scenario SLUG] [--no-reference] [--sims N] "
        "[--threads 1,2,...] [--nstep 1,10] [--steps S] [--sizes 24,48,...] "
        "[--patterns column,brick] [--pallets FILE,...]",
        "Time every curated scenario (or one): the solve of its suggested profile and its "
        "envelope from cold caches (compile and settle included, and reported apart), each the "
        "median of N runs, and the reference system's search on the same pallet after each run "
        "(full model at 2 ms, plain bisection of speed at 1 m/s^2 and of acceleration towards 1 "
        "m/s: ref_ms, and ratio = ref_ms / envelope_ms). A table by default. 'bench scale' "
        "analyses unwrapped pallets of about --sizes cartons (12 a layer of 0.30 x 0.25 x 0.20 m "
        "dairy cases; column and brick), or the --pallets given, each in a child process: items, "
        "degrees of freedom, contacts at rest, the items its searches simulate along the belt / "
        "across it (one copy of each group of identical stacks), microseconds per step, "
        "simulations, the steps their "
        "probes took (jumps not counted: a cost another load on the machine does not change, for "
        "comparing builds on a busy one), envelope ms and the child's peak resident memory. "
        "'bench batch' is the batch engine's scaling "
        "table instead: simulation-steps per second of a serial step loop (pb::step) and of the "
        "batch "
        "at each thread count and nstep, on one curated pallet (default stable-dairy-slab) "
        "settled once and riding a belt that keeps accelerating; each row also gives CPU "
        "seconds (a loaded machine shows there) and whether it ended bitwise where the serial "
        "loop did (exit 1 if not).",
        {{"runs", "N",
          "runs per scenario (default 3), per configuration for batch (default 3), or per "
          "pallet for scale (a fresh child process each; default 1)"},
         {"json", "", "print a JSON array instead of the table"},
         {"scenario", "SLUG", "only this curated scenario"},
         {"fidelity", "LEVEL",
          enum_choices<Fidelity>() + ": the model of every run (default auto)"},
         {"no-reference", "", "skip the reference system's search"},
         {"sizes", "LIST", "scale: cartons per pallet, multiples of 12 (default 24,48,72,96)"},
         {"patterns", "LIST", "scale: layer patterns, column and/or brick (default both)"},
         {"pallets", "LIST",
          "scale: these pallets (files or curated slugs, comma-separated) instead of the sizes' "
          "recipe; a row each, named by its file"},
         {"sims", "N", "batch: simulations (default 64)"},
         {"threads", "LIST", "batch: thread counts to time (default 1,2)"},
         {"nstep", "LIST", "batch: steps per call to time (default 1,10)"},
         {"steps", "S", "batch: steps per simulation, a multiple of every nstep (default 100)"}},
        0,
        1},
       run_bench},
  };
}

}  // namespace pb::cli
