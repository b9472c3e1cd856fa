// SPDX-License-Identifier: MIT
// The JSON contract: exact round trips, reference payloads, and every reading diagnostic.
#include <QtTest>

#include <fstream>
#include <sstream>

#include "core/contract/json_io.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/contract/pallet_type.hpp"
#include "core/inputs/validation.hpp"

using namespace pb;

namespace {

Item item(double x, double y, double z, double yaw = 0.0) {
  Item it;
  it.sku = "SKU-FD-001";
  it.weight_kg = 25.0;
  it.dims_m = {0.4, 0.4, 0.15};
  it.fragility = Fragility::semi_rigid;
  it.position = {x, y, z};
  it.orientation_deg = yaw;
  return it;
}

PalletConfig sample() {
  PalletConfig config;
  config.pallet_id = "P/1~x";
  config.base_pallet_type = PalletType::chep;
  config.base_mass_kg = 20.0;
  config.items = {item(-0.3, -0.2, 0.15), item(0.1 + 0.2, 0.2, 0.15, 37.5),
                  item(-0.3, -0.2, 0.3, -90.0)};
  config.wrap = WrapType::banded;
  config.env = Environment::transitioning;
  config.body_temp_c = -1.75;
  config.seconds_since_temp_change = 120.0;
  config.notes = "dock 4";
  config.belt_surface = BeltSurface::steel_roller;
  return config;
}

// The smallest document a reader accepts.
Json minimal() {
  return Json{{"items", Json::array()}, {"wrap", "none"}, {"env", "frozen"}, {"body_temp_c", -20}};
}

QStringList keys_of(const Json& json) {
  QStringList keys;
  for (const auto& [key, value] : json.items()) keys << QString::fromStdString(key);
  return keys;
}

QString pointers(const Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : diagnostics) out << QString::fromStdString(d.pointer);
  return out.join(' ');
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

Json reference_payload() {
  std::ifstream in(std::string(PB_TEST_DATA_DIR) + "/reference_payload.json");
  std::stringstream text;
  text << in.rdbuf();
  return *parse_json(text.str());
}

}  // namespace

class JsonIoTest : public QObject {
  Q_OBJECT

 private slots:
  // Text that is not UTF-8 is refused, and the refusal itself can be written as JSON (the service
  // answered 500 when it echoed the bytes back: a fuzzing finding, tests/fuzz/regressions/service).
  void invalidUtf8IsRefusedInWordsThatAreText() {
    const std::string text = "{\"f\xfc\xfcragility\": \"rigid\"}";
    const auto json = parse_json(text);
    QVERIFY(!json);
    const std::string message = json.diagnostics.front().message;
    QVERIFY2(message.find("not valid JSON") != std::string::npos, message.c_str());
    QCOMPARE(Json(message).dump().empty(), false);  // throws on invalid UTF-8
  }

  // nlohmann stops at a NUL as at the end of the text: "unexpected end of input at byte 1" for a
  // UTF-16 file. The message names the NUL and what puts one there.
  void aNulByteIsNamed() {
    const std::string text("{\0\"\0i\0", 7);
    const auto json = parse_json(text);
    QVERIFY(!json);
    const std::string message = json.diagnostics.front().message;
    QVERIFY2(message.starts_with("the text has a NUL byte at byte 2"), message.c_str());
    QVERIFY2(message.find("UTF-8") != std::string::npos, message.c_str());
  }

  void palletRoundTripIsIdentity() {
    const Json json = pallet_to_json(sample());
    const auto read = pallet_from_json(json);
    QVERIFY(read.ok());
    QVERIFY2(read.diagnostics.empty(), qPrintable(pointers(read.diagnostics)));
    QVERIFY(*read == sample());
    QCOMPARE(pallet_to_json(*read), json);
    QCOMPARE(to_canonical_text(pallet_to_json(*read)), to_canonical_text(json));
    // Through text as well: doubles survive exactly.
    const auto reparsed = parse_json(to_canonical_text(json));
    QVERIFY(reparsed.ok());
    QVERIFY(*pallet_from_json(*reparsed) == sample());
  }

  void palletKeysAreTheReferenceNamesPlusOurs() {
    const Json json = pallet_to_json(sample());
    QCOMPARE(keys_of(json),
             (QStringList{"base_dims_m", "base_mass_kg", "base_pallet_type", "belt_surface",
                          "body_temp_c", "composite_com_m", "env", "items", "notes", "overhang_m",
                          "pallet_id", "schema_version", "seconds_since_temp_change",
                          "stack_height_m", "total_mass_kg", "wrap"}));
    QCOMPARE(keys_of(json["items"][0]),
             (QStringList{"center_of_mass", "dims_m", "fragility", "orientation_deg", "position",
                          "sku", "weight_kg"}));
    QCOMPARE(json["base_pallet_type"], Json("CHEP"));
    QCOMPARE(json["wrap"], Json("banded"));
    QCOMPARE(json["env"], Json("transitioning"));
    QCOMPARE(json["belt_surface"], Json("steel_roller"));
    QCOMPARE(json["items"][0]["fragility"], Json("semi_rigid"));
    QCOMPARE(json["schema_version"], Json(kSchemaVersion));
    QCOMPARE(json["total_mass_kg"], Json(95.0));
    QCOMPARE(json["items"][2]["center_of_mass"], Json::array({-0.3, -0.2, 0.3 + 0.075}));
  }

  void withoutComputedFields() {
    const Json json = pallet_to_json(sample(), false);
    QCOMPARE(keys_of(json),
             (QStringList{"base_dims_m", "base_mass_kg", "base_pallet_type", "belt_surface",
                          "body_temp_c", "env", "items", "notes", "pallet_id", "schema_version",
                          "seconds_since_temp_change", "wrap"}));
    QVERIFY(!json["items"][0].contains("center_of_mass"));
    QVERIFY(!item_to_json(item(0, 0, 0), false).contains("center_of_mass"));
    QVERIFY(*pallet_from_json(json) == sample());
  }

  void emptyNotesAreNull() {
    PalletConfig config = sample();
    config.notes.clear();
    const Json json = pallet_to_json(config);
    QVERIFY(json["notes"].is_null());
    QVERIFY(*pallet_from_json(json) == config);
  }

  void notesMustBeAStringOrNull() {
    Json json = minimal();
    json["notes"] = 3;
    const auto read = pallet_from_json(json);
    QVERIFY(!read.ok());
    QCOMPARE(pointers(read.diagnostics), QString("/notes"));
  }

  void missingKeysTakeTheDefaults() {
    const auto read = pallet_from_json(minimal());
    QVERIFY(read.ok());
    QVERIFY(read.diagnostics.empty());
    PalletConfig expected;
    expected.wrap = WrapType::none;
    expected.env = Environment::frozen;
    expected.body_temp_c = -20.0;
    QVERIFY(*read == expected);
  }

  void anAbsentBaseIsTheNamedTypes() {
    for (const PalletType type : {PalletType::eur, PalletType::gma, PalletType::chep}) {
      Json json = minimal();
      json["base_pallet_type"] = std::string(to_string(type));
      const auto read = pallet_from_json(json);
      QVERIFY(read.ok());
      QVERIFY(read->base_dims_m == pallet_type_spec(type).dims_m);
      QCOMPARE(read->base_mass_kg, pallet_type_spec(type).mass_kg);
      json["base_dims_m"] = {1.0, 1.0, 0.12};  // given: it stands
      json["base_mass_kg"] = 30.0;
      QVERIFY((pallet_from_json(json)->base_dims_m == Vec3{1.0, 1.0, 0.12}));
      QCOMPARE(pallet_from_json(json)->base_mass_kg, 30.0);
    }
  }

  void requiredKeysAreErrors() {
    const auto read = pallet_from_json(Json::object({{"pallet_id", "x"}}), "/pallet");
    QVERIFY(!read.ok());
    QCOMPARE(read.diagnostics.size(), std::size_t{4});
    QCOMPARE(pointers(read.diagnostics),
             QString("/pallet/items /pallet/wrap /pallet/env /pallet/body_temp_c"));
    QVERIFY(contains(read.diagnostics[0].message, "'items'"));
    // A load is never assumed wrapped: the message lists what to write.
    QVERIFY(contains(read.diagnostics[1].message, "'wrap'"));
    QVERIFY(contains(read.diagnostics[1].message, enum_choices<WrapType>()));
    QVERIFY(contains(read.diagnostics[2].message, "'env'"));
    QVERIFY(contains(read.diagnostics[3].message, "'body_temp_c'"));
    for (const auto& d : read.diagnostics) QCOMPARE(d.severity, Severity::error);
  }

  void itemRequiredKeys() {
    Json json = minimal();
    json["items"] = Json::array({Json::object({{"fragility", "rigid"}})});
    const auto read = pallet_from_json(json);
    QVERIFY(!read.ok());
    QCOMPARE(pointers(read.diagnostics),
             QString("/items/0/sku /items/0/weight_kg /items/0/dims_m /items/0/position"));
  }

  void notAnObject() {
    const auto read = pallet_from_json(Json::array());
    QVERIFY(!read.ok());
    QCOMPARE(pointers(read.diagnostics), QString(""));
    QCOMPARE(read.diagnostics.size(), std::size_t{1});
    Json json = minimal();
    json["items"] = Json::array({1});
    QCOMPARE(pointers(pallet_from_json(json).diagnostics), QString("/items/0"));
    json["items"] = Json::object();
    QCOMPARE(pointers(pallet_from_json(json).diagnostics), QString("/items"));
  }

  void numbersAcceptIntegersAndFloats() {
    Json json = minimal();
    json["body_temp_c"] = 3;
    json["base_mass_kg"] = 22.5;
    const auto read = pallet_from_json(json);
    QVERIFY(read.ok());
    QCOMPARE(read->body_temp_c, 3.0);
    QCOMPARE(read->base_mass_kg, 22.5);
  }

  void numbersRejectBooleansAndStrings() {
    Json json = minimal();
    json["body_temp_c"] = true;
    json["base_mass_kg"] = "25";
    const auto read = pallet_from_json(json);
    QVERIFY(!read.ok());
    QCOMPARE(pointers(read.diagnostics), QString("/base_mass_kg /body_temp_c"));
    QVERIFY(contains(read.diagnostics[0].message, "found string"));
    QVERIFY(contains(read.diagnostics[1].message, "found boolean"));
  }

  void vec3NeedsExactlyThreeNumbers() {
    Json json = pallet_to_json(sample());
    json["base_dims_m"] = Json::array({1.2, 0.8});
    json["items"][2]["dims_m"][1] = "0.4";
    json["items"][0]["position"] = 0.15;
    const auto read = pallet_from_json(json);
    QVERIFY(!read.ok());
    QCOMPARE(pointers(read.diagnostics),
             QString("/base_dims_m /items/0/position /items/2/dims_m/1"));
    QVERIFY(contains(read.diagnostics[0].message, "an array of 2"));
  }

  void unknownEnumValueListsTheChoices() {
    Json json = minimal();
    json["wrap"] = "cling";
    json["env"] = "Frozen";
    json["base_pallet_type"] = "eur";
    json["belt_surface"] = 1;
    const auto read = pallet_from_json(json);
    QVERIFY(!read.ok());
    QCOMPARE(pointers(read.diagnostics), QString("/base_pallet_type /wrap /env /belt_surface"));
    QCOMPARE(read.diagnostics[1].message,
             std::string("'cling' is not a valid choice; use one of ") + enum_choices<WrapType>());
    QVERIFY(contains(read.diagnostics[0].message, "EUR, GMA or CHEP"));
    QVERIFY(contains(read.diagnostics[2].message, enum_choices<Environment>()));
    QVERIFY(contains(read.diagnostics[3].message, enum_choices<BeltSurface>()));
  }

  void unknownKeysAreWarnings() {
    Json json = minimal();
    json["foo"] = 1;
    json["items"] = Json::array({item_to_json(item(0, 0, 0.15))});
    json["items"][0]["colour"] = "red";
    const auto read = pallet_from_json(json);
    QVERIFY(read.ok());
    QCOMPARE(read.diagnostics.size(), std::size_t{2});
    QCOMPARE(read.diagnostics[0],
             (Diagnostic{"/foo", "unknown key 'foo' is ignored; remove it or fix its spelling",
                         Severity::warning}));
    QCOMPARE(read.diagnostics[1].pointer, std::string("/items/0/colour"));
    QCOMPARE(read.diagnostics[1].severity, Severity::warning);
  }

  void schemaVersion() {
    Json json = minimal();
    json["schema_version"] = kSchemaVersion;
    QVERIFY(pallet_from_json(json).ok());
    for (const Json& bad : {Json(kSchemaVersion + 1), Json(0), Json(1.5), Json("1"), Json(true)}) {
      json["schema_version"] = bad;
      const auto read = pallet_from_json(json);
      QVERIFY2(!read.ok(), bad.dump().c_str());
      QCOMPARE(pointers(read.diagnostics), QString("/schema_version"));
    }
    json["schema_version"] = kSchemaVersion + 1;
    QVERIFY(contains(pallet_from_json(json).diagnostics[0].message, "update the program"));
  }

  void computedFieldsAreCheckedNotRequired() {
    Json json = pallet_to_json(sample());
    json["total_mass_kg"] = 96.0;
    json["overhang_m"] = json["overhang_m"].get<double>() + 5e-7;  // within 1e-6: accepted
    json["items"][1]["center_of_mass"][2] = 0.5;
    json["stack_height_m"] = "tall";
    const auto read = pallet_from_json(json);
    QVERIFY(read.ok());
    QVERIFY(*read == sample());
    QCOMPARE(pointers(read.diagnostics),
             QString("/total_mass_kg /stack_height_m /items/1/center_of_mass"));
    for (const auto& d : read.diagnostics) QCOMPARE(d.severity, Severity::warning);
    QVERIFY(contains(read.diagnostics[0].message, "96.0 but the pallet gives 95"));
  }

  void readingCollectsEveryError() {
    Json json = pallet_to_json(sample());
    json["wrap"] = "x";
    json["items"][0]["weight_kg"] = nullptr;
    json["items"][2]["fragility"] = "soft";
    json.erase("env");
    const auto read = pallet_from_json(json);
    QVERIFY(!read.ok());
    QCOMPARE(pointers(read.diagnostics),
             QString("/items/0/weight_kg /items/2/fragility /wrap /env"));
  }

  void pointerPrefixAndEscaping() {
    Json json = minimal();
    json["a/b~c"] = 0;
    json["wrap"] = 2;
    const auto read = pallet_from_json(json, "/scenarios/0/pallet");
    QCOMPARE(pointers(read.diagnostics),
             QString("/scenarios/0/pallet/a~1b~0c /scenarios/0/pallet/wrap"));
  }

  void profileRoundTripAndKeys() {
    ConveyorProfile profile;
    profile.target_speed_mps = 1.25;
    profile.accel_mps2 = 0.1 + 0.2;
    profile.duration_s = 7.0;
    profile.shape = ProfileShape::curve;
    profile.decel_start_s = 4.5;
    profile.decel_mps2 = 3.0;
    profile.curve_radius_m = 2.5;
    profile.curve_angle_deg = 180.0;
    profile.curve_start_s = 0.25;
    profile.curve_turn = CurveTurn::right;
    profile.eumos_g = 0.8;
    profile.eumos_hold_s = 0.5;
    const Json json = profile_to_json(profile);
    QCOMPARE(keys_of(json),
             (QStringList{"accel_mps2", "curve_angle_deg", "curve_radius_m", "curve_start_s",
                          "curve_turn", "decel_mps2", "decel_start_s", "duration_s", "eumos_g",
                          "eumos_hold_s", "schema_version", "shape", "target_speed_mps"}));
    QCOMPARE(json["shape"], Json("curve"));
    const auto read = profile_from_json(json);
    QVERIFY(read.ok());
    QVERIFY(read.diagnostics.empty());
    QVERIFY(*read == profile);
    QCOMPARE(profile_to_json(*read), json);
  }

  void referenceProfileLoads() {
    const Json json = {{"target_speed_mps", 0.9},
                       {"accel_mps2", 0.8},
                       {"duration_s", 2.5},
                       {"shape", "ramp_decel"},
                       {"decel_start_s", 1.5}};
    const auto read = profile_from_json(json);
    QVERIFY(read.ok());
    QVERIFY(read.diagnostics.empty());
    ConveyorProfile expected;
    expected.target_speed_mps = 0.9;
    expected.accel_mps2 = 0.8;
    expected.duration_s = 2.5;
    expected.shape = ProfileShape::ramp_decel;
    expected.decel_start_s = 1.5;
    QVERIFY(*read == expected);
  }

  void profileDefaultsAndErrors() {
    QVERIFY(*profile_from_json(Json::object()) == ConveyorProfile{});
    const auto read = profile_from_json(
        Json{{"shape", "sine"}, {"accel_mps2", "fast"}, {"speed", 1}}, "/profile");
    QVERIFY(!read.ok());
    QCOMPARE(pointers(read.diagnostics), QString("/profile/speed /profile/accel_mps2 "
                                                 "/profile/shape"));
    QCOMPARE(read.diagnostics[0].severity, Severity::warning);
  }

  // Without duration_s a profile runs the reference's 5 s, or until its motion ends plus a
  // second where that is later, at most 30 s; a duration given is kept.
  void anAbsentDurationSeesTheMotionEnd() {
    const Json estop{{"shape", "estop"}, {"target_speed_mps", 1.5}, {"decel_mps2", 2}};
    QCOMPARE(profile_from_json(estop)->duration_s, 5.0);  // it stands at 3.75 s
    Json slow = estop;
    slow["decel_mps2"] = 0.25;  // stands at 3 + 6 s
    QCOMPARE(profile_from_json(slow)->duration_s, 10.0);
    slow["decel_start_s"] = 25.0;
    QCOMPARE(profile_from_json(slow)->duration_s, kMaxProfileDurationS);
    QCOMPARE(validate_profile(*profile_from_json(slow)).size(), std::size_t(1));  // it says so
    slow["duration_s"] = 4.0;
    QCOMPARE(profile_from_json(slow)->duration_s, 4.0);
  }

  void parseJsonReportsTheByteOffset() {
    const auto good = parse_json("{\"a\": [1, 2.5]}");
    QVERIFY(good.ok());
    QCOMPARE((*good)["a"][1], Json(2.5));
    const auto bad = parse_json("{\"a\": [1, }");
    QVERIFY(!bad.ok());
    QCOMPARE(bad.diagnostics.size(), std::size_t{1});
    QCOMPARE(bad.diagnostics[0].pointer, std::string(""));
    QVERIFY2(contains(bad.diagnostics[0].message, "at byte 11"),
             bad.diagnostics[0].message.c_str());
    QVERIFY(!parse_json("").ok());
  }

  // A member given twice in one object says two things (nlohmann keeps the last, other readers
  // the first): refused at its pointer, however deep; the same key in two objects is fine.
  void aMemberGivenTwiceIsRefusedAtItsPointer() {
    const auto top = parse_json(R"({"weight_kg": 5, "weight_kg": 50})");
    QVERIFY(!top.ok());
    QCOMPARE(top.diagnostics[0].pointer, std::string("/weight_kg"));
    QVERIFY2(contains(top.diagnostics[0].message, "appears twice"),
             top.diagnostics[0].message.c_str());
    const auto deep = parse_json(R"({"a": 1, "items": [{"x": 1}, [2, {"d": 2, "e": 1, "d": 3}]]})");
    QVERIFY(!deep.ok());
    QCOMPARE(deep.diagnostics[0].pointer, std::string("/items/1/1/d"));
    const auto escaped = parse_json(R"({"a/b": {"k": 1, "k": 2}})");
    QVERIFY(!escaped.ok());
    QCOMPARE(escaped.diagnostics[0].pointer, std::string("/a~1b/k"));
    QVERIFY(parse_json(R"({"a": {"k": 1}, "b": {"k": 2}, "c": [{"k": 1}, {"k": 2}]})").ok());
  }

  // A number beyond a double's range cannot be read at all: nlohmann throws with no position, so
  // the error names the field it was given for (a member's key, an array's index) and the number.
  void aNumberBeyondADoubleIsRefusedAtItsPointer() {
    const auto member = parse_json(R"({"items": [{"weight_kg": 6}, {"weight_kg": 1e999}]})");
    QVERIFY(!member.ok());
    QCOMPARE(member.diagnostics[0].pointer, std::string("/items/1/weight_kg"));
    QVERIFY2(contains(member.diagnostics[0].message, "1e999"),
             member.diagnostics[0].message.c_str());
    const auto element = parse_json(R"({"base_dims_m": [1.2, -1e400, 0.15]})");
    QVERIFY(!element.ok());
    QCOMPARE(element.diagnostics[0].pointer, std::string("/base_dims_m/1"));
    const auto top = parse_json("1e999");
    QVERIFY(!top.ok());
    QCOMPARE(top.diagnostics[0].pointer, std::string(""));
    // An integer beyond 64 bits is read as a double, and the value's own check judges it.
    QVERIFY(parse_json(R"({"weight_kg": 18446744073709551616})").ok());
  }

  void canonicalTextIsSortedCompactAndExact() {
    const Json json = {{"b", 0.1 + 0.2}, {"a", Json::array({1, 2.0})}, {"c", nullptr}};
    QCOMPARE(to_canonical_text(json),
             std::string("{\"a\":[1,2.0],\"b\":0.30000000000000004,\"c\":null}"));
    const Json again = *parse_json(to_canonical_text(json));
    QCOMPARE(again["b"].get<double>(), 0.1 + 0.2);
    // Invalid UTF-8 does not throw.
    QCOMPARE(to_canonical_text(Json("\xff")), std::string("\"\xEF\xBF\xBD\""));
  }

  void referencePayloadLoadsUnchanged() {
    const Json json = reference_payload();
    QVERIFY(!json.contains("schema_version"));
    QVERIFY(!json.contains("belt_surface"));
    QVERIFY(json["notes"].is_null());
    const auto read = pallet_from_json(json);
    QVERIFY(read.ok());
    QVERIFY2(read.diagnostics.empty(), qPrintable(pointers(read.diagnostics)));
    const PalletConfig& config = *read;
    QCOMPARE(config.pallet_id, std::string("stable-dairy-slab"));
    QCOMPARE(config.base_pallet_type, PalletType::eur);
    QCOMPARE(config.base_dims_m, (Vec3{1.2, 0.8, 0.15}));
    QCOMPARE(config.base_mass_kg, 25.0);
    QCOMPARE(config.wrap, WrapType::stretch);
    QCOMPARE(config.env, Environment::refrigerated);
    QCOMPARE(config.body_temp_c, 2.0);
    QCOMPARE(config.seconds_since_temp_change, 3600.0);
    QVERIFY(config.notes.empty());
    QCOMPARE(config.belt_surface, BeltSurface::rubber_belt);
    QCOMPARE(config.items.size(), std::size_t{8});
    for (std::size_t i = 0; i < config.items.size(); ++i) {
      const Item& it = config.items[i];
      const Json& written = json["items"][i];
      QCOMPARE(it.sku, std::string("SKU-FD-001"));
      QCOMPARE(it.weight_kg, 25.0);
      QCOMPARE(it.dims_m, (Vec3{0.4, 0.4, 0.15}));
      QCOMPARE(it.fragility, Fragility::rigid);
      QCOMPARE(it.orientation_deg, 0.0);
      QCOMPARE(it.position, written["position"].get<Vec3>());
      QCOMPARE(it.position[2], i % 2 == 0 ? 0.15 : 0.3);
    }
    QCOMPARE(config.items[0].position[0], -0.3);
    QCOMPARE(config.items[0].position[1], -0.2);
    QCOMPARE(total_mass_kg(config), 225.0);
    QCOMPARE(Json(stack_height_m(config)), json["stack_height_m"]);
    const Diagnostics findings = validate(config);
    QVERIFY2(!has_errors(findings), qPrintable(pointers(findings)));
  }

  void referencePayloadRewritesWithOurAdditionsOnly() {
    const Json json = reference_payload();
    Json written = pallet_to_json(*pallet_from_json(json));
    QCOMPARE(written["schema_version"], Json(kSchemaVersion));
    QCOMPARE(written["belt_surface"], Json("rubber_belt"));
    written.erase("schema_version");
    written.erase("belt_surface");
    QCOMPARE(to_canonical_text(written), to_canonical_text(json));
  }
};

QTEST_APPLESS_MAIN(JsonIoTest)
#include "json_io_test.moc"
