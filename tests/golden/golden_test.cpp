// SPDX-License-Identifier: MIT
// Golden fingerprints (issue 15, "determinism pinned"): for each curated scenario, a hash of its
// envelope (limits, modes, verdict and every probe: value, outcome, mode, failure time, steps) and
// of the replay of its suggested profile, committed in curated_fingerprints.json. Physics that
// changes them fails here; the commit that changes them regenerates the file
// (PB_GOLDEN_UPDATE=1 ./golden_test) and says why. The envelope must not depend on how many axis
// threads search it (1, 2 or 4).
#include <QtTest>

#include <fstream>

#include "core/analysis/analyzer.hpp"
#include "core/analysis/replay.hpp"
#include "core/base/sha256.hpp"
#include "core/contract/json_io.hpp"
#include "core/inputs/scenario.hpp"

using namespace pb;

namespace {

const char* const kGoldenFile = PB_SOURCE_DIR "/tests/golden/curated_fingerprints.json";

// What the physics decided, and nothing that measures the machine (wall times) or words a
// sentence (the reason): limits, modes and every probe.
Json envelope_digest(const Envelope& e) {
  const SafetyResult& r = e.result;
  Json probes = Json::array();
  for (const Probe& p : e.probes) {
    probes.push_back({to_string(p.axis), p.value, to_string(p.outcome), to_string(p.mode),
                      p.failure_time_s, p.steps, p.sim_time_s});
  }
  return {{"verdict", to_string(r.verdict)},
          {"fidelity", to_string(r.fidelity)},
          {"max_speed_mps", r.max_speed_mps},
          {"max_accel_mps2", r.max_accel_mps2},
          {"max_decel_mps2", r.max_decel_mps2},
          {"max_lateral_g", r.max_lateral_g},
          {"dominant_failure_mode", to_string(r.dominant_failure_mode)},
          {"speed_governed_by", to_string(r.speed_governed_by)},
          {"sims_run", r.sims_run},
          {"probes", probes}};
}

struct Fingerprint {
  std::string envelope, replay;
  Json limits;  // readable, so a diff of the golden file shows what moved
};

// The envelope on `axis_threads` threads and, if asked, the replay of the suggested profile.
Fingerprint fingerprint(const Scenario& s, int axis_threads, bool with_replay, std::string& error) {
  AnalyzerOptions options;
  options.search.axis_threads = axis_threads;
  Analyzer analyzer(options);
  Fingerprint f;
  auto envelope = analyzer.envelope(s.pallet);
  if (!envelope) {
    error = s.slug + ": " + envelope.diagnostics.front().message;
    return f;
  }
  const Json digest = envelope_digest(*envelope.value);
  f.envelope = sha256_hex(digest.dump());
  f.limits = digest;
  f.limits.erase("probes");
  if (!with_replay) return f;
  auto solve = analyzer.solve(s.pallet, s.suggested_profile);
  if (!solve) {
    error = s.slug + ": " + solve.diagnostics.front().message;
    return f;
  }
  f.replay = sha256_hex(replay_to_json(solve.value->replay).dump());
  return f;
}

}  // namespace

class GoldenTest : public QObject {
  Q_OBJECT

 private slots:
  // Each scenario's envelope on 1, 2 and 4 axis threads (the axes search on threads of their
  // own: how many must not change a bit) and its replay, against the committed fingerprints.
  void curatedScenariosMatchTheirFingerprints() {
    const bool update = qEnvironmentVariableIsSet("PB_GOLDEN_UPDATE");
    Json golden = Json::object();
    if (!update) {
      std::ifstream in(kGoldenFile);
      QVERIFY2(in,
               "tests/golden/curated_fingerprints.json is missing: run with PB_GOLDEN_UPDATE=1");
      golden = Json::parse(in);
    }
    Json fresh = Json::object();
    QStringList changed;
    for (const Scenario& s : all_scenarios()) {
      std::string error;
      const Fingerprint f = fingerprint(s, 1, true, error);
      QVERIFY2(error.empty(), error.c_str());
      for (int threads : {2, 4}) {
        const std::string other = fingerprint(s, threads, false, error).envelope;
        QVERIFY2(error.empty(), error.c_str());
        QVERIFY2(other == f.envelope,
                 qPrintable(QString::fromStdString(s.slug) +
                            QStringLiteral(": a different envelope on %1 axis threads than on 1")
                                .arg(threads)));
      }
      fresh[s.slug] = {{"envelope", f.envelope}, {"replay", f.replay}, {"limits", f.limits}};
      if (update) continue;
      if (!golden.contains(s.slug)) {
        changed << QString::fromStdString(s.slug + ": no fingerprint committed");
        continue;
      }
      const Json& g = golden[s.slug];
      if (g["envelope"] != f.envelope) {
        changed << QString::fromStdString(s.slug + ": envelope changed, now " + f.limits.dump() +
                                          ", was " + g["limits"].dump());
      }
      if (g["replay"] != f.replay) {
        changed << QString::fromStdString(s.slug + ": the replay of its suggested profile changed");
      }
    }
    if (update) {
      std::ofstream out(kGoldenFile);
      out << fresh.dump(2) << "\n";
      QSKIP("fingerprints written to tests/golden/curated_fingerprints.json");
    }
    QVERIFY2(changed.isEmpty(),
             qPrintable("physics changed the golden fingerprints (if that is meant, regenerate "
                        "with PB_GOLDEN_UPDATE=1 and say why in the commit):\n" +
                        changed.join('\n')));
  }
};

QTEST_APPLESS_MAIN(GoldenTest)
#include "golden_test.moc"
