// SPDX-License-Identifier: MIT
// The curated scenarios in a combo box (name, tag; the description as tooltip) with a Load button
// that opens the chosen scenario as the document (after the console asks to save unsaved work).
//
// Wiring: ScenarioPicker::scenarioLoaded(const pb::Scenario&) -> the dial panel (its suggested
// profile) and anything that shows the scenario's expected failure.
#pragma once

#include <QWidget>
#include <functional>
#include <vector>

#include "core/inputs/scenario.hpp"

class QComboBox;
class QLabel;
class QPushButton;

namespace pb::ui {

class PalletDocument;

class ScenarioPicker : public QWidget {
  Q_OBJECT

 public:
  explicit ScenarioPicker(PalletDocument* document, QWidget* parent = nullptr);

  int count() const { return static_cast<int>(_scenarios.size()); }
  const pb::Scenario& scenario(int index) const { return _scenarios.at(index); }
  int currentIndex() const;
  void setCurrentIndex(int index);
  /// Asked before a scenario replaces the document; false keeps the document (e.g. the user
  /// cancelled saving unsaved changes). Unset: always replace.
  void setMayReplace(std::function<bool()> mayReplace) { _mayReplace = std::move(mayReplace); }
  /// The words under the box: the selected scenario's description and expected failure, marked as
  /// not the pallet being edited once it is not.
  QString description() const;

 public slots:
  /// Opens the scenario with this slug as the document (false if unknown or not replaced).
  bool loadSlug(const QString& slug);
  /// Opens the selected scenario as the document (false if not replaced).
  bool loadCurrent();

 signals:
  void scenarioLoaded(const pb::Scenario& scenario);

 private:
  void describe();

  PalletDocument* _document;
  std::function<bool()> _mayReplace;
  std::vector<pb::Scenario> _scenarios;
  QComboBox* _combo;
  QLabel* _description;
  QPushButton* _load;
};

}  // namespace pb::ui
