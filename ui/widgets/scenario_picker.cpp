// SPDX-License-Identifier: MIT
#include "ui/widgets/scenario_picker.hpp"

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>

#include "ui/models/pallet_document.hpp"

namespace pb::ui {

ScenarioPicker::ScenarioPicker(PalletDocument* document, QWidget* parent)
    : QWidget(parent),
      _document(document),
      _scenarios(pb::all_scenarios()),
      _combo(new QComboBox(this)),
      _description(new QLabel(this)),
      _load(new QPushButton(tr("Load scenario"), this)) {
  for (const pb::Scenario& s : _scenarios) {
    _combo->addItem(QStringLiteral("%1 — %2").arg(QString::fromStdString(s.name),
                                                  QString::fromStdString(s.tag)),
                    QString::fromStdString(s.slug));
    _combo->setItemData(_combo->count() - 1, QString::fromStdString(s.description),
                        Qt::ToolTipRole);
  }
  _description->setWordWrap(true);
  _combo->setToolTip(tr("A curated scenario: its description shows below"));
  _load->setToolTip(
      tr("Replace the pallet being edited with this scenario's (asks to save first)"));
  auto* row = new QHBoxLayout;
  row->addWidget(_combo, 1);
  row->addWidget(_load);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addLayout(row);
  layout->addWidget(_description);
  connect(_combo, &QComboBox::currentIndexChanged, this, &ScenarioPicker::describe);
  connect(_document, &PalletDocument::changed, this, &ScenarioPicker::describe);
  connect(_load, &QPushButton::clicked, this, &ScenarioPicker::loadCurrent);
  describe();
}

QString ScenarioPicker::description() const {
  return _description->text();
}

void ScenarioPicker::describe() {
  const int index = _combo->currentIndex();
  if (index < 0 || index >= count()) return _description->clear();
  const pb::Scenario& s = _scenarios[static_cast<std::size_t>(index)];
  const QString text = QString::fromStdString(s.description) + tr(" Expected: ") +
                       QString::fromStdString(s.expected_failure) + QStringLiteral(".");
  // The words are the selected scenario's: once the pallet being edited is something else (edited,
  // new, opened from a file), they say that they describe what Load would bring.
  _description->setText(_document->pallet() == s.pallet
                            ? text
                            : tr("Not the pallet being edited; Load brings it: ") + text);
}

int ScenarioPicker::currentIndex() const {
  return _combo->currentIndex();
}

void ScenarioPicker::setCurrentIndex(int index) {
  _combo->setCurrentIndex(index);
}

bool ScenarioPicker::loadSlug(const QString& slug) {
  const int index = _combo->findData(slug);
  if (index < 0) return false;
  _combo->setCurrentIndex(index);
  return loadCurrent();
}

bool ScenarioPicker::loadCurrent() {
  const int index = _combo->currentIndex();
  if (index < 0 || index >= count()) return false;
  if (_mayReplace && !_mayReplace()) return false;
  const pb::Scenario& s = _scenarios[static_cast<std::size_t>(index)];
  _document->loadScenario(s);
  emit scenarioLoaded(s);
  return true;
}

}  // namespace pb::ui
