// SPDX-License-Identifier: MIT
// The console's command line (`palletballet --scenario SLUG ... --screenshot OUT.png`) and the
// headless run that opens the console, dispatches the scenario, places the replay at the asked
// time and writes a PNG of the window or of the replay view alone.
#pragma once

#include <QObject>
#include <QSize>
#include <QString>
#include <optional>

#include "core/contract/conveyor_profile.hpp"

namespace pb::ui {

class MainWindow;

struct ConsoleRequest {
  enum class At { failure, end, time };

  QString slug;
  pb::ConveyorProfile profile;  ///< the scenario's suggested one, with the given speed / accel
  QString screenshotPath;       ///< empty: open the console interactively
  At at = At::failure;
  double atTime = 0.0;  ///< s, when at == time
  QSize size{1600, 1000};
  bool replayOnly = false;

  /// Fills `out` from the option values (empty speed / accel: the scenario's). Empty on success,
  /// else what to change, naming the option.
  static QString parse(const QString& slug, const QString& speed, const QString& accel,
                       const QString& screenshot, const QString& at, const QString& size,
                       const QString& view, ConsoleRequest& out);
};

/// Drives a MainWindow through one screenshot; ends with done(exit code, message).
class ScreenshotRunner : public QObject {
  Q_OBJECT

 public:
  ScreenshotRunner(MainWindow* window, ConsoleRequest request, QObject* parent = nullptr);
  /// The replay time the capture was taken at (after done(0, ...)).
  double capturedTime() const { return _captured; }

 public slots:
  void start();

 signals:
  /// 0: written (message says where and at what time); 1: the run or the capture failed;
  /// 2: bad input (unknown scenario).
  void done(int code, const QString& message);

 private:
  void capture(bool ok, const QString& message);

  MainWindow* _window;
  ConsoleRequest _request;
  double _captured = 0.0;
};

}  // namespace pb::ui
