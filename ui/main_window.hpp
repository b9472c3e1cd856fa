// SPDX-License-Identifier: MIT
// The console's main window. It only wires panels together; each panel is its own widget.
#pragma once

#include <QMainWindow>

namespace pb::ui {

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
};

}  // namespace pb::ui
