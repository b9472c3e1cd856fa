// SPDX-License-Identifier: MIT
#include "core/fidelity.hpp"

#include <QtTest>

using namespace pb;

static_assert(to_string(Fidelity::automatic) == "auto");
static_assert(enum_from_string<Fidelity>("closed_form") == Fidelity::closed_form);

class FidelityTest : public QObject {
  Q_OBJECT

 private slots:
  void namesRoundTrip() {
    const auto& names = EnumTable<Fidelity>::names;
    QCOMPARE(names.size(), std::size_t{4});
    for (std::size_t i = 0; i < names.size(); ++i) {
      QCOMPARE(static_cast<std::size_t>(names[i].value), i);
      QCOMPARE(enum_from_string<Fidelity>(names[i].name), std::optional(names[i].value));
    }
    QCOMPARE(to_string(Fidelity::reduced), std::string_view("reduced"));
    QCOMPARE(to_string(Fidelity::full), std::string_view("full"));
    QVERIFY(!enum_from_string<Fidelity>("automatic"));
    QCOMPARE(enum_choices<Fidelity>(), std::string("auto, closed_form, reduced or full"));
  }
};

QTEST_APPLESS_MAIN(FidelityTest)
#include "fidelity_test.moc"
