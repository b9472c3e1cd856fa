// SPDX-License-Identifier: MIT
// palletballet: the operator console.
#include <QApplication>

#include "ui/main_window.hpp"

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("PalletBallet Console"));
  QApplication::setOrganizationName(QStringLiteral("PalletBallet"));
  pb::ui::MainWindow window;
  window.show();
  return QApplication::exec();
}
