// SPDX-License-Identifier: MIT
// A large unwrapped load analyses within a memory cap, measured as the peak resident set of the
// CLI process that ran it (wait4's rusage), and an impossible one is refused before simulating.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <QtTest>
#include <fstream>

#include "cli_runner.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"

namespace {

// Layers of nx x ny cartons filling a EUR deck, unwrapped, refrigerated (mu ~0.4-0.5).
std::string layered_pallet(int layers, int nx, int ny, double kg) {
  pb::PalletConfig p;
  p.pallet_id = "memory-test";
  p.wrap = pb::WrapType::none;
  p.body_temp_c = 2.0;
  const double lx = 1.2 / nx, ly = 0.8 / ny;
  for (int l = 0; l < layers; ++l) {
    for (int i = 0; i < nx; ++i) {
      for (int j = 0; j < ny; ++j) {
        pb::Item it;
        it.sku = "test";
        it.weight_kg = kg;
        it.dims_m = {lx, ly, 0.25};
        it.position = {-0.6 + lx * (i + 0.5), -0.4 + ly * (j + 0.5), 0.15 + 0.25 * l};
        p.items.push_back(it);
      }
    }
  }
  return pb::pallet_to_json(p).dump();
}

struct Measured {
  int exit_code = -1;
  long peak_rss_kb = 0;
};

// Runs the CLI in a child process and takes its peak resident set from wait4.
Measured run_measured(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    const std::string exe = PB_BIN_DIR "/palletballet-cli";
    argv.push_back(const_cast<char*>(exe.c_str()));
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execv(exe.c_str(), argv.data());
    _exit(127);
  }
  Measured m;
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) == pid && WIFEXITED(status)) {
    m.exit_code = WEXITSTATUS(status);
    m.peak_rss_kb = usage.ru_maxrss;
  }
  return m;
}

}  // namespace

class MemoryCliTest : public QObject {
  Q_OBJECT

 private slots:
  // 32 unwrapped cartons (two layers of 16): the whole envelope, four axis threads included, in
  // well under 400 MB (2.1 GB before the buffers followed the scene).
  void largeUnwrappedLoadStaysWithinTheCap() {
    QTemporaryDir dir;
    const QString path = pb::test::write_file(
        dir, "p32.json", QByteArray::fromStdString(layered_pallet(2, 4, 4, 8.0)));
    const Measured m = run_measured({"analyze", path.toStdString()});
    QCOMPARE(m.exit_code, 0);
    QVERIFY2(m.peak_rss_kb > 0 && m.peak_rss_kb < 400 * 1024,
             qPrintable(QString("peak RSS %1 MB").arg(m.peak_rss_kb / 1024)));
  }

  // A load the engine cannot hold is refused before any simulation, quickly and in words.
  void impossibleLoadIsRefusedInWords() {
    QTemporaryDir dir;
    const QString path = pb::test::write_file(
        dir, "p288.json", QByteArray::fromStdString(layered_pallet(3, 12, 8, 2.0)));
    const pb::test::Run r = pb::test::cli({"analyze", path});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("constraint rows") && r.err.contains("split the load"), r.err);
  }
};

QTEST_APPLESS_MAIN(MemoryCliTest)
#include "memory_cli_test.moc"
