// SPDX-License-Identifier: MIT
// palletballet: the operator console.
//
//   palletballet [--scenario SLUG] [--profile-speed V --profile-accel A]
//                [--screenshot OUT.png [--at failure|end|TIME] [--size WxH] [--screenshot-view
//                replay]]
//
// Without --screenshot it opens the console on SLUG (default stable-dairy-slab) and dispatches
// its suggested profile. With --screenshot it does the same, places the replay at the requested
// time, writes a PNG of the window (or of the replay view alone) and exits: 0 written, 2 bad
// arguments, 1 the run or the capture failed. Without a display it runs the CLI analysis of SLUG
// instead and says why.
#include <unistd.h>

#include <QApplication>
#include <QCommandLineParser>
#include <QTimer>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "ui/models/autosave.hpp"
#include "ui/window/console_screenshot.hpp"
#include "ui/window/main_window.hpp"

namespace {

constexpr const char* kDefaultScenario = "stable-dairy-slab";

bool hasDisplay() {
  const auto set = [](const char* name) {
    const char* v = std::getenv(name);
    return v != nullptr && *v != '\0';
  };
  return set("DISPLAY") || set("WAYLAND_DISPLAY") || set("QT_QPA_PLATFORM");
}

/// The value following `--scenario` (or its default), read before Qt starts.
std::string scenarioArg(int argc, char** argv) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--scenario") return argv[i + 1];
  }
  return kDefaultScenario;
}

bool wantsScreenshot(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--screenshot" || a.starts_with("--screenshot=")) return true;
  }
  return false;
}

/// No display: the console cannot open, so run the same analysis with the CLI next to us.
int runCliInstead(int argc, char** argv) {
  const std::string slug = scenarioArg(argc, argv);
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path cli =
      (ec ? std::filesystem::path(argv[0]).parent_path() : self.parent_path()) / "palletballet-cli";
  std::fprintf(stderr,
               "palletballet: no display ($DISPLAY and $WAYLAND_DISPLAY are unset), so the "
               "console cannot open; running the CLI analysis instead: %s analyze %s\n",
               cli.c_str(), slug.c_str());
  std::fflush(stderr);
  const std::string cliPath = cli.string();
  char* args[] = {const_cast<char*>(cliPath.c_str()), const_cast<char*>("analyze"),
                  const_cast<char*>(slug.c_str()), nullptr};
  execv(cliPath.c_str(), args);
  std::fprintf(stderr, "palletballet: cannot run %s: %s\n", cliPath.c_str(), std::strerror(errno));
  return 1;
}

bool wantsHelp(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h" || a == "-?" || a == "--help-all") return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  // The help needs no display: Qt's offscreen platform is enough to print it.
  if (!hasDisplay() && wantsHelp(argc, argv)) qputenv("QT_QPA_PLATFORM", "offscreen");
  if (!hasDisplay()) {
    if (wantsScreenshot(argc, argv)) {
      std::fprintf(stderr,
                   "palletballet: --screenshot needs a display for OpenGL and none is set "
                   "($DISPLAY, $WAYLAND_DISPLAY); run it under xvfb-run -a\n");
      return 1;
    }
    return runCliInstead(argc, argv);
  }
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("PalletBallet Console"));
  QApplication::setOrganizationName(QStringLiteral("PalletBallet"));

  QCommandLineParser parser;
  parser.setApplicationDescription(QStringLiteral(
      "The PalletBallet operator console. Without a display it runs the CLI analysis instead."));
  parser.addHelpOption();
  const QCommandLineOption scenario(QStringLiteral("scenario"),
                                    QStringLiteral("Curated scenario to open (default %1).")
                                        .arg(QString::fromLatin1(kDefaultScenario)),
                                    QStringLiteral("slug"), QString::fromLatin1(kDefaultScenario));
  const QCommandLineOption speed(QStringLiteral("profile-speed"),
                                 QStringLiteral("Target speed of the dispatched profile (m/s)."),
                                 QStringLiteral("V"));
  const QCommandLineOption accel(QStringLiteral("profile-accel"),
                                 QStringLiteral("Acceleration of the dispatched profile (m/s^2)."),
                                 QStringLiteral("A"));
  const QCommandLineOption screenshot(QStringLiteral("screenshot"),
                                      QStringLiteral("Write a PNG of the console and exit."),
                                      QStringLiteral("OUT.png"));
  const QCommandLineOption at(QStringLiteral("at"),
                              QStringLiteral("Replay time of the screenshot: failure, end or a "
                                             "time in s (default failure)."),
                              QStringLiteral("when"), QStringLiteral("failure"));
  const QCommandLineOption size(
      QStringLiteral("size"), QStringLiteral("Window size of the screenshot (default 1600x1000)."),
      QStringLiteral("WxH"), QStringLiteral("1600x1000"));
  const QCommandLineOption view(QStringLiteral("screenshot-view"),
                                QStringLiteral("window (default) or replay (the 3D view alone)."),
                                QStringLiteral("what"), QStringLiteral("window"));
  parser.addOptions({scenario, speed, accel, screenshot, at, size, view});
  parser.process(app);  // --help, unknown options: message and exit

  pb::ui::ConsoleRequest request;
  const QString error = pb::ui::ConsoleRequest::parse(
      parser.value(scenario), parser.isSet(speed) ? parser.value(speed) : QString(),
      parser.isSet(accel) ? parser.value(accel) : QString(), parser.value(screenshot),
      parser.value(at), parser.value(size), parser.value(view), request);
  if (!error.isEmpty()) {
    std::fprintf(stderr, "palletballet: %s\n", qPrintable(error));
    return 2;
  }

  pb::ui::MainWindow window;
  if (request.screenshotPath.isEmpty()) {
    window.show();
    QTimer::singleShot(0, &window, [&] {
      if (window.enableAutosave(pb::ui::Autosave::defaultDirectory())) return;  // lost work back
      if (!window.loadScenario(request.slug)) return;
      window.dispatch(request.profile, true, true);
    });
    return QApplication::exec();
  }
  pb::ui::ScreenshotRunner runner(&window, request);
  QObject::connect(&runner, &pb::ui::ScreenshotRunner::done, &app,
                   [](int code, const QString& message) {
                     std::fprintf(code == 0 ? stdout : stderr, "%s\n", qPrintable(message));
                     QCoreApplication::exit(code);
                   });
  QTimer::singleShot(0, &runner, &pb::ui::ScreenshotRunner::start);
  return QApplication::exec();
}
