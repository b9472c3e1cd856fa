// SPDX-License-Identifier: MIT
#include "core/analysis/analyzer.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>

#include "core/base/text.hpp"
#include "core/contract/fingerprint.hpp"
#include "core/inputs/validation.hpp"

namespace pb {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// What the confidence says, for the supervisor: the reason's last sentence. Each limit sits where
// this load starts to fail, so a limit friction or mass can move scores low by construction; a low
// score says the four limits together leave no room.
std::string confidence_sentence(const UncertaintyResult& c, const UncertaintySpread& spread) {
  const int judged = c.samples - c.unstable;
  if (judged <= 0) {
    return " No copy of the load with friction and masses varied ran to a verdict (all " +
           std::to_string(c.unstable) + " unstable): confidence unknown.";
  }
  std::string out =
      " At these limits " + std::to_string(c.failures) + " of " + std::to_string(judged) +
      " copies of the load with friction and masses varied (" +
      fixed(100.0 * spread.friction_sigma, 0) + " % and " + fixed(100.0 * spread.mass_sigma, 0) +
      " %) fail: confidence " + fixed(1.0 - c.p_fail, 2) + ".";
  if (1.0 - c.p_fail < 0.5) out += " Run this pallet below its limits, not at them.";
  return out;
}

// A load that cannot stand gets no conveyor limit: a reject whose reason is the build defect.
SafetyResult cannot_stand_result(const StandFailure& defect, const LineDescription& line) {
  SafetyResult r;
  r.verdict = Verdict::reject;
  r.speed_governed_by = SpeedGovernor::build_defect;
  r.dominant_failure_mode = FailureMode::cannot_stand;
  r.accel_mode = r.decel_mode = r.lateral_mode = r.speed_mode = FailureMode::cannot_stand;
  std::string sentence = defect.sentence;
  if (!sentence.empty()) sentence[0] = static_cast<char>(std::toupper(sentence[0]));
  r.reason = "Reject, build defect: " + sentence + ".";
  r.line_estop_decel_mps2 = line.estop_decel_mps2;
  r.line_curve_radius_m = line.curve_radius_m;
  r.sims_run = 1;  // the settle that found it
  return r;
}

// Why a load that cannot stand is not simulated on the conveyor, at the item where it starts.
Diagnostics cannot_stand_diagnostics(const StandFailure& defect) {
  const std::string pointer = defect.item >= 0 ? "/items/" + std::to_string(defect.item) : "/items";
  return {{pointer, defect.sentence, Severity::error}};
}

}  // namespace

Analyzer::Analyzer(AnalyzerOptions options, const FrictionModel& friction)
    : options_(std::move(options)), friction_(&friction) {}

void Analyzer::clear_cache() {
  prepared_.clear();
  results_.clear();
}

SceneOptions Analyzer::scene_options_for(const FidelityChoice& choice) const {
  SceneOptions o = options_.scene;
  o.merge_wrapped = choice.level == Fidelity::reduced;
  o.rigid_carrier = choice.rigid_carrier;
  // A clustered load with no free item is one rigid body, as the reduced model is: its numerics.
  const bool one_body = choice.level == Fidelity::reduced ||
                        (choice.level == Fidelity::clustered &&
                         std::none_of(o.rigid_carrier.begin(), o.rigid_carrier.end(),
                                      [](int c) { return c == kFreeItem; }));
  if (!one_body && options_.full_model_timestep_s) o.timestep_s = *options_.full_model_timestep_s;
  if (!one_body && options_.full_model_solref_s)
    o.contact_solref[0] = *options_.full_model_solref_s;
  return o;
}

FidelityChoice Analyzer::fidelity_choice(const PalletConfig& config) const {
  // The model level: reduced when the wrap holds the items rigidly, clustered when some items of
  // an unwrapped load cannot move (or when asked), else full.
  // The closed-form level needs no scene; a pallet prepared for it is simulated in full.
  if (options_.fidelity == Fidelity::full || options_.fidelity == Fidelity::closed_form) {
    return {Fidelity::full, "requested", {}};
  }
  auto friction = friction_->for_pallet(config);
  if (!friction) return {Fidelity::full, "requested", {}};
  const SearchConfig& s = options_.search;
  const double ceiling = std::max({s.accel_max_mps2, s.decel_max_mps2, s.lateral_max_g * kGravity});
  return choose_fidelity(
      config, *friction.value,
      load_reach_mps2(config, *friction.value, ceiling, options_.line.curve_radius_m),
      options_.sim.thresholds, options_.fidelity);
}

Diagnostics Analyzer::simulation_problems(const PalletConfig& config) const {
  if (options_.fidelity == Fidelity::closed_form) return {};  // nothing is simulated
  if (auto friction = friction_->for_pallet(config); !friction) return friction.diagnostics;
  return capacity_problems(config, scene_options_for(fidelity_choice(config)));
}

Result<PreparedPallet*> Analyzer::prepare(const PalletConfig& config) {
  const std::string key = config_fingerprint(config);
  if (auto it = prepared_.find(key); it != prepared_.end()) {
    ++cache_hits_;
    return Result<PreparedPallet*>{it->second.get(), {}};
  }
  const auto start = std::chrono::steady_clock::now();
  // Refused before its model level is chosen: choosing finds what rests on what (quadratic where
  // every item shares one footprint), and 20,000 cartons in one column took 80 s there before the
  // scene refused their count. Standing is judged with the scene (build_scene).
  ValidationLimits limits;
  limits.check_standing = false;
  if (Diagnostics bad = validate(config, limits); has_errors(bad)) {
    return Result<PreparedPallet*>::failure(std::move(bad));
  }
  FidelityChoice choice = fidelity_choice(config);
  // A reduced request that finds nothing to merge is the full model, at the full model's numerics.
  auto options_for = [&](const FidelityChoice& c) {
    SceneOptions o = scene_options_for(c);
    if (auto it = buffer_scale_.find(key); it != buffer_scale_.end()) o.buffer_scale = it->second;
    return o;
  };
  auto scene = build_scene(config, options_for(choice), *friction_);
  if (scene && choice.level == Fidelity::reduced && !scene.value->layout.merged) {
    choice = {Fidelity::full, "nothing to merge", {}};
    scene = build_scene(config, options_for(choice), *friction_);
  }
  if (!scene) return Result<PreparedPallet*>::failure(std::move(scene.diagnostics));
  auto prepared = std::make_unique<PreparedPallet>();
  prepared->fingerprint = key;
  prepared->scene = std::make_unique<Scene>(std::move(*scene.value));
  auto simulator = Simulator::create(*prepared->scene);
  if (!simulator) return Result<PreparedPallet*>::failure(std::move(simulator.diagnostics));
  prepared->simulator = std::make_unique<Simulator>(std::move(*simulator.value));
  auto rest = prepared->simulator->settle(options_.settle, options_.sim.thresholds);
  if (!rest) {
    if (grow_buffers(key, rest.diagnostics)) return prepare(config);
    return Result<PreparedPallet*>::failure(std::move(rest.diagnostics));
  }
  prepared->rest = std::move(*rest.value);
  prepared->bounds = quasi_static_bounds(config, prepared->scene->friction);
  if (choice.level == Fidelity::clustered) {
    // The model's mechanisms: a merged item cannot slip or tip (its onsets are beyond reach).
    for (auto* list : {&prepared->bounds.along, &prepared->bounds.across}) {
      std::erase_if(*list, [&](const QuasiStaticLimit& m) {
        return m.item >= 0 && choice.rigid_carrier[std::size_t(m.item)] != kFreeItem;
      });
    }
  }
  if (options_.symmetry_reduction && options_.fidelity == Fidelity::automatic &&
      choice.level == Fidelity::full && !prepared->rest.cannot_stand) {
    const SceneOptions so = options_for(choice);
    prepared->planes[0] = plane_model(config, ProbePlane::along, so);
    // Not across the belt: a curve turns the load (turning_frame.hpp), pushing copies at the same
    // Y but different X differently along the belt and, at their own radius, apart; on the
    // unwrapped corpus the reduced curve searches landed 1-4 steps below the reference where the
    // whole load's stayed within one (89 / 96 limits within a step against 87 / 96, at the full
    // model's solref 0.02 then).
    if (const PlaneModel* along = prepared->planes[0].get()) {
      choice.why += "; along the belt " + std::to_string(along->reduction.config.items.size()) +
                    " items stand for " + std::to_string(config.items.size()) + " (" +
                    std::to_string(along->reduction.copies) + " identical copies side by side)";
    }
  }
  prepared->fidelity = std::move(choice);
  prepared->prepare_ms = ms_since(start);
  PreparedPallet* out = prepared.get();
  prepared_.emplace(key, std::move(prepared));
  return Result<PreparedPallet*>{out, std::move(scene.diagnostics)};
}

std::unique_ptr<PlaneModel> Analyzer::plane_model(const PalletConfig& config, ProbePlane plane,
                                                  const SceneOptions& scene_options) {
  auto reduction = reduce_symmetric_stacks(config, plane);
  if (!reduction) return nullptr;
  auto model = std::make_unique<PlaneModel>();
  model->reduction = std::move(*reduction);
  auto scene = build_scene(model->reduction.config, scene_options, *friction_);
  if (!scene) return nullptr;
  model->scene = std::make_unique<Scene>(std::move(*scene.value));
  auto simulator = Simulator::create(*model->scene);
  if (!simulator) return nullptr;
  model->simulator = std::make_unique<Simulator>(std::move(*simulator.value));
  auto rest = model->simulator->settle(options_.settle, options_.sim.thresholds);
  // The whole load stands (prepare checked it); a reduced load that cannot is no stand-in for it.
  if (!rest || rest.value->cannot_stand) return nullptr;
  model->rest = std::move(*rest.value);
  return model;
}

void Analyzer::set_progress(ProgressCounter::Callback callback) {
  progress_ = std::move(callback);
}

void Analyzer::set_axis_found(AxisFound found) {
  axis_found_ = std::move(found);
}

SimOptions Analyzer::counting(ProgressCounter& counter) const {
  SimOptions sim = options_.sim;
  if (progress_) sim.progress = &counter;
  return sim;
}

void Analyzer::set_cancel(const CancelFlag* flag) {
  options_.sim.cancel = flag;
  options_.settle.cancel = flag;
}

bool Analyzer::grow_buffers(std::string key, const Diagnostics& why) {
  if (!mentions_buffer_overflow(why)) return false;
  double& scale = buffer_scale_.try_emplace(key, 1.0).first->second;
  if (scale >= 8.0) return false;  // three doublings: beyond that the layout itself is at fault
  scale *= 2.0;
  prepared_.erase(key);
  return true;
}

Diagnostics Analyzer::line_radius_problem(const PalletConfig& config) const {
  return validate_curve_radius(config, options_.line.curve_radius_m, kLineRadiusPointer);
}

Result<Envelope> Analyzer::envelope(const PalletConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  if (options_.fidelity == Fidelity::closed_form) {  // no simulation: the bounds are the answer
    Diagnostics diags = validate(config);
    if (!has_errors(diags)) {
      for (Diagnostic& d : line_radius_problem(config)) diags.push_back(std::move(d));
    }
    if (has_errors(diags)) return Result<Envelope>::failure(std::move(diags));
    auto friction = friction_->for_pallet(config);
    if (!friction) return Result<Envelope>::failure(std::move(friction.diagnostics));
    Envelope env = closed_form_envelope(quasi_static_bounds(config, *friction.value), options_.line,
                                        options_.search, options_.sim.thresholds);
    env.result.pallet_id = config.pallet_id;
    env.result.config_hash = config_fingerprint(config);
    env.result.sim_runtime_ms = ms_since(start);
    results_.insert_or_assign(env.result.config_hash, env.result);
    return Result<Envelope>{std::move(env), std::move(diags)};
  }
  auto prepared = prepare(config);
  if (!prepared) return Result<Envelope>::failure(std::move(prepared.diagnostics));
  if (auto bad = line_radius_problem(config); has_errors(bad)) {
    return Result<Envelope>::failure(std::move(bad));
  }
  PreparedPallet& p = **prepared.value;
  if (p.rest.cannot_stand) {
    Envelope env;
    env.result = cannot_stand_result(*p.rest.cannot_stand, options_.line);
    env.result.pallet_id = config.pallet_id;
    env.result.config_hash = p.fingerprint;
    env.result.fidelity = p.fidelity.level;
    env.result.sim_runtime_ms = ms_since(start);
    env.rest = p.rest;
    results_.insert_or_assign(p.fingerprint, env.result);
    return Result<Envelope>{std::move(env), {}};
  }
  auto model = [&](std::size_t plane) {
    const PlaneModel* m = p.planes[plane].get();
    return m ? ProbeModel{m->simulator.get(), &m->rest} : ProbeModel{p.simulator.get(), &p.rest};
  };
  ProgressCounter counter(progress_);
  const SimOptions sim = counting(counter);
  auto env = search_envelope(model(0), model(1), config, p.bounds, options_.line, options_.search,
                             sim, axis_found_);
  counter.settle();
  if (!env) {
    if (grow_buffers(p.fingerprint, env.diagnostics)) return envelope(config);
    return env;
  }
  env->rest = p.rest;  // the whole load's, whatever model the probes ran on
  env->result.pallet_id = config.pallet_id;
  env->result.config_hash = p.fingerprint;
  env->result.fidelity = p.fidelity.level;
  env->result.sim_runtime_ms = ms_since(start);
  if (options_.confidence.samples > 0 && env->result.verdict == Verdict::reject) {
    env->result.confidence = 0.0;
  } else if (options_.confidence.samples > 0) {
    auto c = limits_confidence(*p.scene, *env, options_.line, options_.search, options_.confidence,
                               options_.sim);
    if (!c) return Result<Envelope>::failure(std::move(c.diagnostics));
    // Every copy unstable leaves nothing judged: unknown, not 1.
    if (c->samples > c->unstable) env->result.confidence = 1.0 - c->p_fail;
    env->result.reason += confidence_sentence(*c, options_.confidence.spread);
    env->result.sims_run += c->sims;
    env->result.sim_runtime_ms = ms_since(start);
  }
  results_.insert_or_assign(p.fingerprint, env->result);
  return env;
}

Result<FailureMap> Analyzer::failure_map(const PalletConfig& config, const MapOptions& options) {
  auto prepared = prepare(config);
  if (!prepared) return Result<FailureMap>::failure(std::move(prepared.diagnostics));
  if (auto bad = line_radius_problem(config); has_errors(bad)) {
    return Result<FailureMap>::failure(std::move(bad));
  }
  const PreparedPallet& p = **prepared.value;
  if (p.rest.cannot_stand) {
    return Result<FailureMap>::failure(cannot_stand_diagnostics(*p.rest.cannot_stand));
  }
  ProgressCounter counter(progress_);
  const SimOptions sim = counting(counter);
  auto map = run_failure_map(*p.scene, p.rest, options, options_.line, options_.search, sim);
  counter.settle();
  return map;
}

Result<SafetyResult> Analyzer::analyze(const PalletConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  const std::string key = config_fingerprint(config);
  if (auto it = results_.find(key); it != results_.end()) {
    ++cache_hits_;
    SafetyResult cached = it->second;
    cached.pallet_id = config.pallet_id;
    cached.sims_run = 0;
    cached.sim_runtime_ms = ms_since(start);
    return Result<SafetyResult>{std::move(cached), {}};
  }
  auto env = envelope(config);
  if (!env) return Result<SafetyResult>::failure(std::move(env.diagnostics));
  return Result<SafetyResult>{env->result, std::move(env.diagnostics)};
}

void Analyzer::follow_wreck(const PalletConfig& config, PreparedPallet& p,
                            const ConveyorProfile& profile, SimOptions o, SimResult& verdict) {
  if (!p.aftermath_simulator && p.aftermath_problem.empty()) {
    SceneOptions so = p.scene->options;
    so.aftermath = true;
    auto scene = build_scene(config, so, *friction_);
    if (!scene) {
      p.aftermath_problem = scene.diagnostics.empty() ? "the aftermath model could not be built"
                                                      : scene.diagnostics[0].message;
    } else {
      p.aftermath_scene = std::make_unique<Scene>(std::move(*scene.value));
      auto simulator = Simulator::create(*p.aftermath_scene);
      if (!simulator) {
        p.aftermath_problem = simulator.diagnostics.empty() ? "no memory for the aftermath model"
                                                            : simulator.diagnostics[0].message;
        p.aftermath_scene.reset();
      } else {
        p.aftermath_simulator = std::make_unique<Simulator>(std::move(*simulator.value));
      }
    }
  }
  if (!p.aftermath_simulator) {
    verdict.aftermath_cut = "no aftermath: " + p.aftermath_problem;
    return;
  }
  o.fail_fast = false;
  o.follow_failure_s = kSolveAftermathS;
  SimResult wreck = p.aftermath_simulator->run(p.rest, profile, o);
  const bool same = wreck.outcome == Outcome::failed && wreck.failure && verdict.failure &&
                    wreck.failure->mode == verdict.failure->mode &&
                    wreck.failure->time_s == verdict.failure->time_s &&
                    wreck.failure->items == verdict.failure->items;
  if (!same) {
    verdict.aftermath_cut =
        "no aftermath: the model that follows the wreck did not reproduce the first failure";
    verdict.wall_ms += wreck.wall_ms;
    return;
  }
  wreck.wall_ms += verdict.wall_ms;
  verdict = std::move(wreck);
}

Result<Solve> Analyzer::solve(const PalletConfig& config, const ConveyorProfile& profile,
                              double replay_hz) {
  Diagnostics problems = validate_profile(profile, "/profile");
  if (has_errors(problems)) return Result<Solve>::failure(std::move(problems));
  auto prepared = prepare(config);
  if (!prepared) return Result<Solve>::failure(std::move(prepared.diagnostics));
  if (profile.shape == ProfileShape::curve) {
    auto bad = validate_curve_radius(config, profile.curve_radius_m, "/profile/curve_radius_m");
    if (has_errors(bad)) return Result<Solve>::failure(std::move(bad));
  }
  PreparedPallet& p = **prepared.value;
  if (p.rest.cannot_stand) {
    return Result<Solve>::failure(cannot_stand_diagnostics(*p.rest.cannot_stand));
  }
  SimOptions o = options_.sim;
  o.record_trace = true;
  o.energy_stop = false;          // the replay shows a slide to its end (the verdict is the same)
  o.project_pallet_slip = false;  // and a slip crossing its threshold (the wreck follows from it)
  Solve solve;
  solve.sim = p.simulator->run(p.rest, profile, o);  // the verdict, as a search sees it
  if (solve.sim.outcome == Outcome::failed) follow_wreck(config, p, profile, o, solve.sim);
  solve.replay =
      make_replay(solve.sim.trace, config, profile, std::string(to_string(solve.sim.outcome)),
                  solve.sim.failure, replay_hz);
  return Result<Solve>{std::move(solve), std::move(problems)};
}

}  // namespace pb
