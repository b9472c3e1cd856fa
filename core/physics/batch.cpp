// SPDX-License-Identifier: MIT
#include "core/physics/batch.hpp"

#include <mujoco/mjxmacro.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <stop_token>
#include <thread>
#include <type_traits>

#include "core/physics/engine.hpp"
#include "core/physics/step.hpp"

namespace pb {

namespace {

// The row's fields: time, a scalar, first, then the state's arrays (sim_state.hpp) in their order.
constexpr int kFields = 1 + int(kStateArrays.size());

using Warnings = std::array<mjWarningStat, mjNWARNING>;

std::optional<BatchError> invalid(std::string message) {
  return BatchError{-1, {}, std::move(message)};
}

// Where one state field sits in a row of the state table.
struct Layout {
  std::array<int, kFields> offset{};
  std::array<int, kFields> width{};
  int stride = 0;

  explicit Layout(const mjModel& m) {
    width[0] = 1;
    for (std::size_t f = 1; f < kFields; ++f) width[f] = kStateArrays[f - 1].width(m);
    for (int f = 0; f < kFields; ++f) {
      offset[std::size_t(f)] = stride;
      stride += width[std::size_t(f)];
    }
  }
};

// A model field by name: its values (null if the field is not mjtNum) and how many there are.
struct FieldRef {
  bool found = false;
  mjtNum* values = nullptr;
  int size = 0;
};

template <class T>
FieldRef field_ref(T* values, int size) {
  if constexpr (std::is_same_v<T, mjtNum>) {
    return {true, values, size};
  } else {
    return {true, nullptr, size};
  }
}

FieldRef find_field(mjModel* m, std::string_view name) {
#undef MJ_M
#define MJ_M(n) m->n
#define X(type, field, nr, nc) \
  if (name == #field) return field_ref(m->field, m->nr * (nc));
  MJMODEL_POINTERS
#undef X
  if (name.starts_with("opt.")) {
    const std::string_view option = name.substr(4);
#define X(type, field) \
  if (option == #field) return field_ref(&m->opt.field, 1);
    MJOPTION_SCALARS
#undef X
#define X(field, size) \
  if (option == #field) return field_ref(m->opt.field, size);
    MJOPTION_VECTORS
#undef X
  }
#undef MJ_M
#define MJ_M(n) n
  return {};
}

// Calls fn(name, FieldRef) for every mjtNum pointer field of the model.
template <class F>
void for_each_real_field(mjModel* m, F&& fn) {
#undef MJ_M
#define MJ_M(n) m->n
#define X(type, field, nr, nc)                                    \
  {                                                               \
    const FieldRef ref = field_ref(m->field, m->nr * (nc));       \
    if (ref.values != nullptr) fn(std::string_view(#field), ref); \
  }
  MJMODEL_POINTERS
#undef X
#undef MJ_M
#define MJ_M(n) n
}

// Runs fn(worker, item) for every item in [0, n) on `workers` workers and blocks until done; the
// calling thread is worker 0. Item i belongs to the slice of worker i * workers / n, so a
// simulation stays on one worker (and its cache) across calls; a worker that has drained its
// slice takes items from the others through their atomic counters. Idle workers sleep on a
// condition variable. One run at a time; fn must not throw.
class WorkerPool {
 public:
  explicit WorkerPool(int workers) : workers_(workers), next_(std::size_t(workers)) {
    for (int w = 1; w < workers; ++w) {
      threads_.emplace_back([this, w](std::stop_token stop) { serve(stop, w); });
    }
  }

  void run(int n, const std::function<void(int, int)>& fn) {
    if (workers_ == 1 || n == 1) {
      for (int i = 0; i < n; ++i) fn(0, i);
      return;
    }
    {
      std::lock_guard lock(mu_);
      fn_ = &fn;
      n_ = n;
      for (int t = 0; t < workers_; ++t) {
        next_[std::size_t(t)].value.store(begin(t), std::memory_order_relaxed);
      }
      pending_ = workers_ - 1;
      ++epoch_;
    }
    wake_.notify_all();
    work(0);
    std::unique_lock lock(mu_);
    done_.wait(lock, [this] { return pending_ == 0; });
    fn_ = nullptr;
  }

 private:
  // One cache line each: every worker advances a counter on every item.
  struct alignas(64) Counter {
    std::atomic<int> value{0};
  };

  int begin(int slice) const { return static_cast<int>(std::int64_t{slice} * n_ / workers_); }

  void work(int worker) {
    for (int k = 0; k < workers_; ++k) {
      const int slice = (worker + k) % workers_;
      const int end = begin(slice + 1);
      auto& next = next_[std::size_t(slice)].value;
      for (int i = next.fetch_add(1, std::memory_order_relaxed); i < end;
           i = next.fetch_add(1, std::memory_order_relaxed)) {
        (*fn_)(worker, i);
      }
    }
  }

  void serve(std::stop_token stop, int worker) {
    std::uint64_t seen = 0;
    for (;;) {
      {
        std::unique_lock lock(mu_);
        if (!wake_.wait(lock, stop, [&] { return epoch_ != seen; })) return;
        seen = epoch_;
      }
      work(worker);
      std::lock_guard lock(mu_);
      if (--pending_ == 0) done_.notify_one();
    }
  }

  const int workers_;
  std::vector<Counter> next_;
  std::mutex mu_;
  std::condition_variable_any wake_;
  std::condition_variable_any done_;
  std::uint64_t epoch_ = 0;  // one per run; guarded by mu_, like the three below
  int pending_ = 0;
  int n_ = 0;
  const std::function<void(int, int)>* fn_ = nullptr;
  std::vector<std::jthread> threads_;  // last: stopped and joined before the rest goes
};

}  // namespace

struct Batch::Impl {
  // A model field made per simulation: one row per simulation, written into every worker's
  // model copy (`targets`) before that worker steps the simulation.
  struct Param {
    std::string name;
    int size = 0;
    std::vector<mjtNum> rows;
    std::vector<mjtNum*> targets;
  };

  Impl(ModelPtr m, int n, int workers, std::vector<DataPtr> worker_data)
      : model(std::move(m)),
        sims(n),
        layout(*model),
        states(std::size_t(n) * std::size_t(layout.stride)),
        warnings(std::size_t(n)),
        reset_row(std::size_t(layout.stride)),
        data(std::move(worker_data)),
        errors(std::size_t(n)),
        pool(workers) {}

  mjtNum* row(int sim) { return states.data() + std::ptrdiff_t(sim) * layout.stride; }

  void load(int sim, mjData* d) {
    const mjtNum* r = row(sim);
    d->time = r[0];
    for (std::size_t f = 1; f < kFields; ++f) {
      std::copy_n(r + layout.offset[f], layout.width[f], d->*kStateArrays[f - 1].data);
    }
    std::copy(warnings[std::size_t(sim)].begin(), warnings[std::size_t(sim)].end(), d->warning);
  }

  void store(const mjData* d, int sim) {
    mjtNum* r = row(sim);
    r[0] = d->time;
    for (std::size_t f = 1; f < kFields; ++f) {
      std::copy_n(d->*kStateArrays[f - 1].data, layout.width[f], r + layout.offset[f]);
    }
    std::copy_n(d->warning, mjNWARNING, warnings[std::size_t(sim)].begin());
  }

  SimState state_of(const mjtNum* r, const Warnings& warning) const {
    SimState s;
    s.time = r[0];
    for (std::size_t f = 1; f < kFields; ++f) {
      const mjtNum* first = r + layout.offset[f];
      (s.*kStateArrays[f - 1].state).assign(first, first + layout.width[f]);
    }
    s.warning = warning;
    return s;
  }

  std::optional<BatchError> check(const SimState& s) const {
    for (std::size_t f = 1; f < kFields; ++f) {
      const std::size_t given = (s.*kStateArrays[f - 1].state).size();
      if (given != std::size_t(layout.width[f])) {
        return invalid(std::string("the state's ") + kStateArrays[f - 1].name + " has " +
                       std::to_string(given) + " values but the model needs " +
                       std::to_string(layout.width[f]) + ": start from get_state or reset_state");
      }
    }
    return std::nullopt;
  }

  void write(const SimState& s, mjtNum* r, Warnings& warning) const {
    r[0] = s.time;
    for (std::size_t f = 1; f < kFields; ++f) {
      std::copy((s.*kStateArrays[f - 1].state).begin(), (s.*kStateArrays[f - 1].state).end(),
                r + layout.offset[f]);
    }
    warning = s.warning;
  }

  // The selected simulations, ascending, or why the selection is invalid.
  std::optional<BatchError> resolve(const Selection& selection, std::vector<int>& out) const {
    out.clear();
    if (selection.ids && selection.mask) {
      return invalid("a selection is ids or a mask, not both: make it with of_ids or of_mask");
    }
    if (selection.mask) {
      if (selection.mask->size() != std::size_t(sims)) {
        return invalid("the mask has " + std::to_string(selection.mask->size()) +
                       " flags but the batch has " + std::to_string(sims) +
                       " simulations: give one flag per simulation");
      }
      for (int i = 0; i < sims; ++i) {
        if ((*selection.mask)[std::size_t(i)]) out.push_back(i);
      }
      return std::nullopt;
    }
    if (!selection.ids) {
      for (int i = 0; i < sims; ++i) out.push_back(i);
      return std::nullopt;
    }
    int previous = -1;
    for (int id : *selection.ids) {
      if (id <= previous || id >= sims) {
        return invalid("simulation id " + std::to_string(id) + " is out of order, repeated or " +
                       "outside [0, " + std::to_string(sims) + "): give sorted unique ids");
      }
      previous = id;
    }
    out = *selection.ids;
    return std::nullopt;
  }

  mjModel* worker_model(int worker) {
    return models.empty() ? model.get() : models[std::size_t(worker)].get();
  }

  // Steps one simulation on `worker`; "" or why it failed.
  std::string advance(int sim, const mjModel* m, mjData* d, int nstep, const StepHooks& hooks) {
    for (int k = 0; k < nstep; ++k) {
      if (hooks.control) hooks.control(sim, *m, *d);
      pb::step(m, d);
      if (auto reason = instability_reason(m, d)) return *reason;
      if (hooks.observe && !hooks.observe(sim, *m, *d)) break;
    }
    return {};
  }

  void step_one(int worker, int sim, int nstep, const StepHooks& hooks) {
    if (hooks.wanted && !hooks.wanted(sim)) return;
    mjModel* m = worker_model(worker);
    for (const Param& p : params) {
      const mjtNum* first = p.rows.data() + std::ptrdiff_t(sim) * p.size;
      std::copy_n(first, p.size, p.targets[std::size_t(worker)]);
    }
    if (!stats.empty()) m->stat = stats[std::size_t(sim)];
    mjData* d = data[std::size_t(worker)].get();
    load(sim, d);
    std::string failure;
    try {
      if (auto error = guarded([&] { failure = advance(sim, m, d, nstep, hooks); })) {
        failure = *error;
      }
    } catch (const std::exception& e) {
      failure = std::string("a step hook threw: ") + e.what();
    } catch (...) {
      failure = "a step hook threw";
    }
    if (failure.empty()) {
      store(d, sim);
    } else {
      reset_data(m, d);  // an engine error leaves the stack pointer raised
      errors[std::size_t(sim)] = std::move(failure);
    }
  }

  // The failures of the last run among `items` (the failing simulations keep their state).
  std::optional<BatchError> collect(const std::vector<int>& items) {
    std::optional<BatchError> result;
    for (int sim : items) {
      std::string& error = errors[std::size_t(sim)];
      if (error.empty()) continue;
      if (!result) result = BatchError{sim, {}, "simulation " + std::to_string(sim) + ": " + error};
      result->failed.push_back(sim);
      error.clear();
    }
    return result;
  }

  // Gives every worker its own model copy, the first time a field is expanded.
  std::optional<std::string> copy_models() {
    if (!models.empty()) return std::nullopt;
    std::vector<ModelPtr> copies;
    for (std::size_t w = 0; w < data.size(); ++w) {
      mjModel* copy = nullptr;
      if (auto error = guarded([&] { copy = mj_copyModel(nullptr, model.get()); })) return error;
      if (copy == nullptr) return "MuJoCo could not copy the model";
      copies.emplace_back(copy);
    }
    models = std::move(copies);
    return std::nullopt;
  }

  ModelPtr model;
  const int sims;
  const Layout layout;
  std::vector<mjtNum> states;  // sims x layout.stride
  std::vector<Warnings> warnings;
  SimState reset_state;
  std::vector<mjtNum> reset_row;
  Warnings reset_warning{};
  std::vector<DataPtr> data;     // one per worker
  std::vector<ModelPtr> models;  // one per worker once a field is expanded
  std::vector<Param> params;
  std::vector<mjStatistic> stats;   // per simulation once set_const ran (mj_setConst writes it)
  std::vector<std::string> errors;  // per simulation, during a run (each written by one worker)
  std::vector<int> selected;        // of the current call
  mutable std::mutex call;          // serialises calls
  WorkerPool pool;
};

Result<Batch> Batch::create(const mjModel& model, int sims, int threads) {
  init_engine();
  if (sims < 1) {
    return Result<Batch>::failure(
        "", "a batch needs at least one simulation, not " + std::to_string(sims));
  }
  if (threads < 0) {
    return Result<Batch>::failure(
        "", "the thread count must be >= 0 (0: every logical CPU), not " + std::to_string(threads));
  }
  if (model.opt.enableflags & mjENBL_SENSORNOISE) {
    return Result<Batch>::failure(
        "",
        "sensor noise is enabled, and MuJoCo draws it from one process-wide generator, so "
        "results would depend on thread timing: disable the sensornoise flag");
  }
  if (threads == 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, sims);

  mjModel* copy = nullptr;
  if (auto error = guarded([&] { copy = mj_copyModel(nullptr, &model); })) {
    return Result<Batch>::failure("", *error);
  }
  if (copy == nullptr) return Result<Batch>::failure("", "MuJoCo could not copy the model");
  ModelPtr own(copy);
  std::vector<DataPtr> worker_data;
  for (int w = 0; w < threads; ++w) {
    auto d = make_data(own.get());
    if (!d) return Result<Batch>::failure(std::move(d.diagnostics));
    worker_data.push_back(std::move(*d.value));
  }
  auto impl = std::make_unique<Impl>(std::move(own), sims, threads, std::move(worker_data));
  mjData* fresh = impl->data.front().get();
  reset_data(impl->model.get(), fresh);
  impl->store(fresh, 0);
  std::copy_n(impl->row(0), impl->layout.stride, impl->reset_row.begin());
  impl->reset_warning = impl->warnings.front();
  impl->reset_state = impl->state_of(impl->reset_row.data(), impl->reset_warning);
  for (int i = 1; i < sims; ++i) impl->store(fresh, i);
  return Result<Batch>{Batch(std::move(impl)), {}};
}

Batch::Batch(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Batch::Batch(Batch&&) noexcept = default;
Batch& Batch::operator=(Batch&&) noexcept = default;
Batch::~Batch() = default;

int Batch::size() const {
  return impl_->sims;
}

int Batch::threads() const {
  return static_cast<int>(impl_->data.size());
}

const mjModel& Batch::model() const {
  return *impl_->model;
}

std::optional<BatchError> Batch::step(const Selection& selection, int nstep,
                                      const StepHooks& hooks) {
  Impl& b = *impl_;
  std::lock_guard lock(b.call);
  if (nstep < 0) return invalid("nstep must be >= 0, not " + std::to_string(nstep));
  if (auto error = b.resolve(selection, b.selected)) return error;
  const std::vector<int>& items = b.selected;
  b.pool.run(static_cast<int>(items.size()), [&](int worker, int item) {
    b.step_one(worker, items[std::size_t(item)], nstep, hooks);
  });
  return b.collect(items);
}

std::optional<BatchError> Batch::reset(const Selection& selection) {
  Impl& b = *impl_;
  std::lock_guard lock(b.call);
  if (auto error = b.resolve(selection, b.selected)) return error;
  for (int sim : b.selected) {
    std::copy(b.reset_row.begin(), b.reset_row.end(), b.row(sim));
    b.warnings[std::size_t(sim)] = b.reset_warning;
  }
  return std::nullopt;
}

SimState Batch::get_state(int sim) const {
  std::lock_guard lock(impl_->call);
  return impl_->state_of(impl_->row(sim), impl_->warnings[std::size_t(sim)]);
}

std::optional<BatchError> Batch::set_state(int sim, const SimState& state) {
  Impl& b = *impl_;
  std::lock_guard lock(b.call);
  if (sim < 0 || sim >= b.sims) {
    return invalid("simulation " + std::to_string(sim) + " is outside [0, " +
                   std::to_string(b.sims) + "): give a simulation of the batch");
  }
  if (auto error = b.check(state)) return error;
  b.write(state, b.row(sim), b.warnings[std::size_t(sim)]);
  return std::nullopt;
}

SimState Batch::reset_state() const {
  std::lock_guard lock(impl_->call);
  return impl_->reset_state;
}

std::optional<BatchError> Batch::set_reset_state(const SimState& state) {
  Impl& b = *impl_;
  std::lock_guard lock(b.call);
  if (auto error = b.check(state)) return error;
  b.write(state, b.reset_row.data(), b.reset_warning);
  b.reset_state = state;
  return std::nullopt;
}

BatchView Batch::view(StateField field) const {
  Impl& b = *impl_;
  const auto f = static_cast<std::size_t>(field);
  return {b.states.data() + b.layout.offset[f], b.layout.width[f], b.layout.stride, b.sims};
}

Result<BatchView> Batch::expand(std::string_view field) {
  Impl& b = *impl_;
  std::lock_guard lock(b.call);
  auto view_of = [&](Impl::Param& p) {
    return Result<BatchView>{BatchView{p.rows.data(), p.size, p.size, b.sims}, {}};
  };
  for (Impl::Param& p : b.params) {
    if (p.name == field) return view_of(p);
  }
  const FieldRef ref = find_field(b.model.get(), field);
  if (!ref.found) {
    return Result<BatchView>::failure(
        "", "the model has no field \"" + std::string(field) +
                "\": give an mjModel array (\"geom_friction\") or an option (\"opt.timestep\")");
  }
  if (ref.values == nullptr) {
    return Result<BatchView>::failure(
        "", "the field \"" + std::string(field) +
                "\" is not of type mjtNum: only real-valued fields can vary per simulation");
  }
  if (auto error = b.copy_models()) return Result<BatchView>::failure("", *error);
  Impl::Param p{std::string(field), ref.size, {}, {}};
  p.rows.reserve(std::size_t(b.sims) * std::size_t(ref.size));
  for (int i = 0; i < b.sims; ++i) p.rows.insert(p.rows.end(), ref.values, ref.values + ref.size);
  for (auto& m : b.models) p.targets.push_back(find_field(m.get(), field).values);
  b.params.push_back(std::move(p));
  return view_of(b.params.back());
}

std::optional<BatchError> Batch::set_const(const Selection& selection) {
  Impl& b = *impl_;
  std::lock_guard lock(b.call);
  std::vector<int> items;
  if (auto error = b.resolve(selection, items)) return error;
  if (items.empty()) return std::nullopt;
  if (auto error = b.copy_models()) return invalid(*error);
  const mjModel* base = b.model.get();
  mjModel* m = b.models.front().get();  // worker 0's copy, restored from `base` around each use
  mjData* d = b.data.front().get();
  auto restore = [&] { mj_copyModel(m, base); };

  // Work on copies: nothing changes unless every simulation succeeds.
  std::vector<std::vector<mjtNum>> rows;
  for (const Impl::Param& p : b.params) rows.push_back(p.rows);
  std::vector<std::string> added;  // derived fields to expand on success
  std::vector<mjStatistic> stats =
      b.stats.empty() ? std::vector<mjStatistic>(std::size_t(b.sims), base->stat) : b.stats;
  auto names_of = [&](std::size_t k) -> std::string_view {
    return k < b.params.size() ? std::string_view(b.params[k].name) : added[k - b.params.size()];
  };
  for (int round = 0; round < 3; ++round) {
    std::vector<std::string> differing;
    std::vector<int> failed;
    std::string first_error;
    for (int sim : items) {
      restore();
      for (std::size_t k = 0; k < rows.size(); ++k) {
        const FieldRef ref = find_field(m, names_of(k));
        std::copy_n(rows[k].data() + std::ptrdiff_t(sim) * ref.size, ref.size, ref.values);
      }
      if (auto error = guarded([&] { mj_setConst(m, d); })) {
        reset_data(m, d);
        if (failed.empty()) first_error = "simulation " + std::to_string(sim) + ": " + *error;
        failed.push_back(sim);
        continue;
      }
      for (std::size_t k = 0; k < rows.size(); ++k) {
        const FieldRef ref = find_field(m, names_of(k));
        std::copy_n(ref.values, ref.size, rows[k].data() + std::ptrdiff_t(sim) * ref.size);
      }
      stats[std::size_t(sim)] = m->stat;
      for_each_real_field(m, [&](std::string_view name, const FieldRef& ref) {
        bool expanded = false;
        for (std::size_t k = 0; k < rows.size(); ++k) expanded |= names_of(k) == name;
        if (expanded) return;
        const mjtNum* model_values = find_field(b.model.get(), name).values;
        if (std::equal(ref.values, ref.values + ref.size, model_values)) return;
        if (std::find(differing.begin(), differing.end(), name) == differing.end()) {
          differing.emplace_back(name);
        }
      });
    }
    restore();
    if (!failed.empty()) return BatchError{failed.front(), failed, first_error};
    if (differing.empty()) break;
    // Newly derived fields become per simulation, and every simulation gets its own values.
    for (const std::string& name : differing) {
      const FieldRef ref = find_field(b.model.get(), name);
      std::vector<mjtNum> seeded;
      seeded.reserve(std::size_t(b.sims) * std::size_t(ref.size));
      for (int i = 0; i < b.sims; ++i)
        seeded.insert(seeded.end(), ref.values, ref.values + ref.size);
      rows.push_back(std::move(seeded));
      added.push_back(name);
    }
    items.clear();
    for (int i = 0; i < b.sims; ++i) items.push_back(i);
  }
  // Commit: existing rows in place (their views stay valid), then the new fields.
  const std::size_t existing = b.params.size();
  for (std::size_t k = 0; k < existing; ++k) {
    std::copy(rows[k].begin(), rows[k].end(), b.params[k].rows.begin());
  }
  for (std::size_t a = 0; a < added.size(); ++a) {
    Impl::Param p{
        added[a], find_field(b.model.get(), added[a]).size, std::move(rows[existing + a]), {}};
    for (auto& copy : b.models) p.targets.push_back(find_field(copy.get(), p.name).values);
    b.params.push_back(std::move(p));
  }
  b.stats = std::move(stats);
  return std::nullopt;
}

}  // namespace pb
