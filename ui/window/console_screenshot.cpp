// SPDX-License-Identifier: MIT
#include "ui/window/console_screenshot.hpp"

#include <QImage>
#include <QRegularExpression>
#include <QTimer>
#include <cmath>
#include <utility>

#include "core/analysis/analyzer.hpp"
#include "core/inputs/scenario.hpp"
#include "ui/models/replay_player.hpp"
#include "ui/replay/replay_panel.hpp"
#include "ui/replay/replay_view.hpp"
#include "ui/window/main_window.hpp"

namespace pb::ui {

namespace {

bool number(const QString& text, double& out) {
  bool ok = false;
  out = text.toDouble(&ok);
  return ok && std::isfinite(out);
}

}  // namespace

QString ConsoleRequest::parse(const QString& slug, const QString& speed, const QString& accel,
                              const QString& screenshot, const QString& at, const QString& size,
                              const QString& view, ConsoleRequest& out) {
  auto scenario = pb::load_scenario(slug.toStdString());
  if (!scenario) {
    QStringList slugs;
    for (const auto& s : pb::scenario_slugs()) slugs << QString::fromStdString(s);
    return QStringLiteral("--scenario: unknown scenario '%1'; use one of %2")
        .arg(slug, slugs.join(QStringLiteral(", ")));
  }
  out.slug = slug;
  out.profile = scenario->suggested_profile;
  if (!speed.isEmpty() && !number(speed, out.profile.target_speed_mps)) {
    return QStringLiteral("--profile-speed: '%1' is not a number; give m/s, e.g. 1.5").arg(speed);
  }
  if (!accel.isEmpty() && !number(accel, out.profile.accel_mps2)) {
    return QStringLiteral("--profile-accel: '%1' is not a number; give m/s^2, e.g. 2").arg(accel);
  }
  // The analysed range: the console's dials, its search and its map share it (MainWindow's
  // service runs the default options).
  const pb::SearchConfig range = pb::AnalyzerOptions{}.search;
  // Empty when `v` is in [lo, hi], else what to change, naming the option.
  auto outside = [](const char* option, double v, double lo, double hi, const char* unit) {
    if (v >= lo - 1e-9 && v <= hi + 1e-9) return QString();
    return QStringLiteral(
               "%1: %2 %3 is outside the analysed range; give %4 to %5 %3 (the dials, the "
               "search and the failure map share it)")
        .arg(QLatin1String(option))
        .arg(v)
        .arg(QLatin1String(unit))
        .arg(lo)
        .arg(hi);
  };
  for (const QString& why : {outside("--profile-speed", out.profile.target_speed_mps,
                                     range.speed_min_mps, range.speed_max_mps, "m/s"),
                             outside("--profile-accel", out.profile.accel_mps2,
                                     range.accel_min_mps2, range.accel_max_mps2, "m/s^2")}) {
    if (!why.isEmpty()) return why;
  }
  for (const pb::Diagnostic& d : pb::errors_of(pb::validate_profile(out.profile))) {
    const QString option = d.pointer == "/target_speed_mps" ? QStringLiteral("--profile-speed")
                           : d.pointer == "/accel_mps2"     ? QStringLiteral("--profile-accel")
                                                            : QStringLiteral("profile");
    return option + QStringLiteral(": ") + QString::fromStdString(d.message);
  }
  out.screenshotPath = screenshot;
  if (at == QStringLiteral("failure")) {
    out.at = At::failure;
  } else if (at == QStringLiteral("end")) {
    out.at = At::end;
  } else if (number(at, out.atTime) && out.atTime >= 0.0) {
    out.at = At::time;
  } else {
    return QStringLiteral("--at: '%1' is not failure, end or a time in s >= 0").arg(at);
  }
  static const QRegularExpression wxh(QStringLiteral("^(\\d{2,5})x(\\d{2,5})$"));
  const auto m = wxh.match(size);
  const int w = m.hasMatch() ? m.captured(1).toInt() : 0;
  const int h = m.hasMatch() ? m.captured(2).toInt() : 0;
  if (w < 320 || h < 240 || w > 8192 || h > 8192) {
    return QStringLiteral("--size: '%1' is not WxH between 320x240 and 8192x8192, e.g. 1600x1000")
        .arg(size);
  }
  out.size = QSize(w, h);
  if (view == QStringLiteral("replay")) {
    out.replayOnly = true;
  } else if (view == QStringLiteral("window")) {
    out.replayOnly = false;
  } else {
    return QStringLiteral("--screenshot-view: '%1' is not window or replay").arg(view);
  }
  return {};
}

ScreenshotRunner::ScreenshotRunner(MainWindow* window, ConsoleRequest request, QObject* parent)
    : QObject(parent), _window(window), _request(std::move(request)) {}

void ScreenshotRunner::start() {
  // The replay view alone is drawn at the requested size (the window grows around it); otherwise
  // the window is.
  if (_request.replayOnly && _window->replayPanel()->view() != nullptr) {
    _window->replayPanel()->view()->setFixedSize(_request.size);
  } else {
    _window->resize(_request.size);
  }
  _window->show();
  if (!_window->loadScenario(_request.slug)) {
    emit done(2, QStringLiteral("unknown scenario '%1'").arg(_request.slug));
    return;
  }
  connect(_window, &MainWindow::dispatchFinished, this, &ScreenshotRunner::capture,
          Qt::SingleShotConnection);
  // The replay view alone does not need the SafetyResult; the whole window shows it.
  _window->dispatch(_request.profile, !_request.replayOnly);
}

void ScreenshotRunner::capture(bool ok, const QString& message) {
  if (!ok) {
    emit done(1, QStringLiteral("the run failed: %1").arg(message));
    return;
  }
  ReplayPanel* panel = _window->replayPanel();
  ReplayPlayer* player = panel->player();
  player->pause();
  double t = player->endTime();
  QString note;
  switch (_request.at) {
    case ConsoleRequest::At::failure:
      if (player->failureTime()) {
        t = *player->failureTime();
      } else {
        note = QStringLiteral(" (nothing failed: the end of the replay)");
      }
      break;
    case ConsoleRequest::At::end:
      break;
    case ConsoleRequest::At::time:
      if (_request.atTime > player->endTime() + 1e-9) {
        emit done(2, QStringLiteral("--at: %1 s is after the replay's end (%2 s)")
                         .arg(_request.atTime)
                         .arg(player->endTime(), 0, 'f', 3));
        return;
      }
      t = _request.atTime;
      break;
  }
  player->setTime(t);
  _captured = player->time();
  if (_request.replayOnly && panel->view() == nullptr) {
    emit done(1, QStringLiteral("the replay view needs OpenGL: %1").arg(panel->glProblem()));
    return;
  }
  // Let the layout settle and the panels repaint before grabbing.
  QTimer::singleShot(100, this, [this, note] {
    ReplayPanel* shown = _window->replayPanel();
    const QImage image =
        _request.replayOnly ? shown->view()->grabFramebuffer() : _window->grab().toImage();
    if (!image.isNull() && image.deviceIndependentSize().toSize() != _request.size) {
      emit done(1, QStringLiteral("--size: the %1 could only be drawn at %2x%3, not %4x%5; is the "
                                  "screen smaller? (under xvfb-run, pass -s \"-screen 0 WxHx24\")")
                       .arg(_request.replayOnly ? QStringLiteral("replay view")
                                                : QStringLiteral("console"))
                       .arg(image.width())
                       .arg(image.height())
                       .arg(_request.size.width())
                       .arg(_request.size.height()));
      return;
    }
    if (image.isNull() || !image.save(_request.screenshotPath, "PNG")) {
      emit done(1, QStringLiteral("cannot write the PNG %1").arg(_request.screenshotPath));
      return;
    }
    emit done(0, QStringLiteral("wrote %1 (%2x%3), replay at t = %4 s%5")
                     .arg(_request.screenshotPath)
                     .arg(image.width())
                     .arg(image.height())
                     .arg(_captured, 0, 'f', 3)
                     .arg(note));
  });
}

}  // namespace pb::ui
