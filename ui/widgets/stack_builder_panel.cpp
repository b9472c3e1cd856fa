// SPDX-License-Identifier: MIT
#include "ui/widgets/stack_builder_panel.hpp"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QScrollArea>
#include <QSpinBox>
#include <QVBoxLayout>

#include "core/base/enums.hpp"
#include "ui/models/pallet_document.hpp"
#include "ui/models/stack_builder_model.hpp"
#include "ui/widgets/catalog_list.hpp"
#include "ui/widgets/stack_builder_grid.hpp"

namespace pb::ui {

namespace {

template <class E>
QComboBox* enum_combo(QWidget* parent) {
  auto* combo = new QComboBox(parent);
  for (const auto& entry : pb::EnumTable<E>::names) {
    combo->addItem(QString::fromUtf8(entry.name.data(), static_cast<qsizetype>(entry.name.size())),
                   static_cast<int>(entry.value));
  }
  return combo;
}

template <class E>
void show_enum(QComboBox* combo, E value) {
  combo->setCurrentIndex(combo->findData(static_cast<int>(value)));
}

template <class E>
E combo_value(const QComboBox* combo) {
  return static_cast<E>(combo->currentData().toInt());
}

}  // namespace

StackBuilderPanel::StackBuilderPanel(PalletDocument* document, QWidget* parent)
    : QWidget(parent),
      _document(document),
      _grid(new StackBuilderGrid(document, this)),
      _catalog(new CatalogList(pb::Catalog::builtin(), this)),
      _height(new QSpinBox(this)),
      _pattern(new QComboBox(this)),
      _layers(new QSpinBox(this)),
      _applyPreset(new QPushButton(tr("Apply preset"), this)),
      _wrap(enum_combo<pb::WrapType>(this)),
      _env(enum_combo<pb::Environment>(this)),
      _type(enum_combo<pb::PalletType>(this)),
      _temp(new QDoubleSpinBox(this)),
      _since(new QDoubleSpinBox(this)),
      _summary(new QLabel(this)),
      _presetMessage(new QLabel(this)),
      _findings(new QListWidget(this)) {
  _height->setRange(1, 50);
  _height->setValue(4);
  _height->setToolTip(tr("Cartons in the stack a click places, or in the selected stack"));
  for (auto pattern :
       {pb::LayerPattern::column, pb::LayerPattern::brick, pb::LayerPattern::pinwheel}) {
    const auto name = pb::to_string(pattern);
    _pattern->addItem(QString::fromUtf8(name.data(), static_cast<qsizetype>(name.size())),
                      static_cast<int>(pattern));
  }
  _layers->setRange(1, 20);
  _layers->setValue(4);
  _temp->setRange(-40.0, 40.0);
  _temp->setDecimals(1);
  _temp->setSuffix(QStringLiteral(" °C"));
  _temp->setKeyboardTracking(false);
  _since->setRange(0.0, 100000.0);
  _since->setDecimals(0);
  _since->setSuffix(tr(" min"));
  _since->setKeyboardTracking(false);
  _summary->setWordWrap(true);
  _summary->setTextInteractionFlags(Qt::TextSelectableByMouse);
  _presetMessage->setWordWrap(true);
  _presetMessage->setStyleSheet(QStringLiteral("color: #b00000"));
  _findings->setWordWrap(true);
  _findings->setMinimumHeight(60);
  _pattern->setToolTip(tr("How the preset lays each layer: columns, a brick bond or a pinwheel"));
  _layers->setToolTip(tr("Layers of cartons the preset stacks"));
  _applyPreset->setToolTip(
      tr("Replace the load with the pattern and layers above, using the SKU selected in the list"));
  _type->setToolTip(tr("The pallet the load stands on (its size, weight and friction)"));
  _wrap->setToolTip(
      tr("How the load is held together: unwrapped cartons can slide and tip one by one"));
  _env->setToolTip(tr("Where the pallet has been: frozen, refrigerated or thawed (friction)"));
  _temp->setToolTip(tr("The pallet's temperature now (friction depends on it)"));
  _since->setToolTip(tr("Minutes since the pallet's temperature changed (a frost film melts)"));

  // Left: the deck. Right: what to place, presets, the pallet's properties.
  auto* place = new QGroupBox(tr("Place"), this);
  auto* placeLayout = new QVBoxLayout(place);
  placeLayout->addWidget(_catalog, 1);
  auto* heightRow = new QFormLayout;
  heightRow->addRow(tr("Height (cartons)"), _height);
  placeLayout->addLayout(heightRow);

  auto* preset = new QGroupBox(tr("Layer-pattern preset (replaces the load)"), this);
  auto* presetLayout = new QFormLayout(preset);
  presetLayout->addRow(tr("Pattern"), _pattern);
  presetLayout->addRow(tr("Layers"), _layers);
  presetLayout->addRow(_applyPreset);
  presetLayout->addRow(_presetMessage);

  auto* props = new QGroupBox(tr("Pallet"), this);
  auto* propsLayout = new QFormLayout(props);
  propsLayout->addRow(tr("Pallet type"), _type);
  propsLayout->addRow(tr("Wrap"), _wrap);
  propsLayout->addRow(tr("Environment"), _env);
  propsLayout->addRow(tr("Body temperature"), _temp);
  propsLayout->addRow(tr("Since the temperature changed"), _since);

  auto* side = new QVBoxLayout;
  side->addWidget(place, 1);
  side->addWidget(preset);
  side->addWidget(props);

  auto* left = new QVBoxLayout;
  left->addWidget(_grid, 3);
  left->addWidget(_summary);
  left->addWidget(_findings, 1);

  // Everything scrolls when the panel is smaller than its controls need (a small window).
  auto* content = new QWidget;
  _layout = new QBoxLayout(QBoxLayout::LeftToRight, content);
  _layout->setContentsMargins(0, 0, 0, 0);
  _layout->addLayout(left, 3);
  _layout->addLayout(side, 2);
  auto* scroll = new QScrollArea(this);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setWidgetResizable(true);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  scroll->setWidget(content);
  auto* outer = new QVBoxLayout(this);
  outer->setContentsMargins(4, 4, 4, 4);
  outer->addWidget(scroll);

  // Placement follows the catalog and the height spin; the spin resizes a selected stack.
  connect(_catalog, &CatalogList::skuChosen, this,
          [this](const QString& sku) { _grid->setPlacement(sku, _height->value()); });
  connect(_height, &QSpinBox::valueChanged, this, [this](int value) {
    _grid->setPlacement(_grid->placementSku(), value);
    if (_updating || _grid->selectedStack() < 0) return;
    _document->resizeStack(_grid->selectedStack(), value, PalletDocument::Edit::drag);
  });
  connect(_height, &QSpinBox::editingFinished, _document, &PalletDocument::endDrag);
  connect(_grid, &StackBuilderGrid::selectedStackChanged, this, &StackBuilderPanel::showSelection);
  connect(_applyPreset, &QPushButton::clicked, this, &StackBuilderPanel::applyPreset);

  connect(_wrap, &QComboBox::activated, this,
          [this] { _document->setWrap(combo_value<pb::WrapType>(_wrap)); });
  connect(_env, &QComboBox::activated, this,
          [this] { _document->setEnvironment(combo_value<pb::Environment>(_env)); });
  connect(_type, &QComboBox::activated, this,
          [this] { _document->setPalletType(combo_value<pb::PalletType>(_type)); });
  connect(_temp, &QDoubleSpinBox::valueChanged, this, [this](double value) {
    if (!_updating) _document->setBodyTemperature(value, PalletDocument::Edit::drag);
  });
  connect(_temp, &QDoubleSpinBox::editingFinished, _document, &PalletDocument::endDrag);
  connect(_since, &QDoubleSpinBox::valueChanged, this, [this](double minutes) {
    if (!_updating)
      _document->setSecondsSinceTempChange(minutes * 60.0, PalletDocument::Edit::drag);
  });
  connect(_since, &QDoubleSpinBox::editingFinished, _document, &PalletDocument::endDrag);

  // Selecting a finding selects the stack it names.
  connect(_findings, &QListWidget::currentRowChanged, this, [this](int row) {
    if (row < 0) return;
    const int stack = _findings->item(row)->data(Qt::UserRole).toInt();
    if (stack >= 0) _grid->setSelectedStack(stack);
  });

  connect(_document, &PalletDocument::changed, this, &StackBuilderPanel::showPallet);
  if (!pb::Catalog::builtin().all().empty()) {
    _catalog->setCurrentSku(QString::fromStdString(pb::Catalog::builtin().all()[0].sku));
  }
  showPallet(_document->pallet());
}

void StackBuilderPanel::showPallet(const pb::PalletConfig& pallet) {
  _updating = true;
  show_enum(_wrap, pallet.wrap);
  show_enum(_env, pallet.env);
  show_enum(_type, pallet.base_pallet_type);
  if (!_temp->hasFocus() || _temp->value() != pallet.body_temp_c) {
    _temp->setValue(pallet.body_temp_c);
  }
  _since->setValue(pallet.seconds_since_temp_change / 60.0);
  const auto stacks = stacks_of(pallet);
  _summary->setText(summary_line(pallet));
  _findings->clear();
  const auto& diagnostics = _document->diagnostics();
  for (const auto& d : diagnostics) {
    auto* item = new QListWidgetItem(describe_finding(d, stacks), _findings);
    item->setData(Qt::UserRole, stack_of_finding(d, stacks));
    item->setForeground(d.severity == pb::Severity::error ? QColor(0xb0, 0, 0)
                                                          : QColor(0x8a, 0x5a, 0));
  }
  if (diagnostics.empty()) {
    auto* item = new QListWidgetItem(
        pallet.items.empty() ? tr("Empty pallet: click a cell to place a stack, or apply a preset")
                             : tr("Valid: no findings"),
        _findings);
    item->setData(Qt::UserRole, -1);
    item->setForeground(QColor(0x10, 0x70, 0x10));
  }
  const int selected = _grid->selectedStack();
  if (selected >= 0 && selected < static_cast<int>(stacks.size())) {
    _height->setValue(stacks[static_cast<std::size_t>(selected)].height());
  }
  _updating = false;
}

void StackBuilderPanel::showSelection(int stack) {
  const auto stacks = stacks_of(_document->pallet());
  if (stack < 0 || stack >= static_cast<int>(stacks.size())) return;
  _updating = true;
  _height->setValue(stacks[static_cast<std::size_t>(stack)].height());
  _updating = false;
}

void StackBuilderPanel::resizeEvent(QResizeEvent* event) {
  // Side by side when there is room (a window), one above the other in a narrow dock.
  const bool wide = width() >= kSideBySideWidth;
  _layout->setDirection(wide ? QBoxLayout::LeftToRight : QBoxLayout::TopToBottom);
  // Under the deck the controls keep their size and the deck gives way (down to its minimum).
  _layout->setStretch(0, wide ? 3 : 1);
  _layout->setStretch(1, wide ? 2 : 0);
  _findings->setMaximumHeight(wide ? QWIDGETSIZE_MAX : 110);
  QWidget::resizeEvent(event);
}

QString StackBuilderPanel::summaryText() const {
  return _summary->text();
}

QStringList StackBuilderPanel::findingTexts() const {
  QStringList out;
  for (int row = 0; row < _findings->count(); ++row) out << _findings->item(row)->text();
  return out;
}

void StackBuilderPanel::applyPreset() {
  QStringList why;
  const auto pattern = static_cast<pb::LayerPattern>(_pattern->currentData().toInt());
  if (_document->applyPreset(pattern, _catalog->currentSku(), _layers->value(), &why)) {
    _presetMessage->clear();
    _grid->setSelectedStack(-1);
  } else {
    _presetMessage->setText(why.join(QLatin1Char('\n')));
  }
}

}  // namespace pb::ui
