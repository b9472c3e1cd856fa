// SPDX-License-Identifier: MIT
// core/lab/study.hpp: the configurations, the reference configuration and the comparison metrics.
// Fast: no envelope is searched here except one closed-form-only check (the reference's
// convergence runs in tests/cli/study_cli_test.cpp, labelled long).
#include <QtTest>

#include <cmath>
#include <set>

#include "core/lab/study.hpp"

using namespace pb;

namespace {

SafetyResult result(double accel, double decel, double lateral, double speed) {
  SafetyResult r;
  r.max_accel_mps2 = accel;
  r.max_decel_mps2 = decel;
  r.max_lateral_g = lateral;
  r.max_speed_mps = speed;
  r.accel_mode = FailureMode::top_item_slide;
  r.decel_mode = FailureMode::top_item_slide;
  r.lateral_mode = FailureMode::tip_over;
  r.speed_mode = FailureMode::no_failure;
  return r;
}

StudySample make_sample(const std::string& config, const std::string& pallet, double ms,
                        std::optional<EnvelopeComparison> cmp, bool has_result = true) {
  StudySample s;
  s.config = config;
  s.pallet = pallet;
  s.wall_ms = ms;
  s.reference_ok = true;
  if (has_result) s.result = SafetyResult{};
  s.comparison = cmp;
  return s;
}

EnvelopeComparison within(double worst) {
  EnvelopeComparison c;
  c.worst_steps = worst;
  c.within_one_step = worst <= 1.0;
  c.verdict_agrees = true;
  return c;
}

}  // namespace

class StudyTest : public QObject {
  Q_OBJECT

 private slots:
  // The reference is the slow, trusted end: finer in time, stiffer, converged, finer in search,
  // and independent of the closed-form seed; the shipped default is AnalyzerOptions{}.
  void referenceIsFinerThanTheDefaultEverywhere() {
    const AnalyzerOptions def;
    const AnalyzerOptions ref = reference_options();
    QCOMPARE(ref.fidelity, Fidelity::full);
    QCOMPARE(ref.scene.timestep_s, 0.0005);
    QVERIFY(ref.scene.contact_solref[0] < def.scene.contact_solref[0]);
    // MuJoCo clamps a time constant below 2 dt (refsafe): the reference's must stay above it,
    // also at the halved timestep of its convergence check.
    QVERIFY(ref.scene.contact_solref[0] >= 2.0 * reference_options().scene.timestep_s);
    QCOMPARE(ref.scene.solver, Solver::newton);  // converged Newton; the default's CG stops sooner
    QVERIFY(ref.scene.iterations >= def.scene.iterations);
    QVERIFY(ref.scene.tolerance < def.scene.tolerance);
    QCOMPARE(ref.search.accel_precision_mps2, def.search.accel_precision_mps2 / 2.0);
    QCOMPARE(ref.search.decel_precision_mps2, def.search.decel_precision_mps2 / 2.0);
    QCOMPARE(ref.search.lateral_precision_g, def.search.lateral_precision_g / 2.0);
    QCOMPARE(ref.search.speed_precision_mps, def.search.speed_precision_mps / 2.0);
    QVERIFY(!ref.search.seed_with_closed_form);
    const AnalyzerOptions half = reference_half_step_options();
    QCOMPARE(half.scene.timestep_s, 0.00025);
    AnalyzerOptions same = half;
    same.scene.timestep_s = ref.scene.timestep_s;
    QCOMPARE(options_fingerprint(same), options_fingerprint(ref));
  }

  void referenceEquivalentIsTheReferenceSystemsAlgorithm() {
    const AnalyzerOptions eq = reference_equivalent_options();
    QCOMPARE(eq.fidelity, Fidelity::full);
    QCOMPARE(eq.scene.timestep_s, 0.002);
    QVERIFY(!eq.search.seed_with_closed_form);
    QVERIFY(!eq.sim.early_stop);
    QCOMPARE(eq.search.accel_precision_mps2, SearchConfig{}.accel_precision_mps2);
  }

  void configsHaveUniqueNamesAndOneOfEachRole() {
    const auto configs = study_configs();
    std::set<std::string> names, keys;
    int defaults = 0, equivalents = 0, references = 0;
    for (const auto& c : configs) {
      QVERIFY2(names.insert(c.name).second, c.name.c_str());
      // Two configurations that compute the same thing would be one point twice.
      QVERIFY2(keys.insert(options_fingerprint(c.options)).second, c.name.c_str());
      defaults += c.is_default;
      equivalents += c.is_reference_equivalent;
      references += c.is_reference;
      QVERIFY(!c.description.empty());
    }
    QCOMPARE(defaults, 1);
    QCOMPARE(equivalents, 1);
    QCOMPARE(references, 1);
    QVERIFY(configs.front().is_reference);
    const auto def = std::find_if(configs.begin(), configs.end(),
                                  [](const StudyConfig& c) { return c.is_default; });
    QCOMPARE(options_fingerprint(def->options), options_fingerprint(AnalyzerOptions{}));
  }

  void selectionAddsTheReferenceAndNamesUnknownConfigs() {
    auto two = select_study_configs("full-5ms,default,full-5ms");
    QVERIFY(two);
    QCOMPARE(two->size(), std::size_t{3});
    QCOMPARE(two->at(0).name, std::string("reference"));
    QCOMPARE(two->at(1).name, std::string("full-5ms"));
    QCOMPARE(two->at(2).name, std::string("default"));
    auto bad = select_study_configs("default,fast-and-wrong", "/configs");
    QVERIFY(!bad);
    QCOMPARE(bad.diagnostics.front().pointer, std::string("/configs"));
    const QString message = QString::fromStdString(bad.diagnostics.front().message);
    QVERIFY2(message.contains(QStringLiteral("fast-and-wrong")) &&
                 message.contains(QStringLiteral("reduced-2ms")),
             qPrintable(message));
  }

  void fingerprintSeesEveryKnob() {
    const std::string base = options_fingerprint({});
    auto differs = [&](auto change) {
      AnalyzerOptions o;
      change(o);
      return options_fingerprint(o) != base;
    };
    QVERIFY(differs([](AnalyzerOptions& o) { o.scene.timestep_s = 0.001; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.scene.cone = Cone::pyramidal; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.scene.solver = Solver::pgs; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.scene.contact_solref[0] = 0.01; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.search.accel_precision_mps2 = 0.05; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.search.seed_with_closed_form = false; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.sim.early_stop = false; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.fidelity = Fidelity::reduced; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.line.curve_radius_m = 5.0; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.full_model_timestep_s = 0.0005; }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.full_model_timestep_s.reset(); }));
    QVERIFY(differs([](AnalyzerOptions& o) { o.full_model_solref_s = 0.02; }));
    // Threads change the wall time, never the envelope: cached results stay valid.
    QVERIFY(!differs([](AnalyzerOptions& o) { o.search.axis_threads = 1; }));
  }

  // Errors in steps of 0.1 m/s^2, 0.1 m/s^2, 0.01 g and 0.05 m/s.
  void comparisonCountsSearchSteps() {
    const SafetyResult ref = result(2.0, 3.0, 0.20, 1.50);
    const EnvelopeComparison same = compare_envelopes(ref, ref);
    QVERIFY(same.within_one_step);
    QCOMPARE(same.worst_steps, 0.0);

    const EnvelopeComparison one = compare_envelopes(ref, result(2.1, 2.9, 0.21, 1.45));
    QVERIFY(one.within_one_step);  // exactly one step on every axis (up to rounding)
    QVERIFY(std::abs(one.worst_steps - 1.0) < 1e-9);

    const EnvelopeComparison lateral = compare_envelopes(ref, result(2.0, 3.0, 0.235, 1.5));
    QVERIFY(!lateral.within_one_step);
    QCOMPARE(lateral.worst_axis, Axis::lateral);
    QVERIFY(std::abs(lateral.worst_steps - 3.5) < 1e-9);

    SafetyResult rejected = ref;
    rejected.verdict = Verdict::reject;
    const EnvelopeComparison verdict = compare_envelopes(ref, rejected);
    QVERIFY(!verdict.verdict_agrees);
    QVERIFY(!verdict.within_one_step);
  }

  // Modes are compared only where the reference fails more than one step inside the range.
  void modesAreComparedWhereTheReferenceFailsInsideTheRange() {
    SafetyResult ref = result(2.0, 3.0, 0.20, 2.0);  // speed at the 2 m/s ceiling
    SafetyResult cand = ref;
    EnvelopeComparison c = compare_envelopes(ref, cand);
    QCOMPARE(c.modes_compared, 3);
    QVERIFY(c.modes_agree());
    cand.lateral_mode = FailureMode::top_item_slide;
    c = compare_envelopes(ref, cand);
    QCOMPARE(c.modes_agreeing, 2);
    QVERIFY(!c.modes_agree());
    ref.max_lateral_g = 0.495;  // within one step (0.01 g) of the 0.5 g ceiling
    c = compare_envelopes(ref, cand);
    QCOMPARE(c.modes_compared, 2);
    QVERIFY(c.modes_agree());
  }

  void summaryMediansSharesAndParetoFront() {
    std::vector<StudyConfig> configs(3);
    configs[0].name = "slow-good";
    configs[1].name = "fast-bad";
    configs[2].name = "slow-bad";
    configs[1].is_default = true;
    std::vector<StudySample> samples = {
        make_sample("slow-good", "a", 100, within(0.0)),
        make_sample("slow-good", "b", 300, within(0.5)),
        make_sample("slow-good", "c", 200, within(1.0)),
        make_sample("fast-bad", "a", 10, within(0.0)),
        make_sample("fast-bad", "b", 30, within(2.5)),
        make_sample("fast-bad", "c", 20, within(0.0)),
        make_sample("slow-bad", "a", 500, within(3.0)),
        make_sample("slow-bad", "b", 400, std::nullopt, false),
        make_sample("slow-bad", "c", 600, within(0.0)),
    };
    samples[7].error = "unstable";
    const auto s = summarize_study(configs, samples);
    QCOMPARE(s.size(), std::size_t{3});
    QCOMPARE(s[0].median_ms, 200.0);
    QCOMPARE(s[0].within_one_step, 1.0);
    QCOMPARE(s[0].worst_error_steps, 1.0);
    QVERIFY(s[0].pareto);
    QCOMPARE(s[1].median_ms, 20.0);
    QVERIFY(std::abs(s[1].within_one_step - 2.0 / 3.0) < 1e-12);
    QCOMPARE(s[1].worst_pallet, std::string("b"));
    QVERIFY(s[1].is_default);
    QVERIFY(s[1].pareto);
    // An error where the reference has a result counts as outside one step, and as the worst.
    QCOMPARE(s[2].pallets, 3);
    QCOMPARE(s[2].errors, 1);
    QVERIFY(std::abs(s[2].within_one_step - 1.0 / 3.0) < 1e-12);
    QVERIFY(std::isinf(s[2].worst_error_steps));
    QCOMPARE(s[2].median_ms, 550.0);  // of the runs that gave a result
    QVERIFY(!s[2].pareto);
    const Json j = study_summary_to_json(s[2]);
    for (const char* key :
         {"config", "median_ms", "within_one_step", "is_default", "is_reference_equivalent"}) {
      QVERIFY2(j.contains(key), key);
    }
    QVERIFY(j["worst_error_steps"].is_null());
  }

  void corpusIsCuratedThenSeededRandom() {
    const auto a = study_corpus(3, 1000);
    const auto b = study_corpus(3, 1000);
    QVERIFY(a.size() >= 3 + 7);
    QCOMPARE(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) QVERIFY(a[i].pallet == b[i].pallet);
    QCOMPARE(a.back().label, std::string("random-1002"));
    QCOMPARE(study_corpus(2, 5, false).size(), std::size_t{2});
    QVERIFY(!(study_corpus(1, 5, false)[0].pallet == study_corpus(1, 6, false)[0].pallet));
  }
};

QTEST_APPLESS_MAIN(StudyTest)
#include "study_test.moc"
