// SPDX-License-Identifier: MIT
// The one JSON reader: each kind of mistake, its one wording and its pointer.
#include "core/contract/json_reader.hpp"

#include <QtTest>

#include "core/contract/pallet_config.hpp"

using namespace pb;

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

// "pointer: message" of every diagnostic, "; "-joined.
QString describe(const Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : diagnostics) out << q(to_string(d));
  return out.join(QStringLiteral("; "));
}

}  // namespace

class JsonReaderTest : public QObject {
  Q_OBJECT

 private slots:
  void wordings() {
    QCOMPARE(q(wording::wrong_type("a number", "string", "write a plain number")),
             QStringLiteral("expected a number, found string; write a plain number"));
    QCOMPARE(q(wording::missing_key("env")),
             QStringLiteral("the required key 'env' is missing; add it"));
    QCOMPARE(q(wording::unknown_key("colour")),
             QStringLiteral("unknown key 'colour' is ignored; remove it or fix its spelling"));
    QCOMPARE(q(wording::not_a_choice("cling", "none or shrink")),
             QStringLiteral("'cling' is not a valid choice; use one of none or shrink"));
    QCOMPARE(q(wording::out_of_range("2.5", "a number in [0, 2]")),
             QStringLiteral("2.5 is out of range; write a number in [0, 2]"));
    const std::string_view names[] = {"a", "b", "c"};
    QCOMPARE(q(join_choices(names)), QStringLiteral("a, b or c"));
    QCOMPARE(q(join_choices(std::span(names, 1))), QStringLiteral("a"));
  }

  void pointersEscapeKeys() {
    QCOMPARE(q(member_pointer("/surface_pairs", "carton/carton")),
             QStringLiteral("/surface_pairs/carton~1carton"));
    QCOMPARE(q(member_pointer("", "a~b")), QStringLiteral("/a~0b"));
    QCOMPARE(q(element_pointer("/items", 3)), QStringLiteral("/items/3"));
  }

  void wrongTypes() {
    JsonReader reader;
    double number = 7.0;
    int whole = 7;
    std::string text = "kept";
    bool flag = true;
    QVERIFY(!reader.read(Json("1"), "/n", number));
    QVERIFY(!reader.read(Json(1.5), "/i", whole));
    QVERIFY(!reader.read(Json(3), "/s", text));
    QVERIFY(!reader.read(Json(nullptr), "/b", flag));
    QCOMPARE(number, 7.0);  // a failed read leaves its output alone
    QCOMPARE(whole, 7);
    QCOMPARE(q(text), QStringLiteral("kept"));
    QCOMPARE(flag, true);
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("/n: expected a number, found string; write a plain number; "
                            "/i: expected a whole number, found number 1.5; write an integer "
                            "such as 0; "
                            "/s: expected a string, found number 3; write it in quotes; "
                            "/b: expected true or false, found null; write true or false"));
  }

  void valuesThatRead() {
    JsonReader reader;
    double number = 0.0;
    int whole = 0;
    std::uint64_t seed = 0;
    std::string text;
    bool flag = false;
    Vec3 v{};
    QVERIFY(reader.read(Json(3), "", number));  // an integer is a number
    QVERIFY(reader.read(Json(-4), "", whole));
    QVERIFY(reader.read(Json(18446744073709551615ull), "", seed));
    QVERIFY(reader.read(Json("x"), "", text));
    QVERIFY(reader.read(Json(true), "", flag));
    QVERIFY(reader.read(Json::array({1, 2.5, -3}), "", v));
    QVERIFY(reader.diagnostics.empty());
    QCOMPARE(number, 3.0);
    QCOMPARE(whole, -4);
    QCOMPARE(seed, std::uint64_t{18446744073709551615ull});
    QCOMPARE(q(text), QStringLiteral("x"));
    QVERIFY(flag);
    QCOMPARE(v, (Vec3{1.0, 2.5, -3.0}));
  }

  void outOfRange() {
    JsonReader reader;
    int whole = 0;
    std::uint64_t seed = 0;
    double number = 0.0;
    QVERIFY(!reader.read(Json(3000000000ll), "/i", whole));
    QVERIFY(!reader.read(Json(-1), "/seed", seed));
    QVERIFY(!reader.read(Json(std::numeric_limits<double>::infinity()), "/x", number));
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("/i: 3000000000 is out of range; write a whole number from "
                            "-2147483648 to 2147483647; "
                            "/seed: -1 is out of range; write a whole number >= 0; "
                            "/x: inf is out of range; write a finite number"));
  }

  void fixedArraysPointAtTheElement() {
    JsonReader reader;
    Vec3 v{};
    std::array<double, 2> belt{};
    QVERIFY(!reader.read(Json::array({1, 2}), "/dims_m", v));
    QVERIFY(!reader.read(Json(0.15), "/position", v));
    QVERIFY(!reader.numbers(Json::array({1, "2"}), "/belt", belt, "[x, y]"));
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("/dims_m: expected an array of exactly 3 numbers [x, y, z], found an "
                            "array of 2; write 3 numbers; "
                            "/position: expected an array of exactly 3 numbers [x, y, z], found "
                            "number 0.15; write 3 numbers; "
                            "/belt/1: expected a number, found string; write a plain number"));
  }

  void enumChoices() {
    JsonReader reader;
    WrapType wrap = WrapType::none;
    QVERIFY(reader.read(Json("banded"), "/wrap", wrap));
    QCOMPARE(wrap, WrapType::banded);
    QVERIFY(!reader.read(Json("cling"), "/wrap", wrap));
    QVERIFY(!reader.read(Json(1), "/wrap", wrap));
    QCOMPARE(wrap, WrapType::banded);
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("/wrap: 'cling' is not a valid choice; use one of none, shrink, "
                            "stretch or banded; "
                            "/wrap: expected a string, found number 1; use one of none, shrink, "
                            "stretch or banded"));
  }

  void choiceGivesTheIndex() {
    JsonReader reader;
    constexpr std::string_view outcomes[] = {"safe", "failed", "unstable"};
    std::size_t index = 9;
    QVERIFY(reader.choice(Json("unstable"), "/outcome", outcomes, index));
    QCOMPARE(index, std::size_t{2});
    QVERIFY(!reader.choice(Json("exploded"), "/outcome", outcomes, index));
    QCOMPARE(index, std::size_t{2});
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("/outcome: 'exploded' is not a valid choice; use one of safe, failed "
                            "or unstable"));
  }

  void missingMembersPointAtTheirObject() {
    JsonReader reader;
    const Json object = {{"a", 1}};
    double a = 0.0;
    double b = 5.0;
    QVERIFY(reader.field(object, "/p", "a", a, Need::required));
    QVERIFY(reader.field(object, "/p", "b", b));  // optional and absent: kept
    QCOMPARE(b, 5.0);
    QVERIFY(reader.diagnostics.empty());
    QVERIFY(!reader.field(object, "/p", "b", b, Need::required));
    QVERIFY(reader.member(object, "/p", "c", Need::optional) == nullptr);
    QVERIFY(reader.member(Json(3), "/q", "d", Need::required) == nullptr);  // not an object
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("/p/b: the required key 'b' is missing; add it; "
                            "/q/d: the required key 'd' is missing; add it"));
  }

  void nestedPointers() {
    const Json doc = Json::parse(R"({"items": [{"dims_m": [0.4, 0.4, 0.15]},
                                               {"dims_m": [0.4, "x", 0.15]}]})");
    JsonReader reader;
    const Json* items = reader.member(doc, "", "items", Need::required);
    QVERIFY(items != nullptr);
    QVERIFY(reader.array(*items, "/items", "the items", "[{...}, ...]"));
    for (std::size_t i = 0; i < items->size(); ++i) {
      Vec3 dims{};
      reader.field((*items)[i], element_pointer("/items", i), "dims_m", dims, Need::required);
    }
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("/items/1/dims_m/1: expected a number, found string; write a plain "
                            "number"));
  }

  void shapes() {
    JsonReader reader;
    QVERIFY(reader.object(Json::object(), "", "a pallet"));
    QVERIFY(!reader.object(Json::array(), "", "a pallet"));
    QVERIFY(!reader.object(Json("x"), "/frames/2", "a frame", "{\"t\", ...}"));
    QVERIFY(reader.array(Json::array({1}), "/p", "the points", "[...]", 1));
    QVERIFY(!reader.array(Json::array(), "/p", "the points", "[...]", 1));
    QVERIFY(!reader.array(Json::object(), "/q", "the frames", "[]"));
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("(document): expected a pallet as a JSON object, found array; write "
                            "it as {\"key\": value, ...}; "
                            "/frames/2: expected a frame as a JSON object, found string; write it "
                            "as {\"t\", ...}; "
                            "/p: expected the points as a JSON array of at least 1 element, found "
                            "an array of 0; write it as [...]; "
                            "/q: expected the frames as a JSON array, found object; write it as "
                            "[]"));
  }

  void unknownKeysAreWarnings() {
    const Json object = {{"known", 1}, {"colour", 2}, {"_comment", "x"}, {"a/b", 3}};
    JsonReader reader;
    reader.unknown_keys(object, "/p", {"known"});
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("warning: /p/_comment: unknown key '_comment' is ignored; remove it "
                            "or fix its spelling; "
                            "warning: /p/a~1b: unknown key 'a/b' is ignored; remove it or fix its "
                            "spelling; "
                            "warning: /p/colour: unknown key 'colour' is ignored; remove it or "
                            "fix its spelling"));
    JsonReader comments;
    comments.unknown_keys(object, "/p", {"known"}, Comments::underscore);
    QCOMPARE(comments.diagnostics.size(), std::size_t{2});
    auto result = comments.finish(1);
    QVERIFY(result.ok());  // warnings accompany a value
    QCOMPARE(result.diagnostics.size(), std::size_t{2});
  }

  void schemaVersion() {
    for (const Json& good : {Json::object(), Json{{"schema_version", kSchemaVersion}}}) {
      JsonReader reader;
      reader.schema_version(good, "");
      QVERIFY(reader.diagnostics.empty());
    }
    JsonReader reader;
    reader.schema_version(Json{{"schema_version", kSchemaVersion + 1}}, "/pallet");
    reader.schema_version(Json{{"schema_version", 0}}, "");
    reader.schema_version(Json{{"schema_version", "1"}}, "");
    QCOMPARE(describe(reader.diagnostics),
             QStringLiteral("/pallet/schema_version: 2 is out of range; write a version from 1 "
                            "to 1, or update the program; "
                            "/schema_version: 0 is out of range; write a version from 1 to 1; "
                            "/schema_version: expected a whole number, found string; write a "
                            "version from 1 to 1"));
    QVERIFY(!reader.finish(1).ok());
  }

  void mergeAndCount() {
    JsonReader reader;
    reader.warning("/a", "w");
    reader.merge({{"/b", "e", Severity::error}, {"/c", "w", Severity::warning}});
    QCOMPARE(reader.diagnostics.size(), std::size_t{3});
    QCOMPARE(reader.error_count(), std::size_t{1});
  }
};

QTEST_APPLESS_MAIN(JsonReaderTest)
#include "json_reader_test.moc"
