// SPDX-License-Identifier: MIT
// core/lab/stability_study.hpp: every stability case comes out as pinned, every numerically broken
// case is detected unstable (never a verdict), and the reference's probes discriminate (the lower
// one is safe, the upper one fails), so "correct" means something.
#include <QtTest>

#include <set>

#include "core/lab/stability_study.hpp"

using namespace pb;

class StabilityStudyTest : public QObject {
  Q_OBJECT

 private slots:
  void casesAreWellFormed() {
    std::set<std::string> names;
    std::set<std::string> groups;
    for (const auto& c : stability_cases()) {
      QVERIFY2(names.insert(c.name).second, c.name.c_str());
      groups.insert(c.group);
      if (c.broken) QCOMPARE(c.expected, StabilityClass::detected_unstable);
      const auto pallets = stability_pallet_names();
      QVERIFY(std::find(pallets.begin(), pallets.end(), c.pallet) != pallets.end());
    }
    QCOMPARE(groups.size(), std::size_t{6});
  }

  void everyCaseIsClassifiedAsPinned() {
    const auto rows = run_stability_study(stability_cases());
    std::set<std::string> checked_references;
    for (const auto& row : rows) {
      if (checked_references.insert(row.c.pallet).second) {
        QCOMPARE(row.reference.size(), std::size_t{2});
        QCOMPARE(row.reference[0].outcome, Outcome::safe);
        QCOMPARE(row.reference[1].outcome, Outcome::failed);
      }
      const std::string what = row.c.name + ": got " + std::string(to_string(row.got)) +
                               ", expected " + std::string(to_string(row.c.expected)) + " (" +
                               row.detail + ")";
      QVERIFY2(!row.missing_guard(), what.c_str());
      QVERIFY2(row.got == row.c.expected, what.c_str());
      if (row.got == StabilityClass::detected_unstable) QVERIFY(!row.detail.empty());
    }
    QCOMPARE(checked_references.size(), stability_pallet_names().size());
  }
};

QTEST_APPLESS_MAIN(StabilityStudyTest)
#include "stability_study_test.moc"
