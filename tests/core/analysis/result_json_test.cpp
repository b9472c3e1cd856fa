// SPDX-License-Identifier: MIT
// The JSON of the core's answers: what each writer includes, and what it leaves null or out.
#include "core/analysis/result_json.hpp"

#include <QtTest>

using namespace pb;

class ResultJsonTest : public QObject {
  Q_OBJECT

 private slots:
  void diagnosticsKeepTheirOrderAndPointers() {
    const Json j = diagnostics_to_json({{"/items/2/weight_kg", "too heavy", Severity::error},
                                        {"", "about the whole document", Severity::warning}});
    QCOMPARE(j.size(), 2u);
    QCOMPARE(j[0]["pointer"], "/items/2/weight_kg");
    QCOMPARE(j[1]["message"], "about the whole document");
  }

  void aValidationReportSplitsErrorsFromWarnings() {
    PalletConfig config;
    config.pallet_id = "p";
    Item item;
    item.dims_m = {0.4, 0.3, 0.2};
    item.position = {0.0, 0.0, 0.15};
    config.items = {item};
    const Json ok = validation_report_to_json(config, {{"/notes", "odd", Severity::warning}});
    QCOMPARE(ok["valid"], true);
    QCOMPARE(ok["warnings"].size(), 1u);
    QCOMPARE(ok["errors"].size(), 0u);
    QCOMPARE(ok["items"], 1);
    QCOMPARE(ok["min_support_fraction"].get<double>(), 1.0);
    const Json bad = validation_report_to_json(config, {{"/items/0", "floats", Severity::error}});
    QCOMPARE(bad["valid"], false);
  }

  void aSimulationSaysWhyOnlyWhenUnstable() {
    SimResult safe;
    QVERIFY(sim_result_to_json(safe, {})["failure"].is_null());
    QVERIFY(!sim_result_to_json(safe, {}).contains("reason"));
    // A safe run says how near it came: a pallet that slid 0.28 m of its 0.30 m allowance.
    safe.peak_ratio = 0.28 / 0.30;
    safe.load_peak_ratio = 0.1;
    QCOMPARE(sim_result_to_json(safe, {})["peak_ratio"].get<double>(), 0.28 / 0.30);
    QCOMPARE(sim_result_to_json(safe, {})["load_peak_ratio"].get<double>(), 0.1);
    SimResult failed;
    failed.outcome = Outcome::failed;
    failed.failure = FailureEvent{};
    failed.failure->mode = FailureMode::tip_over;
    failed.failure->time_s = 0.5;
    const Json f = sim_result_to_json(failed, {});
    QCOMPARE(f["failure"]["mode"], "tip_over");
    QCOMPARE(f["failure"]["time_s"].get<double>(), 0.5);
    QVERIFY(!f["failure"]["description"].get<std::string>().empty());
    SimResult unstable;
    unstable.outcome = Outcome::unstable;
    unstable.reason = "the solver diverged";
    QCOMPARE(sim_result_to_json(unstable, {})["reason"], "the solver diverged");
    QCOMPARE(sim_result_to_json(unstable, {})["profile"]["shape"], "accel_hold");
  }

  void aProbeHasAFailureTimeOnlyWhenItFailed() {
    Probe safe;
    safe.axis = Axis::lateral;
    Probe failed;
    failed.outcome = Outcome::failed;
    failed.mode = FailureMode::load_shift;
    failed.failure_time_s = 0.25;
    const Json j = probes_to_json({safe, failed});
    QCOMPARE(j[0]["axis"], "lateral");
    QVERIFY(j[0]["failure_time_s"].is_null());
    QCOMPARE(j[1]["failure_time_s"].get<double>(), 0.25);
    QCOMPARE(j[1]["mode"], "load_shift");
  }

  void aMapHasARowPerAccelerationAndACellPerSpeed() {
    FailureMap map;
    map.speeds_mps = {0.5, 1.0, 1.5};
    map.accels_mps2 = {1.0, 2.0};
    map.cells.resize(6);
    map.at(2, 1).outcome = Outcome::failed;
    map.at(2, 1).failure_time_s = 0.3;
    map.at(0, 1).outcome = Outcome::unstable;
    map.at(0, 1).reason = "diverged";
    map.line_cells.resize(3);
    const Json j = failure_map_to_json(map);
    QCOMPARE(j["cells"].size(), 2u);
    QCOMPARE(j["cells"][0].size(), 3u);
    QCOMPARE(j["cells"][1][2]["outcome"], "failed");
    QCOMPARE(j["cells"][1][2]["failure_time_s"].get<double>(), 0.3);
    QVERIFY(j["cells"][0][0]["failure_time_s"].is_null());
    QCOMPARE(j["cells"][1][0]["reason"], "diverged");
    QVERIFY(!j["cells"][0][0].contains("reason"));
    QCOMPARE(j["line_cells"].size(), 3u);
    QVERIFY(j["envelope"].contains("reject"));
  }
};

QTEST_APPLESS_MAIN(ResultJsonTest)
#include "result_json_test.moc"
