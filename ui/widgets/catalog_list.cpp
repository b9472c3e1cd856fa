// SPDX-License-Identifier: MIT
#include "ui/widgets/catalog_list.hpp"

#include <QLineEdit>
#include <QListView>
#include <QVBoxLayout>

#include "core/base/text.hpp"

namespace pb::ui {

namespace {

QString q(std::string_view s) {
  return QString::fromUtf8(s.data(), static_cast<qsizetype>(s.size()));
}

}  // namespace

CatalogModel::CatalogModel(const pb::Catalog& catalog, QObject* parent)
    : QAbstractListModel(parent), _catalog(catalog) {}

int CatalogModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : static_cast<int>(_catalog.all().size());
}

const pb::SkuTemplate& CatalogModel::sku(int row) const {
  return _catalog.all()[static_cast<std::size_t>(row)];
}

QVariant CatalogModel::data(const QModelIndex& index, int role) const {
  if (!index.isValid() || index.row() < 0 || index.row() >= rowCount()) return {};
  const pb::SkuTemplate& s = sku(index.row());
  switch (role) {
    case Qt::DisplayRole:
      return QStringLiteral("%1  %2  %3 kg  %4×%5×%6 m")
          .arg(q(s.sku), q(s.name), q(pb::fixed(s.weight_kg, 1)), q(pb::fixed(s.dims_m[0], 2)),
               q(pb::fixed(s.dims_m[1], 2)), q(pb::fixed(s.dims_m[2], 2)));
    case Qt::UserRole:
      return q(s.sku);
    case Qt::ToolTipRole:
      return tr("%1 · %2 · usually %3")
          .arg(q(s.category), q(pb::to_string(s.fragility)), q(pb::to_string(s.default_env)));
    default:
      return {};
  }
}

CatalogList::CatalogList(const pb::Catalog& catalog, QWidget* parent)
    : QWidget(parent), _model(catalog), _filter(new QLineEdit(this)), _view(new QListView(this)) {
  _proxy.setSourceModel(&_model);
  _proxy.setFilterCaseSensitivity(Qt::CaseInsensitive);
  // Search the row text and the category (tooltip) alike.
  _proxy.setFilterRole(Qt::DisplayRole);
  _filter->setPlaceholderText(tr("Search SKU, name or category"));
  _filter->setClearButtonEnabled(true);
  _filter->setToolTip(tr("Filter the catalogue by SKU, name or category"));
  _view->setModel(&_proxy);
  _view->setSelectionMode(QAbstractItemView::SingleSelection);
  _view->setEditTriggers(QAbstractItemView::NoEditTriggers);
  _view->setMinimumHeight(5 * _view->fontMetrics().height() + 8);  // five rows at least
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(_filter);
  layout->addWidget(_view);
  connect(_filter, &QLineEdit::textChanged, this, &CatalogList::setFilterText);
  connect(_view->selectionModel(), &QItemSelectionModel::currentChanged, this,
          [this](const QModelIndex& current) {
            if (!current.isValid()) return;
            const QString sku = current.data(Qt::UserRole).toString();
            if (sku == _current) return;
            _current = sku;
            emit skuChosen(sku);
          });
}

void CatalogList::setFilterText(const QString& text) {
  if (_filter->text() != text) _filter->setText(text);
  _proxy.setFilterFixedString(text);
}

int CatalogList::visibleCount() const {
  return _proxy.rowCount();
}

QString CatalogList::visibleSku(int row) const {
  return _proxy.index(row, 0).data(Qt::UserRole).toString();
}

void CatalogList::setCurrentSku(const QString& sku) {
  for (int row = 0; row < _proxy.rowCount(); ++row) {
    if (visibleSku(row) == sku) {
      _view->setCurrentIndex(_proxy.index(row, 0));
      return;
    }
  }
  if (sku != _current && _model.rowCount() > 0) {
    for (int row = 0; row < _model.rowCount(); ++row) {
      if (_model.index(row).data(Qt::UserRole).toString() == sku) {
        _current = sku;
        emit skuChosen(sku);
        return;
      }
    }
  }
}

}  // namespace pb::ui
