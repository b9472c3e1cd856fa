// SPDX-License-Identifier: MIT
// The searchable SKU list: a filter line over the catalog (matches SKU, name and category, any
// case), each row "SKU-FM-001  Frozen Beef Cuts 10kg Box  10.5 kg  0.40×0.30×0.20 m".
//
// Wiring: CatalogList::skuChosen(const QString& sku) -> what places it (the stack builder panel).
#pragma once

#include <QAbstractListModel>
#include <QSortFilterProxyModel>
#include <QWidget>

#include "core/inputs/catalog.hpp"

class QLineEdit;
class QListView;

namespace pb::ui {

/// The catalog as a list model: DisplayRole is the row text, Qt::UserRole the SKU, ToolTipRole
/// the category, fragility and default environment.
class CatalogModel : public QAbstractListModel {
  Q_OBJECT

 public:
  explicit CatalogModel(const pb::Catalog& catalog, QObject* parent = nullptr);
  int rowCount(const QModelIndex& parent = {}) const override;
  QVariant data(const QModelIndex& index, int role) const override;
  const pb::SkuTemplate& sku(int row) const;

 private:
  const pb::Catalog& _catalog;
};

class CatalogList : public QWidget {
  Q_OBJECT

 public:
  explicit CatalogList(const pb::Catalog& catalog = pb::Catalog::builtin(),
                       QWidget* parent = nullptr);

  void setFilterText(const QString& text);
  /// Rows shown after filtering.
  int visibleCount() const;
  /// The SKU of visible row `row`.
  QString visibleSku(int row) const;
  /// The chosen SKU ("" if none); selects it in the list when visible.
  QString currentSku() const { return _current; }
  void setCurrentSku(const QString& sku);

 signals:
  void skuChosen(const QString& sku);

 private:
  CatalogModel _model;
  QSortFilterProxyModel _proxy;
  QLineEdit* _filter;
  QListView* _view;
  QString _current;
};

}  // namespace pb::ui
