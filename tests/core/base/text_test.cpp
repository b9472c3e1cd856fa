// SPDX-License-Identifier: MIT
// Numbers in messages: fixed decimals, and never a truncated wall of digits for a huge number.
#include "core/base/text.hpp"

#include <QtTest>
#include <cmath>
#include <limits>

class TextTest : public QObject {
  Q_OBJECT

 private slots:
  void fixedDecimals() {
    QCOMPARE(pb::fixed(0.4, 2), std::string("0.40"));
    QCOMPARE(pb::fixed(-3.14159, 3), std::string("-3.142"));
    QCOMPARE(pb::fixed(123456789012.5, 1), std::string("123456789012.5"));
  }

  // A limit is never shown above itself: "up to 1.2 m/s^2" for 1.168 or 1.25 is a promise the
  // pallet does not keep. A sum's last-bit error under the digits does not drop a step.
  void limitsAreFlooredNotRounded() {
    QCOMPARE(pb::fixed_floor(1.168, 1), std::string("1.1"));
    QCOMPARE(pb::fixed_floor(1.25 + 2e-16, 1), std::string("1.2"));
    QCOMPARE(pb::fixed_floor(0.2265, 2), std::string("0.22"));
    double sum = 0.0;
    for (int i = 0; i < 13; ++i)
      sum += 0.1;  // 1.3000000000000003, and 0.1 * 3 = 0.30000000000000004
    QCOMPARE(pb::fixed_floor(sum, 1), std::string("1.3"));
    QCOMPARE(pb::fixed_floor(1.2999999999999998, 1), std::string("1.3"));
    QCOMPARE(pb::fixed_floor(0.0, 2), std::string("0.00"));
    QCOMPARE(pb::fixed_floor(2.0, 2), std::string("2.00"));
    QCOMPARE(pb::fixed_floor(1e300, 2), std::string("1e+300"));
  }

  // A hostile 1e300 read as a temperature was shown as 63 digits cut off mid-number.
  void hugeNumbersAreScientific() {
    QCOMPARE(pb::fixed(1e300, 2), std::string("1e+300"));
    QCOMPARE(pb::fixed(-1e308, 2), std::string("-1e+308"));
    QCOMPARE(pb::fixed(2.5e15, 1), std::string("2.5e+15"));
    QCOMPARE(pb::fixed(std::numeric_limits<double>::infinity(), 2), std::string("inf"));
    QCOMPARE(pb::fixed(std::nan(""), 2), std::string("nan"));
  }
};

QTEST_APPLESS_MAIN(TextTest)
#include "text_test.moc"
