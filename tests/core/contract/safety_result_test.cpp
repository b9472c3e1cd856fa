// SPDX-License-Identifier: MIT
// SafetyResult's JSON: the reference's field names, our additions, and an exact round trip.
#include <QtTest>

#include "core/contract/json_io.hpp"
#include "core/contract/safety_result.hpp"

using namespace pb;

namespace {

SafetyResult sample() {
  SafetyResult r;
  r.pallet_id = "P-7";
  r.max_speed_mps = 1.3;
  r.max_accel_mps2 = 0.1 + 0.2;  // not exactly 0.3: the round trip must keep every bit
  r.max_decel_mps2 = 2.25;
  r.max_lateral_g = 0.31;
  r.dominant_failure_mode = FailureMode::top_item_slide;
  r.margin_pct = 12.5;
  r.confidence = 0.8;
  r.sim_runtime_ms = 431.75;
  r.config_hash = "ab12";
  r.sims_run = 17;
  r.accel_mode = FailureMode::tip_over;
  r.decel_mode = FailureMode::top_item_slide;
  r.lateral_mode = FailureMode::pallet_slip;
  r.speed_mode = FailureMode::top_item_slide;
  r.speed_item_tipped = true;                 // an item tips over in the stop that sets the speed
  r.decel_load_as_one = true;                 // the load slides on its pallet in a stop
  r.dominant_slide = SlideKind::load_as_one;  // the stop is the tightest axis
  r.speed_governed_by = SpeedGovernor::estop;
  r.verdict = Verdict::ok;
  r.reason = "the top layer slides first in a stop";
  r.line_estop_decel_mps2 = 3.5;
  r.line_curve_radius_m = 2.0;
  r.fidelity = Fidelity::reduced;
  return r;
}

}  // namespace

class SafetyResultTest : public QObject {
  Q_OBJECT

 private slots:
  void writesEveryFieldUnderItsReferenceName() {
    const Json json = safety_result_to_json(sample());
    QStringList keys;
    for (const auto& [key, value] : json.items()) keys << QString::fromStdString(key);
    QCOMPARE(keys, (QStringList{"accel_item_tipped",
                                "accel_load_as_one",
                                "accel_mode",
                                "confidence",
                                "config_hash",
                                "decel_item_tipped",
                                "decel_load_as_one",
                                "decel_mode",
                                "dominant_failure_mode",
                                "dominant_slide",
                                "fidelity",
                                "lateral_item_tipped",
                                "lateral_load_as_one",
                                "lateral_mode",
                                "line_curve_radius_m",
                                "line_estop_decel_mps2",
                                "margin_pct",
                                "max_accel_mps2",
                                "max_decel_mps2",
                                "max_lateral_g",
                                "max_speed_mps",
                                "pallet_id",
                                "reason",
                                "schema_version",
                                "sim_runtime_ms",
                                "sims_run",
                                "speed_governed_by",
                                "speed_item_tipped",
                                "speed_load_as_one",
                                "speed_mode",
                                "verdict"}));
    QCOMPARE(json["speed_item_tipped"], true);
    QCOMPARE(json["accel_item_tipped"], false);
    QCOMPARE(json["decel_load_as_one"], true);
    QCOMPARE(json["dominant_slide"].get<std::string>(), std::string("load_as_one"));
    QCOMPARE(json["accel_mode"].get<std::string>(), std::string("tip_over"));
    QCOMPARE(json["fidelity"].get<std::string>(), std::string("reduced"));
    QCOMPARE(json["dominant_failure_mode"].get<std::string>(), std::string("top_item_slide"));
    QCOMPARE(json["schema_version"].get<int>(), kSchemaVersion);
    QCOMPARE(json["sims_run"].get<int>(), 17);
    QCOMPARE(json["max_accel_mps2"].get<double>(), 0.1 + 0.2);
  }

  void roundTripIsIdentity() {
    const Json json = safety_result_to_json(sample());
    const auto read = safety_result_from_json(json);
    QVERIFY(read.ok());
    QVERIFY(read.diagnostics.empty());
    QVERIFY(*read == sample());
    QCOMPARE(to_canonical_text(safety_result_to_json(*read)), to_canonical_text(json));
  }

  void readsAReferenceResultWithoutOurAdditions() {
    Json json = safety_result_to_json(sample());
    for (const char* ours : {"schema_version",
                             "sims_run",
                             "accel_mode",
                             "decel_mode",
                             "lateral_mode",
                             "speed_mode",
                             "speed_governed_by",
                             "verdict",
                             "reason",
                             "line_estop_decel_mps2",
                             "line_curve_radius_m",
                             "fidelity",
                             "accel_item_tipped",
                             "decel_item_tipped",
                             "lateral_item_tipped",
                             "speed_item_tipped",
                             "accel_load_as_one",
                             "decel_load_as_one",
                             "lateral_load_as_one",
                             "speed_load_as_one",
                             "dominant_slide"}) {
      json.erase(ours);
    }
    const auto read = safety_result_from_json(json);
    QVERIFY(read.ok());
    QVERIFY(read.diagnostics.empty());
    // Our fields take their defaults; the reference's keep their values.
    SafetyResult expected;
    const SafetyResult full = sample();
    expected.pallet_id = full.pallet_id;
    expected.max_speed_mps = full.max_speed_mps;
    expected.max_accel_mps2 = full.max_accel_mps2;
    expected.max_decel_mps2 = full.max_decel_mps2;
    expected.max_lateral_g = full.max_lateral_g;
    expected.dominant_failure_mode = full.dominant_failure_mode;
    expected.margin_pct = full.margin_pct;
    expected.confidence = full.confidence;
    expected.sim_runtime_ms = full.sim_runtime_ms;
    expected.config_hash = full.config_hash;
    QVERIFY(*read == expected);
  }

  // Not estimated: null, and read back as none (a 0 would read as "certain to fail").
  void confidenceNotEstimatedIsNull() {
    SafetyResult r = sample();
    r.confidence.reset();
    const Json json = safety_result_to_json(r);
    QVERIFY(json.contains("confidence") && json["confidence"].is_null());
    auto read = safety_result_from_json(json);
    QVERIFY(read.ok());
    QVERIFY(!read->confidence);
    QVERIFY(*read == r);
  }

  void missingReferenceFieldIsAnError() {
    Json json = safety_result_to_json(sample());
    json.erase("margin_pct");
    const auto read = safety_result_from_json(json, "/result");
    QVERIFY(!read.ok());
    QCOMPARE(read.diagnostics.size(), std::size_t{1});
    QCOMPARE(read.diagnostics[0].pointer, std::string("/result/margin_pct"));
    QVERIFY(read.diagnostics[0].message.find("'margin_pct'") != std::string::npos);
  }

  void badValuesAreErrorsAtTheirPointers() {
    Json json = safety_result_to_json(sample());
    json["dominant_failure_mode"] = "wobble";
    json["sims_run"] = 2.5;
    const auto read = safety_result_from_json(json);
    QVERIFY(!read.ok());
    QCOMPARE(read.diagnostics.size(), std::size_t{2});
    QCOMPARE(read.diagnostics[0].pointer, std::string("/dominant_failure_mode"));
    QVERIFY(read.diagnostics[0].message.find(enum_choices<FailureMode>()) != std::string::npos);
    QCOMPARE(read.diagnostics[1].pointer, std::string("/sims_run"));
  }

  // The verdict and what governs the speed are enums: a value outside them is named, with the
  // choices, instead of being carried as a string nobody compares correctly.
  void verdictAndGovernorAreChecked() {
    Json json = safety_result_to_json(sample());
    QCOMPARE(json["verdict"], "ok");
    QCOMPARE(json["speed_governed_by"], "estop");
    json["verdict"] = "maybe";
    json["speed_governed_by"] = "luck";
    const auto read = safety_result_from_json(json);
    QVERIFY(!read.ok());
    QCOMPARE(read.diagnostics.size(), std::size_t{2});
    QCOMPARE(read.diagnostics[0].pointer, std::string("/speed_governed_by"));
    QVERIFY(read.diagnostics[0].message.find(enum_choices<SpeedGovernor>()) != std::string::npos);
    QCOMPARE(read.diagnostics[1].pointer, std::string("/verdict"));
    QVERIFY(read.diagnostics[1].message.find(enum_choices<Verdict>()) != std::string::npos);
  }
};

QTEST_APPLESS_MAIN(SafetyResultTest)
#include "safety_result_test.moc"
