// SPDX-License-Identifier: MIT
// The core never includes Qt: every file under core/ is scanned for an #include of a Qt header.
// (The test itself uses Qt Test as its harness only.)
#include <QtTest>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace {

namespace fs = std::filesystem;

// An #include whose header starts with a capital Q: <QString>, "QObject", <Qt>, <QtCore/QList>.
bool includes_qt_header(const std::string& line) {
  // A plain literal: moc's tokenizer mistakes a raw string holding '"' for the end of a string.
  static const std::regex pattern("^\\s*#\\s*include\\s*[<\"]Q");
  return std::regex_search(line, pattern);
}

struct Scan {
  std::vector<std::string> files;     ///< relative to the source tree
  std::vector<std::string> offences;  ///< "core/x.cpp:12: #include <QString>"
};

Scan scan_core() {
  Scan scan;
  const fs::path root(PB_SOURCE_DIR);
  for (const auto& entry : fs::recursive_directory_iterator(root / "core")) {
    if (!entry.is_regular_file()) continue;
    const std::string relative = fs::relative(entry.path(), root).generic_string();
    scan.files.push_back(relative);
    std::ifstream in(entry.path());
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      if (includes_qt_header(line)) {
        scan.offences.push_back(relative + ":" + std::to_string(number) + ": " + line);
      }
    }
  }
  return scan;
}

}  // namespace

class NoQtTest : public QObject {
  Q_OBJECT

 private slots:
  void detectorFlagsQtIncludes() {
    for (const char* line :
         {"#include <QString>", "#include \"QObject\"", "#include <QtCore/QList>", "#include <Qt>",
          "#include <QtGlobal>", "  #  include <QVector>", "#include<QHash>",
          "#include <QString>  // for the UI"}) {
      QVERIFY2(includes_qt_header(line), line);
    }
  }

  void detectorIgnoresOtherLines() {
    for (const char* line :
         {"#include \"core/quaternion.hpp\"", "#include <queue>", "#include <nlohmann/json.hpp>",
          "// #include <QString>", "const char* s = \"#include <QString>\";", "QString s;",
          "#include \"core/Qt_free.hpp\""}) {
      QVERIFY2(!includes_qt_header(line), line);
    }
  }

  void coreIncludesNoQtHeader() {
    const Scan scan = scan_core();
    // Guard against scanning the wrong folder and passing vacuously.
    QVERIFY2(std::find(scan.files.begin(), scan.files.end(), "core/inputs/friction.cpp") !=
                 scan.files.end(),
             "core/inputs/friction.cpp was not among the scanned files");
    QVERIFY(scan.files.size() >= 10);
    std::string report;
    for (const auto& offence : scan.offences) report += "\n  " + offence;
    QVERIFY2(scan.offences.empty(), ("core/ must not include Qt headers:" + report).c_str());
  }
};

QTEST_APPLESS_MAIN(NoQtTest)
#include "no_qt_test.moc"
