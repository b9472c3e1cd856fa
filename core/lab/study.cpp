// SPDX-License-Identifier: MIT
#include "core/lab/study.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <utility>

#include "core/contract/fingerprint.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/scenario.hpp"

namespace pb {

namespace {

// The process's CPU time: an envelope may search its axes on several threads, and the study runs
// one envelope at a time.
double process_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Half the shipped steps of every axis.
SearchConfig fine_search(SearchConfig s) {
  s.speed_precision_mps *= 0.5;
  s.accel_precision_mps2 *= 0.5;
  s.decel_precision_mps2 *= 0.5;
  s.lateral_precision_g *= 0.5;
  return s;
}

double limit_of(const SafetyResult& r, Axis axis) {
  switch (axis) {
    case Axis::accel:
      return r.max_accel_mps2;
    case Axis::decel:
      return r.max_decel_mps2;
    case Axis::lateral:
      return r.max_lateral_g;
    case Axis::speed:
      return r.max_speed_mps;
  }
  return 0.0;
}

FailureMode mode_of(const SafetyResult& r, Axis axis) {
  switch (axis) {
    case Axis::accel:
      return r.accel_mode;
    case Axis::decel:
      return r.decel_mode;
    case Axis::lateral:
      return r.lateral_mode;
    case Axis::speed:
      return r.speed_mode;
  }
  return FailureMode::no_failure;
}

double step_of(const SearchSteps& s, Axis axis) {
  switch (axis) {
    case Axis::accel:
      return s.accel;
    case Axis::decel:
      return s.decel;
    case Axis::lateral:
      return s.lateral;
    case Axis::speed:
      return s.speed;
  }
  return 1.0;
}

double ceiling_of(const SearchConfig& s, Axis axis) {
  switch (axis) {
    case Axis::accel:
      return s.accel_max_mps2;
    case Axis::decel:
      return s.decel_max_mps2;
    case Axis::lateral:
      return s.lateral_max_g;
    case Axis::speed:
      return s.speed_max_mps;
  }
  return 0.0;
}

StudyConfig make(std::string name, std::string description, AnalyzerOptions options) {
  StudyConfig c;
  c.name = std::move(name);
  c.description = std::move(description);
  c.options = std::move(options);
  return c;
}

AnalyzerOptions at(Fidelity fidelity, double timestep_s) {
  AnalyzerOptions o;
  o.fidelity = fidelity;
  o.scene.timestep_s = timestep_s;
  o.full_model_timestep_s.reset();  // the configuration's numerics for every level
  o.full_model_solref_s.reset();
  return o;
}

}  // namespace

AnalyzerOptions reference_options() {
  AnalyzerOptions o;
  o.fidelity = Fidelity::full;
  o.scene.timestep_s = 0.0005;
  o.full_model_timestep_s.reset();
  o.full_model_solref_s.reset();
  o.scene.contact_solref = {0.005, 1.0};
  o.scene.solver = Solver::newton;  // converged Newton
  o.scene.iterations = 1000;
  o.scene.tolerance = 1e-12;
  o.search = fine_search(o.search);
  o.search.seed_with_closed_form = false;
  o.sim.skip_creeping = false;        // every step of a creeping load is stepped
  o.sim.project_pallet_slip = false;  // a slip fails where it crosses its threshold
  o.search.parallel_probes = 1;
  o.search.derive_axes = false;      // the judge probes every axis
  o.search.confirm_from_peak = 2.0;  // and takes each verdict as it comes
  return o;
}

AnalyzerOptions reference_half_step_options() {
  AnalyzerOptions o = reference_options();
  o.scene.timestep_s *= 0.5;
  return o;
}

AnalyzerOptions reference_equivalent_options() {
  AnalyzerOptions o;
  o.fidelity = Fidelity::full;
  o.scene.timestep_s = 0.002;
  o.scene = with_mujoco_solver(o.scene);  // the reference system keeps MuJoCo's defaults
  o.full_model_timestep_s.reset();
  o.full_model_solref_s.reset();
  o.search.seed_with_closed_form = false;
  o.search.parallel_probes = 1;
  o.search.axis_threads = 1;  // one probe after another, as the reference system searched
  o.search.derive_axes = false;
  o.search.confirm_from_peak = 2.0;
  o.sim.early_stop = false;
  o.sim.project_pallet_slip = false;
  return o;
}

std::vector<StudyConfig> study_configs() {
  std::vector<StudyConfig> out;
  StudyConfig ref = make("reference",
                         "the judge: full model, 0.5 ms, stiff contacts, converged Newton, plain "
                         "bisection at half steps",
                         reference_options());
  ref.is_reference = true;
  out.push_back(std::move(ref));
  StudyConfig def =
      make("default", "shipped: automatic fidelity (reduced 2 ms, full 1.5 ms), seeded search", {});
  def.is_default = true;
  out.push_back(std::move(def));
  StudyConfig eq = make("reference-equivalent",
                        "the reference system's algorithm: full model, 2 ms, plain bisection, no "
                        "early stop",
                        reference_equivalent_options());
  eq.is_reference_equivalent = true;
  out.push_back(std::move(eq));
  out.push_back(make("closed-form", "quasi-static bounds only (no simulation)",
                     at(Fidelity::closed_form, 0.002)));
  out.push_back(make("reduced-2ms", "reduced model (wrap-held items merged), 2 ms",
                     at(Fidelity::reduced, 0.002)));
  out.push_back(make("reduced-5ms", "reduced model, 5 ms", at(Fidelity::reduced, 0.005)));
  out.push_back(make("full-1ms", "full model, 1 ms", at(Fidelity::full, 0.001)));
  out.push_back(make("full-2ms", "full model, 2 ms (the default's settings, forced full)",
                     at(Fidelity::full, 0.002)));
  out.push_back(make("full-5ms", "full model, 5 ms", at(Fidelity::full, 0.005)));
  AnalyzerOptions pyramidal = at(Fidelity::full, 0.002);
  pyramidal.scene.cone = Cone::pyramidal;
  out.push_back(make("full-2ms-pyramidal", "full model, 2 ms, MuJoCo's pyramidal cone", pyramidal));
  AnalyzerOptions soft = at(Fidelity::full, 0.002);
  soft.scene.contact_solimp = {0.9, 0.95, 0.001, 0.5, 2.0};
  out.push_back(
      make("full-2ms-soft", "full model, 2 ms, MuJoCo's default contact impedance", soft));
  AnalyzerOptions implicit = at(Fidelity::full, 0.002);
  implicit.scene.integrator = Integrator::implicit;
  out.push_back(make("full-2ms-implicit",
                     "full model, 2 ms, implicit integrator (false belt creep, 2.4-3.7x per step)",
                     implicit));
  AnalyzerOptions newton = at(Fidelity::full, 0.002);
  newton.scene.solver = Solver::newton;
  out.push_back(make("full-2ms-newton", "full model, 2 ms, Newton solver", newton));
  AnalyzerOptions pgs = at(Fidelity::full, 0.002);
  pgs.scene.solver = Solver::pgs;
  out.push_back(make("full-2ms-pgs", "full model, 2 ms, PGS solver (slow)", pgs));
  AnalyzerOptions soft_full;  // the shipped default before session 15: solref 0.02 at every level
  soft_full.full_model_solref_s.reset();
  out.push_back(make("default-solref-0.02",
                     "shipped default with the full model's contacts as the reduced model's "
                     "(solref 0.02)",
                     soft_full));
  AnalyzerOptions stiff_full;  // the full model's contacts as stiff as the reference's
  stiff_full.full_model_solref_s = 0.005;
  out.push_back(make("default-solref-0.005",
                     "shipped default with the full model's contacts as stiff as the reference "
                     "configuration's (solref 0.005)",
                     stiff_full));
  AnalyzerOptions fixed_walk;  // the shipped default, its walk down in fixed steps
  fixed_walk.search.hasten_walk = false;
  out.push_back(make("default-fixed-walk",
                     "the default with the walk down in fixed steps (three single, then doubling)",
                     fixed_walk));
  AnalyzerOptions solver_kinetic;  // the shipped default, sliding pairs in MuJoCo's cone
  solver_kinetic.scene.solver_kinetic_friction = true;
  out.push_back(make("default-solver-kinetic",
                     "the default with sliding pairs in MuJoCo's friction cone at mu_d (a sliding "
                     "pallet hops; the model until session 17)",
                     solver_kinetic));
  for (double dt : {0.001, 0.002}) {  // the shipped default, the full model's timestep finer
    AnalyzerOptions other_dt;         // (the default until session 30) or coarser
    other_dt.full_model_timestep_s = dt;
    const std::string ms = dt == 0.002 ? "2" : "1";
    out.push_back(make("default-full-" + ms + "ms",
                       "the default with the full model at " + ms + " ms (solref 0.01)", other_dt));
  }
  // The shipped default, its solver's tolerance looser.
  for (const auto& [tol, name] : {std::pair{1e-7, "1e-7"}, std::pair{3e-7, "3e-7"}}) {
    AnalyzerOptions loose;
    loose.scene.tolerance = tol;
    out.push_back(
        make(std::string("default-tol-") + name,
             std::string("the default with the solver's tolerance at ") + name + " (1e-8)", loose));
  }
  AnalyzerOptions pyramid;  // the shipped default until session 28: pyramid, Newton
  pyramid.scene = with_mujoco_solver(pyramid.scene);
  out.push_back(make("default-pyramidal",
                     "the default in MuJoCo's pyramidal cone, solved by Newton (a load near its "
                     "onset chatters; the model until session 28)",
                     pyramid));
  AnalyzerOptions newton_default;  // the shipped default solved by Newton (until session 28)
  newton_default.scene.solver = Solver::newton;
  out.push_back(
      make("default-newton",
           "the default solved by Newton (dearer per step in large interlocked loads; the "
           "solver until session 28)",
           newton_default));
  AnalyzerOptions mujoco_cg;  // the shipped default, solved by MuJoCo's CG (until session 33)
  mujoco_cg.scene.solver = Solver::cg;
  out.push_back(make("default-mujoco-cg",
                     "the default solved by MuJoCo's CG, preconditioned by the mass matrix alone "
                     "(the solver until session 33)",
                     mujoco_cg));
  AnalyzerOptions coarse;  // the shipped default, search steps doubled
  coarse.search.accel_precision_mps2 *= 2.0;
  coarse.search.decel_precision_mps2 *= 2.0;
  coarse.search.lateral_precision_g *= 2.0;
  coarse.search.speed_precision_mps *= 2.0;
  out.push_back(make("default-coarse", "the default at twice the search steps", coarse));
  AnalyzerOptions band;  // the shipped default until session 31: each answer checked a step below
  band.search.band_checks = 3;
  out.push_back(make("default-band-checks",
                     "the default with each answer of a load whose items can move probed a step "
                     "below, up to three times (the default until session 31)",
                     band));
  AnalyzerOptions confirmed;  // the shipped default, each limit run again along another path
  confirmed.search.confirm_limits = true;
  out.push_back(make("default-confirmed",
                     "the default, each limit confirmed along a second numerical path", confirmed));
  return out;
}

Result<std::vector<StudyConfig>> select_study_configs(const std::string& names,
                                                      const std::string& pointer) {
  const std::vector<StudyConfig> all = study_configs();
  std::vector<StudyConfig> out{all.front()};
  std::set<std::string> seen{all.front().name};
  std::size_t start = 0;
  while (start <= names.size()) {
    const std::size_t comma = std::min(names.find(',', start), names.size());
    const std::string name = names.substr(start, comma - start);
    start = comma + 1;
    if (name.empty()) continue;
    auto it =
        std::find_if(all.begin(), all.end(), [&](const StudyConfig& c) { return c.name == name; });
    if (it == all.end()) {
      std::string known;
      for (const auto& c : all) known += (known.empty() ? "" : ", ") + c.name;
      return Result<std::vector<StudyConfig>>::failure(
          pointer, "unknown configuration '" + name + "'; choose from " + known);
    }
    if (seen.insert(name).second) out.push_back(*it);
  }
  return Result<std::vector<StudyConfig>>{std::move(out), {}};
}

std::string options_fingerprint(const AnalyzerOptions& o) {
  const SceneOptions& s = o.scene;
  const SearchConfig& q = o.search;
  Json j = {
      {"timestep_s", s.timestep_s},
      {"integrator", static_cast<int>(s.integrator)},
      {"solver", static_cast<int>(s.solver)},
      {"cone", static_cast<int>(s.cone)},
      {"impratio", s.impratio},
      {"iterations", s.iterations},
      {"tolerance", s.tolerance},
      {"solref", s.contact_solref},
      {"solimp", s.contact_solimp},
      {"belt", {s.belt_mass_kg, s.belt_kv_ratio}},
      {"gap", s.lateral_gap_m},
      {"neighbour", s.neighbour_distance_m},
      {"welds", s.wrap_welds},
      {"buffers", {s.nconmax, s.njmax, s.nstack}},
      {"settle",
       {o.settle.rest_speed_mps, o.settle.rest_spin_radps, o.settle.min_time_s, o.settle.max_time_s,
        o.settle.check_every_s}},
      {"early_stop", o.sim.early_stop},
      {"comove", {o.sim.comove_speed_mps, o.sim.comove_spin_radps}},
      {"line", {o.line.estop_decel_mps2, o.line.curve_radius_m, o.line.curve_angle_deg}},
      {"range",
       {q.speed_min_mps, q.speed_max_mps, q.accel_min_mps2, q.accel_max_mps2, q.decel_min_mps2,
        q.decel_max_mps2, q.lateral_min_g, q.lateral_max_g}},
      {"precision",
       {q.speed_precision_mps, q.accel_precision_mps2, q.decel_precision_mps2,
        q.lateral_precision_g}},
      {"hold", {q.hold_s, q.max_ramp_s}},
      {"seeded", q.seed_with_closed_form},
      {"fidelity", to_string(o.fidelity)},
  };
  // Only when set, so that the keys of cached reference envelopes (which leave it unset) hold.
  if (o.full_model_timestep_s) j["full_model_timestep_s"] = *o.full_model_timestep_s;
  if (o.full_model_solref_s) j["full_model_solref_s"] = *o.full_model_solref_s;
  if (q.confirm_limits) j["confirm_limits"] = true;
  if (q.confirm_from_peak <= 1.0) j["confirm_from_peak"] = q.confirm_from_peak;
  if (o.sim.skip_comoving && o.sim.skip_creeping) j["skip_creeping"] = true;
  if (o.sim.project_pallet_slip) j["project_pallet_slip"] = true;
  if (q.seed_with_closed_form && q.hasten_walk) j["hasten_walk"] = true;
  if (q.seed_with_closed_form && q.band_checks > 0) j["band_checks"] = q.band_checks;
  if (s.solver_kinetic_friction) j["solver_kinetic_friction"] = true;
  return fingerprint_json(j);
}

SearchSteps SearchSteps::of(const SearchConfig& s) {
  return {s.accel_precision_mps2, s.decel_precision_mps2, s.lateral_precision_g,
          s.speed_precision_mps};
}

EnvelopeComparison compare_envelopes(const SafetyResult& reference, const SafetyResult& candidate,
                                     const SearchSteps& steps, const SearchConfig& range) {
  constexpr double kSlack = 1e-6;  // rounding of limits built from sums of steps
  EnvelopeComparison c;
  c.verdict_agrees = reference.verdict == candidate.verdict;
  c.within_one_step = c.verdict_agrees;
  for (std::size_t i = 0; i < kStudyAxes.size(); ++i) {
    const Axis axis = kStudyAxes[i];
    const double step = step_of(steps, axis);
    const double ref = limit_of(reference, axis);
    const double signed_err = (limit_of(candidate, axis) - ref) / step;
    const double err = std::abs(signed_err);
    c.error_steps[i] = err;
    if (err <= 1.0 + kSlack) ++c.limits_within;
    if (signed_err > 1.0 + kSlack) {
      ++c.limits_above;
      c.worst_above_steps = std::max(c.worst_above_steps, signed_err);
    }
    if (err > c.worst_steps) {
      c.worst_steps = err;
      c.worst_axis = axis;
    }
    if (err > 1.0 + kSlack) c.within_one_step = false;
    // The mode is compared where the reference fails more than one step below the ceiling.
    if (ceiling_of(range, axis) - ref > step * (1.0 + kSlack)) {
      ++c.modes_compared;
      if (mode_of(reference, axis) == mode_of(candidate, axis)) ++c.modes_agreeing;
    }
  }
  return c;
}

std::vector<CorpusPallet> study_corpus(int random_count, std::uint64_t first_seed, bool curated) {
  std::vector<CorpusPallet> out;
  if (curated) {
    for (const Scenario& s : all_scenarios()) out.push_back({s.slug, s.pallet});
  }
  for (int i = 0; i < random_count; ++i) {
    RandomPalletOptions o;
    o.seed = first_seed + static_cast<std::uint64_t>(i);
    auto pallet = random_pallet(o, Catalog::builtin());
    if (pallet) out.push_back({"random-" + std::to_string(o.seed), std::move(*pallet.value)});
  }
  return out;
}

StudySample measure_envelope(const StudyConfig& config, const CorpusPallet& pallet) {
  StudySample s;
  s.config = config.name;
  s.pallet = pallet.label;
  Analyzer analyzer(config.options);
  const double cpu0 = process_cpu_ms();
  const auto start = std::chrono::steady_clock::now();
  auto env = analyzer.envelope(pallet.pallet);
  s.wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  s.cpu_ms = process_cpu_ms() - cpu0;
  if (!env) {
    for (const auto& d : errors_of(env.diagnostics)) {
      s.error += (s.error.empty() ? "" : "; ") + to_string(d);
    }
    if (s.error.empty()) s.error = "no result";
    return s;
  }
  s.sims = static_cast<int>(env->probes.size());
  s.result = env->result;
  return s;
}

std::vector<StudySummary> summarize_study(const std::vector<StudyConfig>& configs,
                                          const std::vector<StudySample>& samples) {
  std::vector<StudySummary> out;
  for (const StudyConfig& c : configs) {
    StudySummary s;
    s.config = c.name;
    s.description = c.description;
    s.is_default = c.is_default;
    s.is_reference_equivalent = c.is_reference_equivalent;
    s.is_reference = c.is_reference;
    std::vector<double> wall, cpu;
    std::set<std::string> levels;
    int within = 0, mode_ok = 0, limits_within = 0;
    for (const StudySample& x : samples) {
      if (x.config != c.name) continue;
      if (x.result) {
        wall.push_back(x.wall_ms);
        cpu.push_back(x.cpu_ms);
        levels.insert(std::string(to_string(x.result->fidelity)));
      } else {
        ++s.errors;
      }
      if (!x.comparison) {
        // No result where the reference has one: the worst outcome there is.
        if (!x.result && x.reference_ok) {
          ++s.pallets;
          s.worst_error_steps = std::numeric_limits<double>::infinity();
          s.worst_pallet = x.pallet;
          s.worst_axis = "error";
        }
        continue;
      }
      ++s.pallets;
      const EnvelopeComparison& cmp = *x.comparison;
      if (cmp.within_one_step) ++within;
      limits_within += cmp.limits_within;
      s.limits_above += cmp.limits_above;
      s.worst_above_steps = std::max(s.worst_above_steps, cmp.worst_above_steps);
      if (s.worst_pallet.empty() || cmp.worst_steps > s.worst_error_steps) {
        s.worst_error_steps = cmp.worst_steps;
        s.worst_pallet = x.pallet;
        s.worst_axis = std::string(to_string(cmp.worst_axis));
        if (!cmp.verdict_agrees) s.worst_axis += " (verdict differs)";
      }
      if (cmp.modes_compared > 0) {
        ++s.mode_pallets;
        if (cmp.modes_agree()) ++mode_ok;
      }
    }
    for (const auto& level : levels) s.fidelity += (s.fidelity.empty() ? "" : "+") + level;
    s.median_ms = median(wall);
    s.median_cpu_ms = median(cpu);
    s.within_one_step = s.pallets > 0 ? static_cast<double>(within) / s.pallets : 0.0;
    s.limits_within_one_step =
        s.pallets > 0 ? static_cast<double>(limits_within) / (4.0 * s.pallets) : 0.0;
    s.mode_agreement = s.mode_pallets > 0 ? static_cast<double>(mode_ok) / s.mode_pallets : 1.0;
    out.push_back(std::move(s));
  }
  // Pareto front over configurations with measurements: no other is at least as fast and at least
  // as accurate while strictly better in one.
  auto better_or_equal = [](const StudySummary& a, const StudySummary& b) {
    return a.median_ms <= b.median_ms && a.within_one_step >= b.within_one_step &&
           a.worst_error_steps <= b.worst_error_steps;
  };
  auto strictly_better = [](const StudySummary& a, const StudySummary& b) {
    return a.median_ms < b.median_ms || a.within_one_step > b.within_one_step ||
           a.worst_error_steps < b.worst_error_steps;
  };
  for (auto& s : out) {
    // The reference agrees with itself by definition: it anchors the chart, not the front.
    if (s.is_reference || s.pallets == 0 || s.errors == s.pallets) continue;
    s.pareto = std::none_of(out.begin(), out.end(), [&](const StudySummary& o) {
      return &o != &s && !o.is_reference && o.pallets > 0 && o.errors < o.pallets &&
             better_or_equal(o, s) && strictly_better(o, s);
    });
  }
  return out;
}

Json study_summary_to_json(const StudySummary& s) {
  return {{"config", s.config},
          {"description", s.description},
          {"is_default", s.is_default},
          {"is_reference_equivalent", s.is_reference_equivalent},
          {"is_reference", s.is_reference},
          {"fidelity", s.fidelity},
          {"pallets", s.pallets},
          {"errors", s.errors},
          {"median_ms", s.median_ms},
          {"median_cpu_ms", s.median_cpu_ms},
          {"within_one_step", s.within_one_step},
          {"limits_within_one_step", s.limits_within_one_step},
          {"limits_above", s.limits_above},
          {"worst_above_steps", s.worst_above_steps},
          {"worst_error_steps",
           std::isfinite(s.worst_error_steps) ? Json(s.worst_error_steps) : Json(nullptr)},
          {"worst_pallet", s.worst_pallet},
          {"worst_axis", s.worst_axis},
          {"mode_pallets", s.mode_pallets},
          {"mode_agreement", s.mode_agreement},
          {"pareto", s.pareto}};
}

ConvergenceRow reference_convergence(const CorpusPallet& pallet) {
  ConvergenceRow row;
  row.pallet = pallet.label;
  StudyConfig ref = study_configs().front();
  StudyConfig half = ref;
  half.name = "reference-0.25ms";
  half.options = reference_half_step_options();
  row.reference = measure_envelope(ref, pallet);
  row.half_step = measure_envelope(half, pallet);
  if (row.reference.result && row.half_step.result) {
    row.comparison = compare_envelopes(*row.reference.result, *row.half_step.result,
                                       SearchSteps::of(ref.options.search), ref.options.search);
  }
  return row;
}

}  // namespace pb
