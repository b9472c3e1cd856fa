// SPDX-License-Identifier: MIT
// `bench scale`: how the analysis of an unwrapped load grows with its size. Each pallet is analysed
// in a child process (forked before any thread exists), so that its peak resident memory is its
// own: the parent reads the child's JSON row from a pipe and its peak RSS from wait4.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli/commands.hpp"
#include "core/analysis/analyzer.hpp"
#include "core/base/text.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/layer_layout.hpp"
#include "core/inputs/pallet_source.hpp"
#include "core/physics/probe_run.hpp"

namespace pb::cli {

namespace {

constexpr int kPerLayer = 12;  // 4 x 3 dairy cases of 0.30 x 0.25 m fill a EUR deck
constexpr const char* kSku = "SKU-FD-003";

Result<PalletConfig> scale_pallet(LayerPattern pattern, int items) {
  ScannerInputs in;
  in.pallet_id = "scale-" + std::string(to_string(pattern)) + "-" + std::to_string(items);
  in.pattern = pattern;
  in.layers = std::max(1, items / kPerLayer);
  in.items_per_layer = kPerLayer;
  in.skus = {kSku};
  in.wrap = WrapType::none;
  return build_from_scanner(in, Catalog::builtin());
}

// The analysis of one pallet, as the child runs it: a cold Analyzer's envelope.
Json analyse(const PalletConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  Analyzer analyzer;
  auto env = analyzer.envelope(config);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  Json row = {{"items", config.items.size()}};
  // The analysis's peak, taken before this row's own mjData (for the contact count below) adds
  // a whole model's buffers to it.
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) == 0) row["peak_rss_mb"] = double(usage.ru_maxrss) / 1024.0;
  if (!env) {
    row["error"] = env.diagnostics.empty() ? "failed" : env.diagnostics.front().message;
    return row;
  }
  auto prepared = analyzer.prepare(config);  // cached
  if (!prepared) {
    row["error"] = prepared.diagnostics.empty() ? "failed" : prepared.diagnostics.front().message;
    return row;
  }
  const PreparedPallet& p = **prepared.value;
  const mjModel* m = p.scene->model.get();
  auto data = make_data(m);
  int contacts = -1;
  if (data) {
    load_rest_state(p.scene->layout, p.rest, 0.0, **data);
    mj_forward(m, data->get());
    contacts = (*data)->ncon;
  }
  double wall = 0.0;
  long steps = 0;
  for (const Probe& probe : env->probes) {
    wall += probe.wall_ms;
    steps += probe.steps;
  }
  row["dofs"] = m->nv;
  // The items the searches simulate per plane (symmetry.hpp: one copy of each group of identical
  // stacks), along the belt and across it.
  for (std::size_t plane = 0; plane < 2; ++plane) {
    const PlaneModel* model = p.planes[plane].get();
    row[plane == 0 ? "searched_items_along" : "searched_items_across"] =
        model ? model->reduction.config.items.size() : config.items.size();
  }
  row["contacts"] = contacts;
  row["us_per_step"] = steps > 0 ? 1000.0 * wall / double(steps) : 0.0;
  row["sims"] = env->result.sims_run;
  // The steps its searches' probes took (jumps not counted): a cost that, unlike the time, no other
  // load on the machine changes, for comparing two builds on a noisy one.
  row["steps"] = steps;
  row["envelope_ms"] = ms;
  row["fidelity"] = to_string(env->result.fidelity);
  row["verdict"] = to_string(env->result.verdict);
  row["max_accel_mps2"] = env->result.max_accel_mps2;
  row["max_lateral_g"] = env->result.max_lateral_g;
  return row;
}

// analyse() in a child process; its row, with the child's peak resident set where analyse() could
// not take the analysis's own.
Json analyse_in_child(const PalletConfig& config) {
  int fd[2];
  if (pipe(fd) != 0) return {{"error", "could not create a pipe"}};
  std::cout.flush();
  const pid_t pid = fork();
  if (pid < 0) {
    close(fd[0]);
    close(fd[1]);
    return {{"error", "could not fork"}};
  }
  if (pid == 0) {
    close(fd[0]);
    const std::string text = analyse(config).dump();
    std::size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = write(fd[1], text.data() + done, text.size() - done);
      if (n <= 0) break;
      done += std::size_t(n);
    }
    close(fd[1]);
    _exit(0);
  }
  close(fd[1]);
  std::string text;
  char buf[4096];
  for (ssize_t n; (n = read(fd[0], buf, sizeof buf)) > 0;) text.append(buf, std::size_t(n));
  close(fd[0]);
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  Json row = Json::parse(text, nullptr, false);
  // A child that dies writes no row: say how it ended (a SIGKILL is usually the OOM killer, an
  // abort an uncaught exception such as bad_alloc), with the memory it had reached.
  if (row.is_discarded() || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = WIFSIGNALED(status)
                                ? "was killed by signal " + std::to_string(WTERMSIG(status)) +
                                      " (" + strsignal(WTERMSIG(status)) + ")"
                                : "exited with status " + std::to_string(WEXITSTATUS(status));
    return {{"error", "the analysis process " + how + " at a peak of " +
                          fixed(double(usage.ru_maxrss) / 1024.0, 0) + " MB resident"}};
  }
  if (!row.contains("peak_rss_mb")) row["peak_rss_mb"] = double(usage.ru_maxrss) / 1024.0;
  return row;
}

// The row of `config` (named `row`'s "pattern" and "size", or "pallet"), analysed `runs` times
// each in a child of its own: the last run's figures with the median envelope and the largest
// peak. Sets `exit_code` on an error.
Json bench_row(Json row, const PalletConfig& config, std::int64_t runs, const std::string& label,
               int& exit_code) {
  std::vector<double> ms;
  double rss = 0.0;
  Json last;
  for (int r = 0; r < runs; ++r) {
    std::cerr << "bench scale: " << label << " run " << r + 1 << "/" << runs << "\n";
    last = analyse_in_child(config);
    if (last.contains("error")) break;
    ms.push_back(last["envelope_ms"].get<double>());
    rss = std::max(rss, last["peak_rss_mb"].get<double>());
  }
  row.update(last);
  if (!last.contains("error")) {
    std::sort(ms.begin(), ms.end());
    row["envelope_ms"] = ms[ms.size() / 2];
    row["peak_rss_mb"] = rss;
    row["runs"] = runs;
  } else {
    exit_code = kExitFailure;
  }
  return row;
}

// Prints `rows` as the table (or, `json`, as a JSON array); returns `exit_code`.
int print_rows(const Json& rows, bool json, int exit_code) {
  if (json) {
    print_json(rows);
    return exit_code;
  }
  // A row names its pattern and size, or its pallet (the file's name without its folder and
  // extension).
  auto name = [](const Json& r) {
    if (!r.contains("pallet")) {
      return r["pattern"].get<std::string>() + " " + std::to_string(r["size"].get<int>());
    }
    std::string file = r["pallet"].get<std::string>();
    file = file.substr(file.find_last_of('/') + 1);
    return file.substr(0, file.rfind(".json"));
  };
  std::printf("%-20s %5s %5s %8s %8s %9s %5s %7s %11s %11s %s\n", "pallet", "items", "dofs",
              "contacts", "searched", "us/step", "sims", "steps", "envelope_ms", "peak_rss_mb",
              "verdict");
  for (const Json& r : rows) {
    if (r.contains("error")) {
      std::printf("%-20s error: %s\n", name(r).c_str(), r["error"].get<std::string>().c_str());
      continue;
    }
    const std::string searched = std::to_string(r["searched_items_along"].get<int>()) + "/" +
                                 std::to_string(r["searched_items_across"].get<int>());
    std::printf("%-20s %5d %5d %8d %8s %9.1f %5d %7ld %11.0f %11.0f %s\n", name(r).c_str(),
                r["items"].get<int>(), r["dofs"].get<int>(), r["contacts"].get<int>(),
                searched.c_str(), r["us_per_step"].get<double>(), r["sims"].get<int>(),
                r["steps"].get<long>(), r["envelope_ms"].get<double>(),
                r["peak_rss_mb"].get<double>(), r["verdict"].get<std::string>().c_str());
  }
  return exit_code;
}

// `bench scale --pallets`: the rows of the caller's pallets (files or curated slugs, a
// random generator's, a warehouse's) instead of the sizes' recipe.
int bench_pallets(const std::string& list, const Args& args, std::int64_t runs) {
  Json rows = Json::array();
  int exit_code = kExitOk;
  for (const char* recipe_only : {"sizes", "patterns"}) {
    if (args.flag(recipe_only)) {
      throw UsageError{std::string("bench: --") + recipe_only +
                       " and --pallets exclude each other"};
    }
  }
  std::vector<std::string> names;
  std::istringstream text(list);
  for (std::string name; std::getline(text, name, ',');) {
    if (!name.empty()) names.push_back(name);
  }
  if (names.empty()) {
    throw UsageError{"bench: --pallets takes pallet files or curated slugs, comma-separated"};
  }
  for (const std::string& name : names) {
    auto source = read_pallet_source(name);
    if (!source) {
      const Diagnostic& why = source.diagnostics.front();
      rows.push_back(
          {{"pallet", name},
           {"error", why.pointer.empty() ? why.message : why.pointer + ": " + why.message}});
      exit_code = kExitFailure;
      continue;
    }
    rows.push_back(bench_row({{"pallet", name}}, source->pallet, runs, name, exit_code));
  }
  return print_rows(rows, args.flag("json"), exit_code);
}

}  // namespace

int run_bench_scale(const Args& args) {
  const std::int64_t runs = args.integer("runs").value_or(1);
  if (runs < 1 || runs > 100) throw UsageError{"bench: --runs must be between 1 and 100"};
  if (auto list = args.text("pallets")) return bench_pallets(*list, args, runs);
  Json rows = Json::array();
  int exit_code = kExitOk;
  const std::vector<int> sizes = int_list(args, "sizes", {24, 48, 72, 96}, kPerLayer, 400);
  for (int n : sizes) {
    if (n % kPerLayer != 0) {
      throw UsageError{"bench: --sizes must be multiples of " + std::to_string(kPerLayer) +
                       " (cartons a layer), not " + std::to_string(n)};
    }
  }
  std::vector<LayerPattern> patterns;
  if (auto text = args.text("patterns")) {
    std::istringstream list(*text);
    for (std::string name; std::getline(list, name, ',');) {
      auto pattern = enum_from_string<LayerPattern>(name);
      if (!pattern || (*pattern != LayerPattern::column && *pattern != LayerPattern::brick)) {
        throw UsageError{"bench: --patterns takes column and brick, not '" + name + "'"};
      }
      patterns.push_back(*pattern);
    }
  } else {
    patterns = {LayerPattern::column, LayerPattern::brick};
  }
  for (LayerPattern pattern : patterns) {
    for (int n : sizes) {
      Json row = {{"pattern", to_string(pattern)}, {"size", n}};
      auto config = scale_pallet(pattern, n);
      if (!config) {
        row["error"] =
            config.diagnostics.front().pointer + ": " + config.diagnostics.front().message;
        rows.push_back(row);
        exit_code = kExitFailure;
        continue;
      }
      rows.push_back(bench_row(row, *config.value, runs,
                               std::string(to_string(pattern)) + " " + std::to_string(n),
                               exit_code));
    }
  }
  return print_rows(rows, args.flag("json"), exit_code);
}

}  // namespace pb::cli
