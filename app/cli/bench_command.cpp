// SPDX-License-Identifier: MIT
// `bench batch`: the mjbatch scaling table for our scene. Simulation-steps per second of a serial
// step loop (pb::step) and of the batch at each thread count and nstep, on a curated pallet settled
// once and started riding along a belt that keeps accelerating (so every contact carries friction).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>

#include "app/cli/commands.hpp"
#include "core/base/text.hpp"
#include "core/inputs/scenario.hpp"
#include "core/physics/batch.hpp"
#include "core/physics/engine.hpp"
#include "core/physics/probe_run.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/simulate.hpp"
#include "core/physics/step.hpp"

namespace pb::cli {

namespace {

constexpr double kRideSpeed = 0.5;  // m/s, every body at the start
constexpr double kBeltAccel = 0.5;  // m/s^2 for simulation 0; the last one reaches 2x

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU seconds used by the whole process (every thread), user + system.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The belt of simulation `sim` of `sims`: speeds up at its own rate from the ride-along speed.
struct Belt {
  int act = -1;
  int sims = 1;
  void drive(int sim, const mjModel& m, mjData& d) const {
    const double accel = kBeltAccel * (1.0 + double(sim) / double(std::max(1, sims - 1)));
    d.ctrl[act] = kRideSpeed + accel * (d.time + m.opt.timestep);
  }
};

struct Setup {
  Scene scene;
  SimState start;  // settled, everything riding along at kRideSpeed
};

// The scene of a curated scenario, settled, as a batch state; or the reason it can't be.
Result<Setup> make_setup(const Scenario& scenario) {
  auto scene = build_scene(scenario.pallet);
  if (!scene) return Result<Setup>::failure(std::move(scene.diagnostics));
  Setup setup{std::move(*scene.value), {}};
  RestState rest;
  {
    auto sim = Simulator::create(setup.scene);
    if (!sim) return Result<Setup>::failure(std::move(sim.diagnostics));
    auto settled = sim->settle();
    if (!settled) return Result<Setup>::failure(std::move(settled.diagnostics));
    rest = std::move(*settled.value);
  }
  setup.start = start_state(setup.scene.layout, rest, kRideSpeed);
  return Result<Setup>{std::move(setup), {}};
}

struct Timing {
  double wall_s = 0.0;
  double cpu_s = 0.0;
};

struct Config {
  std::string mode;  // serial | batch
  int threads = 1;
  int nstep = 1;
  std::vector<Timing> reps;
  std::vector<double> final_qpos_x;  // the pallet's x of each simulation after the run
};

// The serial reference: one mjData; each simulation loaded from the start and stepped `steps`
// times in a plain loop with the same belt.
std::optional<std::string> run_serial(const Setup& setup, const Belt& belt, int sims, int steps,
                                      Config& config) {
  const mjModel& m = *setup.scene.model;
  auto made = make_data(&m);
  if (!made) return made.diagnostics.front().message;
  mjData* d = made->get();
  config.final_qpos_x.assign(std::size_t(sims), 0.0);
  // One untimed simulation warms the caches, as the batch's untimed first call does.
  if (auto error = guarded([&] {
        restore_state(setup.start, *d);
        for (int k = 0; k < steps; ++k) {
          belt.drive(0, m, *d);
          pb::step(&m, d);
        }
      })) {
    return error;
  }
  const auto wall = Clock::now();
  const double cpu = cpu_seconds();
  std::optional<std::string> failure;
  if (auto error = guarded([&] {
        for (int i = 0; i < sims && !failure; ++i) {
          restore_state(setup.start, *d);
          for (int k = 0; k < steps; ++k) {
            belt.drive(i, m, *d);
            pb::step(&m, d);
          }
          failure = instability_reason(&m, d);
          config.final_qpos_x[std::size_t(i)] = d->qpos[setup.scene.layout.pallet_qpos];
        }
      })) {
    return error;
  }
  if (failure) return "the serial loop became unstable: " + *failure;
  config.reps.push_back({seconds_since(wall), cpu_seconds() - cpu});
  return std::nullopt;
}

std::optional<std::string> run_batch(Batch& batch, const Belt& belt, int steps, int pallet_qpos,
                                     Config& config) {
  const StepHooks hooks{[&belt](int sim, const mjModel& m, mjData& d) { belt.drive(sim, m, d); },
                        {}};
  if (auto error = batch.reset()) return error->message;
  // One untimed call wakes the workers and warms their caches; then start over.
  if (auto error = batch.step({}, config.nstep, hooks)) return error->message;
  if (auto error = batch.reset()) return error->message;
  const int calls = steps / config.nstep;
  const auto wall = Clock::now();
  const double cpu = cpu_seconds();
  for (int c = 0; c < calls; ++c) {
    if (auto error = batch.step({}, config.nstep, hooks)) return error->message;
  }
  config.reps.push_back({seconds_since(wall), cpu_seconds() - cpu});
  const BatchView qpos = batch.view(StateField::qpos);
  config.final_qpos_x.resize(std::size_t(batch.size()));
  for (int i = 0; i < batch.size(); ++i) config.final_qpos_x[std::size_t(i)] = qpos(i, pallet_qpos);
  return std::nullopt;
}

std::string cell(const std::string& text, int width) {
  std::ostringstream out;
  out << std::right << std::setw(width) << text;
  return out.str();
}

}  // namespace

// A whole positive number from a list option (threads, nstep, sizes).
std::vector<int> int_list(const Args& args, const std::string& name, std::vector<int> fallback,
                          int lo, int hi) {
  auto values = args.numbers(name);
  if (!values) return fallback;
  std::vector<int> out;
  for (double v : *values) {
    if (!(v >= lo && v <= hi) || v != std::floor(v)) {
      throw UsageError{"bench: --" + name + " takes whole numbers from " + std::to_string(lo) +
                       " to " + std::to_string(hi) + ", got " + short_number(v)};
    }
    out.push_back(static_cast<int>(v));
  }
  return out;
}

int run_bench_batch(const Args& args) {
  const std::int64_t sims = args.integer("sims").value_or(64);
  if (sims < 1 || sims > 100000) throw UsageError{"bench: --sims must be between 1 and 100000"};
  const std::int64_t reps = args.integer("runs").value_or(3);
  if (reps < 1 || reps > 1000) throw UsageError{"bench: --runs must be between 1 and 1000"};
  const std::int64_t steps = args.integer("steps").value_or(100);
  if (steps < 1 || steps > 100000) throw UsageError{"bench: --steps must be between 1 and 100000"};
  const std::vector<int> threads = int_list(args, "threads", {1, 2}, 1, 256);
  const std::vector<int> nsteps = int_list(args, "nstep", {1, 10}, 1, 100000);
  for (int n : nsteps) {
    if (steps % n != 0) {
      throw UsageError{"bench: --steps (" + std::to_string(steps) +
                       ") must be a multiple of every "
                       "--nstep, and " +
                       std::to_string(n) + " is not a divisor"};
    }
  }
  const std::string slug = args.text("scenario").value_or("stable-dairy-slab");
  auto scenario = load_scenario(slug);
  if (!scenario) {
    print_diagnostics(scenario.diagnostics);
    return kExitBadInput;
  }
  auto setup = make_setup(*scenario);
  if (!setup) {
    print_diagnostics(setup.diagnostics);
    return kExitFailure;
  }
  const Belt belt{setup->scene.layout.belt_x_act, static_cast<int>(sims)};
  const int pallet_qpos = setup->scene.layout.pallet_qpos;

  std::vector<Config> configs;
  configs.push_back({"serial", 1, 1, {}, {}});
  for (int t : threads) {
    for (int n : nsteps) configs.push_back({"batch", t, n, {}, {}});
  }
  // One batch per thread count, made once and reused (as a caller would).
  std::vector<Batch> batches;
  for (int t : threads) {
    auto b = Batch::create(*setup->scene.model, static_cast<int>(sims), t);
    if (!b) {
      print_diagnostics(b.diagnostics);
      return kExitFailure;
    }
    if (auto error = b->set_reset_state(setup->start)) {
      std::cerr << "bench: " << error->message << "\n";
      return kExitFailure;
    }
    batches.push_back(std::move(*b.value));
  }
  // Repetitions interleave the configurations, so a change of machine load hits them all alike.
  for (std::int64_t r = 0; r < reps; ++r) {
    std::cerr << "bench batch: run " << r + 1 << "/" << reps << "\n";
    for (Config& c : configs) {
      std::optional<std::string> error;
      if (c.mode == "serial") {
        error = run_serial(*setup, belt, static_cast<int>(sims), static_cast<int>(steps), c);
      } else {
        const auto at = std::find(threads.begin(), threads.end(), c.threads) - threads.begin();
        error = run_batch(batches[std::size_t(at)], belt, static_cast<int>(steps), pallet_qpos, c);
      }
      if (error) {
        std::cerr << "bench: " << c.mode << " threads " << c.threads << " nstep " << c.nstep << ": "
                  << *error << "\n";
        return kExitFailure;
      }
    }
  }

  double load1 = -1.0;
  double loads[3];
  if (getloadavg(loads, 3) >= 1) load1 = loads[0];
  const double total = double(sims) * double(steps);
  std::vector<double> wall_serial;
  for (const Timing& t : configs.front().reps) wall_serial.push_back(t.wall_s);
  const double serial_rate = total / median(wall_serial);
  Json rows = Json::array();
  for (const Config& c : configs) {
    std::vector<double> wall, cpu;
    for (const Timing& t : c.reps) {
      wall.push_back(t.wall_s);
      cpu.push_back(t.cpu_s);
    }
    const double rate = total / median(wall);
    const bool same = c.final_qpos_x == configs.front().final_qpos_x;
    rows.push_back({{"mode", c.mode},
                    {"threads", c.threads},
                    {"nstep", c.nstep},
                    {"sims", sims},
                    {"steps_per_sim", steps},
                    {"runs", reps},
                    {"wall_s_median", median(wall)},
                    {"steps_per_s", rate},
                    {"steps_per_s_best", total / *std::min_element(wall.begin(), wall.end())},
                    {"speedup_vs_serial", rate / serial_rate},
                    {"cpu_s_median", median(cpu)},
                    {"steps_per_cpu_s", total / median(cpu)},
                    {"same_result_as_serial", same},
                    {"scenario", slug},
                    {"items", setup->scene.layout.item_bodies.size()},
                    {"load_average_1min", load1},
                    {"cpus", std::thread::hardware_concurrency()}});
  }
  if (args.flag("json")) {
    print_json(rows);
  } else {
    std::cout << "scenario " << slug << ", " << sims << " simulations x " << steps
              << " steps, median of " << reps << " runs, load average " << fixed(load1, 2) << ", "
              << std::thread::hardware_concurrency() << " cpus\n";
    std::cout << "mode    threads nstep   steps/s  speedup  cpu_s  steps/cpu_s  same\n";
    for (const Json& row : rows) {
      std::cout << std::left << std::setw(7) << row["mode"].get<std::string>() << std::right
                << cell(std::to_string(row["threads"].get<int>()), 8)
                << cell(std::to_string(row["nstep"].get<int>()), 6)
                << cell(fixed(row["steps_per_s"].get<double>(), 0), 10)
                << cell(fixed(row["speedup_vs_serial"].get<double>(), 3), 9)
                << cell(fixed(row["cpu_s_median"].get<double>(), 2), 7)
                << cell(fixed(row["steps_per_cpu_s"].get<double>(), 0), 13)
                << cell(row["same_result_as_serial"].get<bool>() ? "yes" : "NO", 6) << "\n";
    }
  }
  for (const Json& row : rows) {
    if (!row["same_result_as_serial"].get<bool>()) {
      std::cerr << "bench: the batch's results differ from the serial loop's\n";
      return kExitFailure;
    }
  }
  return kExitOk;
}

}  // namespace pb::cli
