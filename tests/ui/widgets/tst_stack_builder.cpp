// SPDX-License-Identifier: MIT
// The stack builder: its headless model (stacks, grid, findings naming stacks), the deck grid
// driven by the mouse and the keyboard, the panel's controls (presets, properties, a spin drag as
// one undo step), the catalog search, the scenario picker, and the panel's screenshot.
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QMouseEvent>
#include <QPushButton>
#include <QSignalSpy>
#include <QSpinBox>
#include <QTest>

#include "core/contract/pallet_metrics.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/scenario.hpp"
#include "core/inputs/stack_builder.hpp"
#include "core/inputs/validation.hpp"
#include "ui/models/pallet_document.hpp"
#include "ui/models/stack_builder_model.hpp"
#include "ui/widgets/catalog_list.hpp"
#include "ui/widgets/scenario_picker.hpp"
#include "ui/widgets/sku_color.hpp"
#include "ui/widgets/stack_builder_grid.hpp"
#include "ui/widgets/stack_builder_panel.hpp"

using pb::ui::PalletDocument;
using pb::ui::StackBuilderGrid;
using pb::ui::StackBuilderPanel;

namespace {

const QString kSku = QStringLiteral("SKU-FM-001");  // 0.40 x 0.30 x 0.20 m: a 3 x 2 grid on EUR

void send_mouse(QWidget* w, QEvent::Type type, QPoint at, Qt::MouseButtons buttons) {
  const QPointF local(at);
  QMouseEvent event(type, local, w->mapToGlobal(local), Qt::LeftButton, buttons, Qt::NoModifier);
  QCoreApplication::sendEvent(w, &event);
}

// A pixel well inside the footprint of stack `s` but away from its centred label.
QPoint inside_stack(const StackBuilderGrid& grid, const pb::PalletConfig& p,
                    const pb::ui::StackView& s) {
  const pb::Item& top = p.items[s.items.back()];
  return grid.deckPixel({s.centre[0] - 0.35 * top.dims_m[0], s.centre[1] + 0.35 * top.dims_m[1]})
      .toPoint();
}

}  // namespace

class TestStackBuilder : public QObject {
  Q_OBJECT

 private slots:
  // The model sees the stacks build_from_stacks made, in order, with their cells' centres.
  void stacksOfABuiltPallet() {
    const std::vector<pb::StackSpec> specs{
        {"SKU-FM-001", 0, 0, 3}, {"SKU-FM-001", 1, 1, 5}, {"SKU-FM-002", 0, 1, 2}};
    auto built = pb::build_from_stacks(specs, {}, pb::Catalog::builtin());
    QVERIFY(built);
    const auto stacks = pb::ui::stacks_of(*built);
    QCOMPARE(stacks.size(), std::size_t{3});
    const pb::GridShape grid = pb::ui::builder_grid(*built);
    QCOMPARE(grid, pb::grid_for(specs, built->base_dims_m, pb::Catalog::builtin()));
    for (std::size_t i = 0; i < specs.size(); ++i) {
      QCOMPARE(stacks[i].height(), specs[i].height);
      QCOMPARE(stacks[i].sku, specs[i].sku);
      QVERIFY(!stacks[i].mixed);
      const pb::Vec2 c = pb::ui::cell_centre(*built, grid, specs[i].row, specs[i].col);
      QVERIFY(qAbs(stacks[i].centre[0] - c[0]) < 1e-12 && qAbs(stacks[i].centre[1] - c[1]) < 1e-12);
      const auto cell = pb::ui::cell_at(*built, grid, c);
      QVERIFY(cell.has_value());
      QCOMPARE(cell->row, specs[i].row);
      QCOMPARE(cell->col, specs[i].col);
      QCOMPARE(pb::ui::stack_at(*built, stacks, c), static_cast<int>(i));
      // Bottom to top.
      for (int k = 1; k < stacks[i].height(); ++k) {
        QVERIFY(built->items[stacks[i].items[k]].position[2] >
                built->items[stacks[i].items[k - 1]].position[2]);
      }
    }
    QVERIFY(!pb::ui::cell_at(*built, grid, {0.61, 0.0}).has_value());
    QCOMPARE(pb::ui::stack_at(*built, stacks, {0.55, 0.35}), -1);
    // Every item in exactly one stack.
    int total = 0;
    for (const auto& s : stacks) total += s.height();
    QCOMPARE(total, static_cast<int>(built->items.size()));
    QCOMPARE(pb::ui::stack_label(stacks, 1), QStringLiteral("Stack 2 (SKU-FM-001, 5 high)"));
  }

  // A finding about an item names its stack and carton; others keep their pointer.
  void findingsNameTheStack() {
    PalletDocument doc;
    QVERIFY(doc.addStack({-0.4, -0.2}, kSku, 2));
    QVERIFY(doc.addStack({0.4, 0.2}, kSku, 12));  // 0.15 + 12 * 0.2 = 2.55 m: over the cap
    QVERIFY(!doc.isValid());
    const auto stacks = pb::ui::stacks_of(doc.pallet());
    bool named = false;
    for (const auto& d : pb::errors_of(doc.diagnostics())) {
      const QString text = pb::ui::describe_finding(d, stacks);
      if (pb::ui::stack_of_finding(d, stacks) == 1) {
        QVERIFY2(text.startsWith(u"Stack 2 (SKU-FM-001, 12 high), carton "), qPrintable(text));
        named = true;
      }
    }
    QVERIFY(named);
    const pb::Diagnostic global{"/wrap", "choose a wrap", pb::Severity::warning};
    QCOMPARE(pb::ui::describe_finding(global, stacks),
             QStringLiteral("Warning: /wrap: choose a wrap"));
  }

  void summaryQuotesTheMetrics() {
    PalletDocument doc;
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 3));
    const QString s = pb::ui::summary_line(doc.pallet());
    // 25 kg tare + 3 x 10.5 kg; top at 0.15 + 0.6 m.
    QVERIFY2(s.startsWith(u"56.5 kg · 3 cartons"), qPrintable(s));
    QVERIFY2(s.contains(u"height 0.75 m"), qPrintable(s));
    QVERIFY2(s.contains(u"overhang 0.00 m"), qPrintable(s));
    QVERIFY2(s.contains(u"least support 100 %"), qPrintable(s));
  }

  // Clicking an empty cell places a stack of the chosen SKU and height at that cell's centre;
  // clicking it again selects it; Delete removes it.
  void clickPlacesAStackWhereClicked() {
    PalletDocument doc;
    StackBuilderPanel panel(&doc);
    panel.resize(1000, 640);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    panel.catalog()->setCurrentSku(kSku);
    panel.heightSpin()->setValue(3);
    StackBuilderGrid* grid = panel.grid();
    QCOMPARE(grid->placementSku(), kSku);
    QCOMPARE(grid->placementHeight(), 3);
    QCOMPARE(grid->grid(), (pb::GridShape{2, 3}));

    QTest::mouseClick(grid, Qt::LeftButton, Qt::NoModifier, grid->cellCentrePixel(1, 2));
    QCOMPARE(doc.pallet().items.size(), std::size_t{3});
    const pb::Vec2 c = pb::ui::cell_centre(doc.pallet(), grid->grid(), 1, 2);
    for (const pb::Item& item : doc.pallet().items) {
      QCOMPARE(item.sku, kSku.toStdString());
      QVERIFY(qAbs(item.position[0] - c[0]) < 1e-12 && qAbs(item.position[1] - c[1]) < 1e-12);
    }
    QCOMPARE(c[0], 0.4);  // col 2 of 3 on 1.2 m, +X
    QCOMPARE(c[1], 0.2);  // row 1 of 2 on 0.8 m, +Y
    QCOMPARE(grid->selectedStack(), 0);
    QVERIFY(doc.isValid());

    // Another cell, a taller stack.
    panel.heightSpin()->setValue(5);  // resizes the selected stack: one step
    QCOMPARE(pb::ui::stacks_of(doc.pallet())[0].height(), 5);
    grid->setSelectedStack(-1);
    QTest::mouseClick(grid, Qt::LeftButton, Qt::NoModifier, grid->cellCentrePixel(0, 0));
    auto stacks = pb::ui::stacks_of(doc.pallet());
    QCOMPARE(stacks.size(), std::size_t{2});
    QCOMPARE(stacks[1].height(), 5);
    QCOMPARE(stacks[1].centre, pb::ui::cell_centre(doc.pallet(), grid->grid(), 0, 0));

    // A click on a stack selects it, adds nothing.
    QTest::mouseClick(grid, Qt::LeftButton, Qt::NoModifier, grid->cellCentrePixel(1, 2));
    QCOMPARE(grid->selectedStack(), 0);
    QCOMPARE(pb::ui::stacks_of(doc.pallet()).size(), std::size_t{2});

    // Delete key removes the selected stack; undo brings it back.
    QTest::keyClick(grid, Qt::Key_Delete);
    stacks = pb::ui::stacks_of(doc.pallet());
    QCOMPARE(stacks.size(), std::size_t{1});
    QCOMPARE(stacks[0].centre, pb::ui::cell_centre(doc.pallet(), grid->grid(), 0, 0));
    QCOMPARE(grid->selectedStack(), -1);
    doc.undoStack()->undo();
    QCOMPARE(pb::ui::stacks_of(doc.pallet()).size(), std::size_t{2});
    // add, resize, add, delete: four steps.
    QCOMPARE(doc.undoStack()->count(), 4);
  }

  // Dragging a stack across cells moves it to the cell it is released on, as one undo step;
  // it never lands on another stack.
  void dragMovesAStackInOneStep() {
    PalletDocument doc;
    StackBuilderPanel panel(&doc);
    panel.resize(1000, 640);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    panel.catalog()->setCurrentSku(kSku);
    panel.heightSpin()->setValue(2);
    StackBuilderGrid* grid = panel.grid();
    QTest::mouseClick(grid, Qt::LeftButton, Qt::NoModifier, grid->cellCentrePixel(0, 0));
    grid->setSelectedStack(-1);
    QTest::mouseClick(grid, Qt::LeftButton, Qt::NoModifier, grid->cellCentrePixel(1, 1));
    const int before = doc.undoStack()->count();

    send_mouse(grid, QEvent::MouseButtonPress, grid->cellCentrePixel(0, 0), Qt::LeftButton);
    send_mouse(grid, QEvent::MouseMove, grid->cellCentrePixel(0, 1), Qt::LeftButton);
    send_mouse(grid, QEvent::MouseMove, grid->cellCentrePixel(1, 1), Qt::LeftButton);  // occupied
    send_mouse(grid, QEvent::MouseMove, grid->cellCentrePixel(0, 2), Qt::LeftButton);
    send_mouse(grid, QEvent::MouseButtonRelease, grid->cellCentrePixel(0, 2), Qt::NoButton);

    QCOMPARE(doc.undoStack()->count(), before + 1);
    const auto stacks = pb::ui::stacks_of(doc.pallet());
    QCOMPARE(stacks[0].centre, pb::ui::cell_centre(doc.pallet(), grid->grid(), 0, 2));
    QCOMPARE(stacks[1].centre, pb::ui::cell_centre(doc.pallet(), grid->grid(), 1, 1));
    QVERIFY(doc.isValid());
    doc.undoStack()->undo();
    QCOMPARE(pb::ui::stacks_of(doc.pallet())[0].centre,
             pb::ui::cell_centre(doc.pallet(), grid->grid(), 0, 0));
  }

  // Presets from the panel: valid pallets of the chosen pattern, SKU and layer count.
  void presetsProduceValidPallets_data() {
    QTest::addColumn<int>("pattern");
    QTest::addColumn<QString>("sku");
    QTest::addColumn<int>("layers");
    for (const char* sku : {"SKU-FM-001", "SKU-FM-002", "SKU-FS-001"}) {
      QTest::addRow("column %s", sku)
          << int(pb::LayerPattern::column) << QString::fromLatin1(sku) << 4;
      QTest::addRow("brick %s", sku)
          << int(pb::LayerPattern::brick) << QString::fromLatin1(sku) << 5;
      QTest::addRow("pinwheel %s", sku)
          << int(pb::LayerPattern::pinwheel) << QString::fromLatin1(sku) << 3;
    }
  }
  void presetsProduceValidPallets() {
    QFETCH(int, pattern);
    QFETCH(QString, sku);
    QFETCH(int, layers);
    PalletDocument doc;
    QVERIFY(doc.setWrap(pb::WrapType::shrink));
    StackBuilderPanel panel(&doc);
    panel.catalog()->setCurrentSku(sku);
    panel.patternCombo()->setCurrentIndex(panel.patternCombo()->findData(pattern));
    panel.layersSpin()->setValue(layers);
    panel.presetButton()->click();
    const pb::PalletConfig& p = doc.pallet();
    QVERIFY2(!p.items.empty(), qPrintable(panel.findingTexts().join(u'\n')));
    QVERIFY2(!pb::has_errors(pb::validate(p)), qPrintable(panel.findingTexts().join(u'\n')));
    QCOMPARE(p.wrap, pb::WrapType::shrink);  // the pallet's other fields stay
    const std::size_t perLayer = p.items.size() / layers;
    QCOMPARE(p.items.size(), perLayer * layers);
    QVERIFY(perLayer >= 4);  // a full layer of cartons of 0.2 m^2 or less on a 0.96 m^2 deck
    for (const pb::Item& item : p.items) QCOMPARE(item.sku, sku.toStdString());
    const double h = pb::Catalog::builtin().find(sku.toStdString())->dims_m[2];
    QVERIFY(qAbs(pb::stack_height_m(p) - (p.base_dims_m[2] + layers * h)) < 1e-6);
    if (pattern == int(pb::LayerPattern::pinwheel)) {
      QCOMPARE(p.items[0].orientation_deg, 0.0);
      QCOMPARE(std::abs(p.items[perLayer].orientation_deg), 90.0);
    }
    QCOMPARE(doc.undoStack()->count(), 2);
    QVERIFY(panel.findingTexts().join(u' ').contains(u"Valid") ||
            !pb::has_errors(doc.diagnostics()));
  }

  // The pallet's properties edit the document; a spin box drag is one undo step.
  void propertiesEditTheDocument() {
    PalletDocument doc;
    StackBuilderPanel panel(&doc);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    panel.wrapCombo()->setCurrentIndex(panel.wrapCombo()->findData(int(pb::WrapType::banded)));
    emit panel.wrapCombo()->activated(panel.wrapCombo()->currentIndex());
    QCOMPARE(doc.pallet().wrap, pb::WrapType::banded);
    panel.environmentCombo()->setCurrentIndex(
        panel.environmentCombo()->findData(int(pb::Environment::frozen)));
    emit panel.environmentCombo()->activated(panel.environmentCombo()->currentIndex());
    QCOMPARE(doc.pallet().env, pb::Environment::frozen);
    panel.palletTypeCombo()->setCurrentIndex(
        panel.palletTypeCombo()->findData(int(pb::PalletType::chep)));
    emit panel.palletTypeCombo()->activated(panel.palletTypeCombo()->currentIndex());
    QCOMPARE(doc.pallet().base_pallet_type, pb::PalletType::chep);
    const int steps = doc.undoStack()->count();
    QCOMPARE(steps, 3);

    // Holding the arrow: many values, one step once editing finishes.
    QDoubleSpinBox* temp = panel.temperatureSpin();
    temp->setFocus();
    for (int i = 0; i < 6; ++i) temp->stepDown();
    QCOMPARE(doc.pallet().body_temp_c, 2.0 - 6 * 1.0);
    emit temp->editingFinished();
    QCOMPARE(doc.undoStack()->count(), steps + 1);
    temp->stepDown();
    QCOMPARE(doc.undoStack()->count(), steps + 2);
    doc.undoStack()->undo();
    doc.undoStack()->undo();
    QCOMPARE(doc.pallet().body_temp_c, 2.0);
    QCOMPARE(temp->value(), 2.0);  // the panel shows what the document holds

    panel.minutesSinceChangeSpin()->setValue(15.0);
    QCOMPARE(doc.pallet().seconds_since_temp_change, 900.0);
    doc.undoStack()->undo();
    QCOMPARE(panel.minutesSinceChangeSpin()->value(), 60.0);
  }

  void catalogSearchFilters() {
    pb::ui::CatalogList list;
    const int all = list.visibleCount();
    QCOMPARE(all, static_cast<int>(pb::Catalog::builtin().all().size()));
    list.setFilterText(QStringLiteral("salmon"));
    int expected = 0;
    for (const auto& s : pb::Catalog::builtin().all()) {
      if (QString::fromStdString(s.name).contains(u"salmon", Qt::CaseInsensitive)) ++expected;
    }
    QVERIFY(expected >= 1);
    QCOMPARE(list.visibleCount(), expected);
    for (int row = 0; row < list.visibleCount(); ++row) {
      const auto* s = pb::Catalog::builtin().find(list.visibleSku(row).toStdString());
      QVERIFY(s != nullptr);
      QVERIFY(QString::fromStdString(s->name).contains(u"salmon", Qt::CaseInsensitive));
    }
    QSignalSpy chosen(&list, &pb::ui::CatalogList::skuChosen);
    list.setCurrentSku(list.visibleSku(0));
    QCOMPARE(chosen.count(), 1);
    QCOMPARE(list.currentSku(), list.visibleSku(0));
    list.setFilterText(QStringLiteral("sku-fm"));
    QVERIFY(list.visibleCount() >= 3);
    list.setFilterText(QString());
    QCOMPARE(list.visibleCount(), all);
  }

  // The picker loads a curated scenario as one undo step and says which.
  void scenarioPickerOpensAScenario() {
    PalletDocument doc;
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 1));
    pb::ui::ScenarioPicker picker(&doc);
    QCOMPARE(picker.count(), static_cast<int>(pb::scenario_slugs().size()));
    QSignalSpy loaded(&picker, &pb::ui::ScenarioPicker::scenarioLoaded);
    QVERIFY(picker.loadSlug(QStringLiteral("tall-unwrapped-tower")));
    QVERIFY(!picker.loadSlug(QStringLiteral("no-such-scenario")));
    QCOMPARE(loaded.count(), 1);
    const auto tower = pb::load_scenario("tall-unwrapped-tower");
    QCOMPARE(doc.pallet(), tower->pallet);
    QVERIFY(!doc.isModified());  // opened as a document of its own
    // When replacing the document is refused (the user cancelled saving), nothing changes.
    QVERIFY(doc.addStack({0.3, 0.0}, kSku, 1));
    const pb::PalletConfig edited = doc.pallet();
    picker.setMayReplace([] { return false; });
    QVERIFY(!picker.loadSlug(QStringLiteral("top-heavy-surprise")));
    QCOMPARE(doc.pallet(), edited);
    QCOMPARE(loaded.count(), 1);
  }

  // The words under the box describe the pallet being edited only while it is the scenario's.
  void scenarioWordsNeverDescribeAnotherPallet() {
    PalletDocument doc;
    pb::ui::ScenarioPicker picker(&doc);
    const QString marked = QStringLiteral("Not the pallet being edited");
    QVERIFY(picker.description().startsWith(marked));  // a new, empty document
    QVERIFY(picker.loadSlug(QStringLiteral("tall-unwrapped-tower")));
    QVERIFY(!picker.description().startsWith(marked));
    QVERIFY(picker.description().contains(QStringLiteral("Expected: top item slide")));
    QVERIFY(doc.addStack({0.3, 0.0}, kSku, 1));  // edited
    QVERIFY(picker.description().startsWith(marked));
    doc.undoStack()->undo();  // the scenario's pallet again
    QVERIFY(!picker.description().startsWith(marked));
    picker.setCurrentIndex(0);  // another scenario selected, not loaded
    QVERIFY(picker.description().startsWith(marked));
    doc.newDocument();
    QVERIFY(picker.description().startsWith(marked));
  }

  // In a narrow dock the controls go under the deck; in a window beside it.
  void narrowPanelStacksVertically() {
    PalletDocument doc;
    pb::ui::ScenarioPicker picker(&doc);
    QVERIFY(picker.loadSlug(QStringLiteral("frozen-meat-sprint")));
    StackBuilderPanel panel(&doc);
    panel.resize(380, 980);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    QTest::qWait(20);
    const QRect grid = panel.grid()->geometry();
    const QRect catalog(panel.catalog()->mapTo(&panel, QPoint(0, 0)), panel.catalog()->size());
    QVERIFY2(grid.bottom() < catalog.top(), "the catalog is under the deck");
    QVERIFY(grid.width() > 300);
    QVERIFY(panel.grab().toImage().save(
        QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_stack_builder_narrow.png")));
    panel.resize(1000, 640);
    QTest::qWait(20);
    const QRect wideGrid = panel.grid()->geometry();
    const QRect wideCatalog(panel.catalog()->mapTo(&panel, QPoint(0, 0)), panel.catalog()->size());
    QVERIFY2(wideGrid.right() < wideCatalog.left(), "the catalog is beside the deck");
  }

  // A carton whose centre of mass is beyond the end of the one under it: the findings say it
  // cannot stand (naming its stack and the shift), the grid outlines it red, before any dispatch.
  void anItemThatCannotStandIsRedWithItsSentence() {
    PalletDocument doc;
    StackBuilderPanel panel(&doc);
    panel.resize(1000, 640);
    pb::PalletConfig config = doc.pallet();
    const pb::SkuTemplate* sku = pb::Catalog::builtin().find(kSku.toStdString());
    QVERIFY(sku != nullptr);
    pb::Item bottom = pb::make_item(*sku, {0.0, 0.0, config.base_dims_m[2]}, 0.0);
    pb::Item top = pb::make_item(*sku, {0.7 * sku->dims_m[0], 0.0, bottom.top_z()}, 0.0);
    config.items = {bottom, top};
    QVERIFY(doc.replacePallet(config, QStringLiteral("overhanging carton")));
    QVERIFY(!doc.isValid());
    const QString texts = panel.findingTexts().join(u'\n');
    QVERIFY2(texts.contains(QStringLiteral("cannot stand: its centre of mass is")),
             qPrintable(texts));
    QVERIFY2(texts.contains(QStringLiteral("towards -x to stand it over its support")),
             qPrintable(texts));
    const auto stacks = pb::ui::stacks_of(doc.pallet());
    bool named = false;
    for (const auto& d : pb::errors_of(doc.diagnostics())) {
      if (pb::ui::stack_of_finding(d, stacks) >= 0) named = true;
    }
    QVERIFY(named);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    StackBuilderGrid* grid = panel.grid();
    grid->setSelectedStack(-1);
    const QImage image = grid->grab().toImage();
    QVERIFY(panel.grab().toImage().save(
        QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_stack_builder_cannot_stand.png")));
    // The middle of the overhanging carton's front (+X) edge: the red outline.
    const QPoint edge = grid->deckPixel({top.position[0] + top.dims_m[0] / 2.0, 0.0}).toPoint();
    QCOMPARE(image.pixelColor(edge).rgb(), QColor(0xd0, 0x10, 0x10).rgb());
  }

  // The panel with a scenario loaded, one stack selected: the artifact, and its pixels.
  void panelScreenshot() {
    PalletDocument doc;
    StackBuilderPanel panel(&doc);
    panel.resize(1000, 640);
    pb::ui::ScenarioPicker picker(&doc);
    QVERIFY(picker.loadSlug(QStringLiteral("asymmetric-load")));
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    StackBuilderGrid* grid = panel.grid();
    const auto stacks = pb::ui::stacks_of(doc.pallet());
    QVERIFY(!stacks.empty());
    grid->setSelectedStack(-1);
    const QImage image = panel.grab().toImage();
    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    const QString path = QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_stack_builder.png");
    QVERIFY(image.save(path));
    qInfo("screenshot: %s", qPrintable(path));

    // Every stack shows its top carton's SKU colour inside its footprint.
    const QImage gridImage = grid->grab().toImage();
    for (const auto& s : stacks) {
      const QPoint at = inside_stack(*grid, doc.pallet(), s);
      const std::string& sku = doc.pallet().items[s.items.back()].sku;
      QCOMPARE(gridImage.pixelColor(at).rgb(), pb::ui::skuColor(sku).rgb());
    }
    // The empty cells of the deck show the deck.
    int emptyCells = 0;
    for (int r = 0; r < grid->grid().rows; ++r) {
      for (int c = 0; c < grid->grid().cols; ++c) {
        const pb::Vec2 centre = pb::ui::cell_centre(doc.pallet(), grid->grid(), r, c);
        if (pb::ui::stack_at(doc.pallet(), stacks, centre) >= 0) continue;
        ++emptyCells;
        QCOMPARE(gridImage.pixelColor(grid->cellCentrePixel(r, c) + QPoint(3, 3)).rgb(),
                 StackBuilderGrid::deckColour(doc.pallet().base_pallet_type).rgb());
      }
    }
    qInfo("%d stacks, %d empty cells", int(stacks.size()), emptyCells);
    QCOMPARE(panel.summaryText(), pb::ui::summary_line(doc.pallet()));
    QVERIFY(!panel.findingTexts().isEmpty());

    // A third stack too tall for the height cap: the findings name it, the grid outlines it red.
    QVERIFY(doc.addStack({0.0, 0.0}, kSku, 12));  // between the two stacks, 2.55 m high
    const auto texts = panel.findingTexts();
    QVERIFY2(texts.filter(QStringLiteral("Stack 3 (SKU-FM-001, 12 high), carton ")).size() >= 1,
             qPrintable(texts.join(u'\n')));
    const QImage invalid = panel.grab().toImage();
    QVERIFY(invalid.save(QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_stack_builder_invalid.png")));
    const QImage invalidGrid = grid->grab().toImage();
    const auto all = pb::ui::stacks_of(doc.pallet());
    const pb::Item& top = doc.pallet().items[all[2].items.back()];
    // The middle of the stack's front (+X) edge: the red outline.
    const QPoint edge = grid->deckPixel({top.dims_m[0] / 2.0, 0.0}).toPoint();
    QCOMPARE(invalidGrid.pixelColor(edge).rgb(), QColor(0xd0, 0x10, 0x10).rgb());
  }
};

QTEST_MAIN(TestStackBuilder)
#include "tst_stack_builder.moc"
