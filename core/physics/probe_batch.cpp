// SPDX-License-Identifier: MIT
#include "core/physics/probe_batch.hpp"

#include <memory>

#include "core/physics/engine.hpp"
#include "core/physics/probe_run.hpp"

namespace pb {

Result<std::vector<SimResult>> run_probes_batched(const Scene& scene, const RestState& rest,
                                                  const std::vector<ConveyorProfile>& profiles,
                                                  const SimOptions& o, int threads,
                                                  const BatchConfigure& configure,
                                                  int* threads_used) {
  using Out = Result<std::vector<SimResult>>;
  if (profiles.empty()) return Out{std::vector<SimResult>{}, {}};
  const mjModel& m = *scene.model;
  auto batch = Batch::create(m, int(profiles.size()), threads);
  if (!batch) return Out::failure(std::move(batch.diagnostics));
  if (threads_used != nullptr) *threads_used = batch.value->threads();
  if (configure) {
    if (auto error = configure(*batch.value)) {
      return Out::failure("", "the batch could not be configured: " + *error);
    }
  }
  auto scratch = make_data(&m);
  if (!scratch) return Out::failure(std::move(scratch.diagnostics));
  mjData* d = scratch.value->get();
  std::vector<std::unique_ptr<ProbeRun>> runs;
  runs.reserve(profiles.size());
  std::vector<int> active;
  int nstep = 0;
  for (std::size_t k = 0; k < profiles.size(); ++k) {
    runs.push_back(std::make_unique<ProbeRun>(scene, rest, profiles[k], o));
    ProbeRun& run = *runs.back();
    const SimState start = start_state(scene.layout, rest, run.initial_speed());
    if (auto error = batch.value->set_state(int(k), start)) {
      return Out::failure("", "the batch could not load its start states: " + error->message);
    }
    if (run.done()) {
      if (run.result().outcome != Outcome::unstable) {
        reset_data(&m, d);
        restore_state(start, *d);
        run.finish(m, *d);
      }
    } else {
      active.push_back(int(k));
      nstep = std::max(nstep, run.max_steps());
    }
  }
  int stopped = 0;  // runs the engine stopped (not counted as they ended)
  if (!active.empty()) {
    StepHooks hooks;
    hooks.control = [&runs](int sim, const mjModel&, mjData& data) {
      runs[std::size_t(sim)]->before_step(data);
    };
    // Cancelled: the runs not yet started are not loaded and stepped once each just to stop.
    hooks.wanted = [&o](int) { return !is_cancelled(o.cancel); };
    hooks.observe = [&runs, &o](int sim, const mjModel& model, const mjData& data) {
      const bool more = runs[std::size_t(sim)]->after_step(model, data);
      if (!more && o.progress != nullptr) o.progress->finished();
      return more;
    };
    if (auto error = batch.value->step(Selection::of_ids(active), nstep, hooks)) {
      if (error->sim < 0) return Out::failure("", "the batch call failed: " + error->message);
      const std::string prefix = "simulation " + std::to_string(error->sim) + ": ";
      for (int sim : error->failed) {
        std::string why = "the engine stopped this simulation (error or instability)";
        if (sim == error->sim) {
          why = error->message.rfind(prefix, 0) == 0 ? error->message.substr(prefix.size())
                                                     : error->message;
        }
        runs[std::size_t(sim)]->engine_error(why);
        ++stopped;
      }
    }
  }
  std::vector<SimResult> out;
  out.reserve(runs.size());
  int uncounted = int(runs.size()) - int(active.size()) + stopped;  // done before stepping, stopped
  for (auto& run : runs) {
    if (!run->done()) {
      run->engine_error("the batch call ended before the run did");
      ++uncounted;
    }
    out.push_back(run->take_result());
  }
  if (o.progress != nullptr && uncounted > 0) o.progress->finished(uncounted);
  // A cancelled call is no answer: its stopped runs would read as unstable cells or samples.
  if (is_cancelled(o.cancel)) {
    return Out::failure(
        "", std::string(kCancelledReason) + ": the batched runs were stopped before they ended");
  }
  return Out{std::move(out), {}};
}

}  // namespace pb
