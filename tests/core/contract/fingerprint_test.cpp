// SPDX-License-Identifier: MIT
// Fingerprints: equal physics gives equal keys, any physical difference a different one.
#include "core/contract/fingerprint.hpp"

#include <QtTest>

#include "core/base/sha256.hpp"

using namespace pb;

namespace {

PalletConfig sample() {
  PalletConfig config;
  config.pallet_id = "PAL-0001";
  config.base_pallet_type = PalletType::eur;
  Item a;
  a.sku = "SKU-A";
  a.weight_kg = 12.5;
  a.dims_m = {0.4, 0.3, 0.25};
  a.position = {-0.2, 0.0, 0.15};
  Item b = a;
  b.sku = "SKU-B";
  b.position = {0.2, 0.0, 0.15};
  b.orientation_deg = 90.0;
  config.items = {a, b};
  config.env = Environment::frozen;
  config.body_temp_c = -18.0;
  config.notes = "dock 4";
  return config;
}

QString fingerprint(const PalletConfig& config) {
  return QString::fromStdString(config_fingerprint(config));
}

// The same pallet written twice with every object's keys in a different order.
constexpr const char* kKeysForward = R"({
  "pallet_id": "P1", "base_pallet_type": "GMA", "base_dims_m": [1.219, 1.016, 0.14],
  "base_mass_kg": 22, "wrap": "shrink", "env": "refrigerated", "body_temp_c": 3.5,
  "items": [{"sku": "S1", "weight_kg": 8, "dims_m": [0.5, 0.4, 0.3], "fragility": "rigid",
             "position": [0.1, -0.1, 0.14], "orientation_deg": 0}]
})";
constexpr const char* kKeysReversed = R"({
  "items": [{"orientation_deg": 0, "position": [0.1, -0.1, 0.14], "fragility": "rigid",
             "dims_m": [0.5, 0.4, 0.3], "weight_kg": 8, "sku": "S1"}],
  "body_temp_c": 3.5, "env": "refrigerated", "wrap": "shrink", "base_mass_kg": 22,
  "base_dims_m": [1.219, 1.016, 0.14], "base_pallet_type": "GMA", "pallet_id": "P1"
})";

PalletConfig load(const char* text) {
  const auto json = parse_json(text);
  if (!json) return {};
  const auto config = pallet_from_json(*json);
  return config ? *config : PalletConfig{};
}

}  // namespace

class FingerprintTest : public QObject {
  Q_OBJECT

 private slots:
  void isLowercaseHex() {
    const QString f = fingerprint(sample());
    QCOMPARE(f.size(), 64);
    QVERIFY(QRegularExpression("^[0-9a-f]{64}$").match(f).hasMatch());
  }

  void nameAndNotesDoNotCount() {
    PalletConfig renamed = sample();
    renamed.pallet_id = "another name";
    renamed.notes = "";
    QCOMPARE(fingerprint(renamed), fingerprint(sample()));
  }

  void everyPhysicalFieldCounts() {
    const QString base = fingerprint(sample());
    std::vector<PalletConfig> changed(8, sample());
    changed[0].items[1].position[0] += 1e-9;
    changed[1].wrap = WrapType::banded;
    changed[2].body_temp_c = -17.5;
    changed[3].belt_surface = BeltSurface::steel_roller;
    changed[4].items[0].weight_kg = 12.6;
    changed[5].seconds_since_temp_change = 60.0;
    changed[6].base_pallet_type = PalletType::chep;
    std::swap(changed[7].items[0], changed[7].items[1]);  // item order names the items
    for (std::size_t k = 0; k < changed.size(); ++k) {
      QVERIFY2(fingerprint(changed[k]) != base, qPrintable(QString::number(k)));
    }
  }

  void keyOrderDoesNotCount() {
    const PalletConfig forward = load(kKeysForward);
    const PalletConfig reversed = load(kKeysReversed);
    QCOMPARE(forward.items.size(), std::size_t{1});
    QCOMPARE(forward.base_pallet_type, PalletType::gma);
    QCOMPARE(fingerprint(reversed), fingerprint(forward));
    QCOMPARE(fingerprint_json(Json::parse(R"({"b": 2, "a": [1, {"d": 4, "c": 3}]})")),
             fingerprint_json(Json::parse(R"({"a": [1, {"c": 3, "d": 4}], "b": 2})")));
  }

  void jsonFingerprintIsShaOfCanonicalText() {
    const Json json = Json::parse(R"({"solver": {"dt": 0.002}, "pallet": "abc"})");
    QCOMPARE(QString::fromStdString(fingerprint_json(json)),
             QString::fromStdString(sha256_hex(R"({"pallet":"abc","solver":{"dt":0.002}})")));
  }

  // Guards the canonical form: if this changes, every cached model and stored config_hash is
  // invalidated, so change it only on purpose. (Cross-checked with Python hashlib over the text.)
  void pinnedValue() {
    QCOMPARE(fingerprint(sample()),
             QStringLiteral("5abf98db5560cb69bb382ce6c89a2fb25f2cda1b7b567446bcafdd357d905800"));
  }
};

QTEST_APPLESS_MAIN(FingerprintTest)
#include "fingerprint_test.moc"
