// SPDX-License-Identifier: MIT
#include "ui/main_window.hpp"

#include <QLabel>
#include <QStatusBar>

#include "core/catalog.hpp"
#include "core/scenario.hpp"

namespace pb::ui {

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  setWindowTitle(QStringLiteral("PalletBallet Console"));
  // The panels (stack builder, friction chart, dials, results, replay) arrive with the console
  // issue; until then the window states what the core has loaded.
  auto* label = new QLabel(this);
  label->setAlignment(Qt::AlignCenter);
  label->setText(
      QStringLiteral("PalletBallet Console\n%1 SKUs in the catalog, %2 curated scenarios")
          .arg(pb::Catalog::builtin().all().size())
          .arg(pb::scenario_slugs().size()));
  setCentralWidget(label);
  statusBar()->showMessage(QStringLiteral("Ready"));
  resize(1280, 800);
}

}  // namespace pb::ui
