// SPDX-License-Identifier: MIT
#include "core/lab/batch_study.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

#include "core/contract/fingerprint.hpp"

namespace pb {

Distribution distribution_of(std::vector<double> v) {
  Distribution d;
  d.count = int(v.size());
  if (v.empty()) return d;
  std::sort(v.begin(), v.end());
  auto quantile = [&](double q) {  // linear interpolation between order statistics
    const double x = q * double(v.size() - 1);
    const std::size_t i = std::size_t(std::floor(x));
    const std::size_t j = std::min(i + 1, v.size() - 1);
    return v[i] + (v[j] - v[i]) * (x - double(i));
  };
  d.min = v.front();
  d.max = v.back();
  d.p10 = quantile(0.1);
  d.median = quantile(0.5);
  d.p90 = quantile(0.9);
  double sum = 0.0;
  for (double x : v) sum += x;
  d.mean = sum / double(v.size());
  return d;
}

void summarise(BatchStudy& study) {
  study.analysed = study.errors = study.cache_hits = study.rejects = study.sims = 0;
  study.dominant_modes.clear();
  study.speed_governed_by.clear();
  study.reject_modes.clear();
  std::vector<double> speed, accel, decel, lateral;
  for (const StudyEntry& e : study.pallets) {
    if (!e.result) {
      ++study.errors;
      continue;
    }
    ++study.analysed;
    if (e.cached) ++study.cache_hits;
    const SafetyResult& r = *e.result;
    study.sims += r.sims_run;
    ++study.dominant_modes[std::string(to_string(r.dominant_failure_mode))];
    ++study.speed_governed_by[std::string(to_string(r.speed_governed_by))];
    if (r.verdict == Verdict::reject) {
      ++study.rejects;
      ++study.reject_modes[std::string(to_string(r.dominant_failure_mode))];
      continue;
    }
    speed.push_back(r.max_speed_mps);
    accel.push_back(r.max_accel_mps2);
    decel.push_back(r.max_decel_mps2);
    lateral.push_back(r.max_lateral_g);
  }
  study.max_speed_mps = distribution_of(speed);
  study.max_accel_mps2 = distribution_of(accel);
  study.max_decel_mps2 = distribution_of(decel);
  study.max_lateral_g = distribution_of(lateral);
}

Result<BatchStudy> run_batch_study(const BatchStudyOptions& o, const Catalog& catalog,
                                   const FrictionModel& friction) {
  using Out = Result<BatchStudy>;
  const int n = o.pallets.empty() ? o.n : int(o.pallets.size());
  if (n < 1 || n > 100000) return Out::failure("/n", "give 1 to 100000 pallets");
  if (o.threads < 0 || o.threads > 1024) {
    return Out::failure("/threads", "give 0 (every CPU) to 1024 threads");
  }
  {
    Diagnostics d = validate_random_options(o.pallet);
    if (has_errors(d)) return Out::failure(std::move(d));
  }
  const auto start = std::chrono::steady_clock::now();
  int threads = o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, n);
  AnalyzerOptions analyzer_options = o.analyzer;
  // Each worker is already one of T threads: its axes and its batched runs (confidence) stay on it.
  if (threads > 1 && analyzer_options.confidence.threads == 0) {
    analyzer_options.confidence.threads = 1;
  }
  if (threads > 1 && analyzer_options.search.axis_threads == 0) {
    analyzer_options.search.axis_threads = 1;
  }

  BatchStudy study;
  study.threads = threads;
  study.pallets.resize(std::size_t(n));
  std::mutex cache_mutex;
  std::map<std::string, SafetyResult> cache;  // shared by fingerprint
  std::atomic<int> next{0};

  auto work = [&] {
    Analyzer analyzer(analyzer_options, friction);
    for (int k = next++; k < n; k = next++) {
      const auto t0 = std::chrono::steady_clock::now();
      StudyEntry& e = study.pallets[std::size_t(k)];
      e.seed = o.pallets.empty() ? o.seed + std::uint64_t(k) : std::uint64_t(k);
      RandomPalletOptions po = o.pallet;
      po.seed = e.seed;
      auto pallet = o.pallets.empty() ? random_pallet(po, catalog)
                                      : Result<PalletConfig>{o.pallets[std::size_t(k)], {}};
      if (!pallet) {
        e.error = pallet.diagnostics.empty() ? "no pallet" : to_string(pallet.diagnostics[0]);
      } else {
        e.pallet_id = pallet->pallet_id;
        e.notes = pallet->notes;
        e.items = int(pallet->items.size());
        e.fingerprint = config_fingerprint(*pallet);
        {
          std::lock_guard lock(cache_mutex);
          if (auto it = cache.find(e.fingerprint); it != cache.end()) {
            e.result = it->second;
            e.result->pallet_id = e.pallet_id;
            e.result->sims_run = 0;
            e.cached = true;
          }
        }
        if (!e.cached) {
          try {
            auto r = analyzer.analyze(*pallet);
            if (r) {
              e.result = *r;
              std::lock_guard lock(cache_mutex);
              cache.emplace(e.fingerprint, *r);
            } else {
              e.error = r.diagnostics.empty() ? "analysis failed" : to_string(r.diagnostics[0]);
            }
          } catch (const std::exception& ex) {
            e.error = std::string("internal error: ") + ex.what();
          }
          analyzer.clear_cache();  // a study's pallets rarely repeat: keep memory flat
        }
      }
      e.wall_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();

  summarise(study);
  study.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  study.pallets_per_s = study.wall_s > 0.0 ? n / study.wall_s : 0.0;
  return Out{std::move(study), {}};
}

}  // namespace pb
