// SPDX-License-Identifier: MIT
#include "ui/window/main_window.hpp"

#include <QCloseEvent>
#include <QDockWidget>
#include <QFileDialog>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QScrollArea>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>
#include <algorithm>

#include "core/inputs/scenario.hpp"
#include "core/physics/detectors.hpp"
#include "ui/models/autosave.hpp"
#include "ui/models/pallet_document.hpp"
#include "ui/models/recent_files.hpp"
#include "ui/models/replay_player.hpp"
#include "ui/models/stack_builder_model.hpp"
#include "ui/replay/replay_panel.hpp"
#include "ui/widgets/dial_panel.hpp"
#include "ui/widgets/failure_map_view.hpp"
#include "ui/widgets/file_actions.hpp"
#include "ui/widgets/friction_chart.hpp"
#include "ui/widgets/results_panel.hpp"
#include "ui/widgets/scenario_picker.hpp"
#include "ui/widgets/stack_builder_panel.hpp"
#include "ui/widgets/trace_plots.hpp"

namespace pb::ui {

namespace {

QDockWidget* dock(QMainWindow* window, const QString& title, const QString& name, QWidget* content,
                  Qt::DockWidgetArea area) {
  auto* d = new QDockWidget(title, window);
  d->setObjectName(name);
  // In a scroll area, so that a panel's own minimum size never forces the window wider or taller
  // than the screen (or a screenshot's --size): on a small screen the panel scrolls instead.
  auto* scroll = new QScrollArea(d);
  scroll->setWidget(content);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  d->setWidget(scroll);
  d->setFeatures(QDockWidget::DockWidgetMovable | QDockWidget::DockWidgetFloatable |
                 QDockWidget::DockWidgetClosable);
  window->addDockWidget(area, d);
  return d;
}

}  // namespace

MainWindow::MainWindow(QWidget* parent)
    : QMainWindow(parent),
      _document(new PalletDocument(this)),
      _recent(new RecentFiles(this)),
      _files(new FileActions(_document, _recent, this, this)),
      _service(new AnalysisService({}, this)) {
  setObjectName(QStringLiteral("mainWindow"));
  setDockNestingEnabled(true);

  // Centre: the replay over the trace plots.
  _replay = new ReplayPanel(this);
  _traces = new TracePlots(this);
  auto* centre = new QSplitter(Qt::Vertical, this);
  centre->addWidget(_replay);
  centre->addWidget(_traces);
  centre->setStretchFactor(0, 3);
  centre->setStretchFactor(1, 2);
  setCentralWidget(centre);

  // Left: what is on the pallet.
  auto* left = new QWidget(this);
  auto* leftLayout = new QVBoxLayout(left);
  leftLayout->setContentsMargins(0, 0, 0, 0);
  _picker = new ScenarioPicker(_document, left);
  // A scenario is opened like a file: unsaved work is saved, discarded or kept (cancel) first.
  _picker->setMayReplace([this] { return _files->maybeSave(); });
  _builder = new StackBuilderPanel(_document, left);
  leftLayout->addWidget(_picker);
  leftLayout->addWidget(_builder, 1);
  QDockWidget* leftDock =
      dock(this, tr("Pallet"), QStringLiteral("palletDock"), left, Qt::LeftDockWidgetArea);

  // Right: the dials and what the analysis says; the friction chart under them.
  _dials = new DialPanel(_service->options().search, this);
  _results = new ResultsPanel(this);
  _friction = new FrictionChart(this);
  QDockWidget* dialDock =
      dock(this, tr("Dispatch"), QStringLiteral("dialDock"), _dials, Qt::RightDockWidgetArea);
  QDockWidget* resultsDock =
      dock(this, tr("Results"), QStringLiteral("resultsDock"), _results, Qt::RightDockWidgetArea);
  QDockWidget* frictionDock = dock(this, tr("Friction"), QStringLiteral("frictionDock"), _friction,
                                   Qt::RightDockWidgetArea);
  tabifyDockWidget(resultsDock, frictionDock);
  resultsDock->raise();
  // As wide as their panels ask where the window allows; narrower windows scroll them.
  resizeDocks(
      {leftDock, dialDock},
      {std::max(380, left->minimumSizeHint().width()),
       std::max({420, _dials->minimumSizeHint().width(), _results->minimumSizeHint().width()})},
      Qt::Horizontal);

  _status = new QLabel(tr("Ready"), this);
  _status->setObjectName(QStringLiteral("statusText"));
  _cancel = new QPushButton(tr("Cancel"), this);
  _cancel->setToolTip(tr("Cancel the running analysis"));
  _cancel->setEnabled(false);
  statusBar()->addWidget(_status, 1);
  statusBar()->addPermanentWidget(_cancel);
  connect(_cancel, &QPushButton::clicked, _service, &AnalysisService::cancelAll);

  // The document drives the title and every panel that shows the pallet.
  setWindowTitle(_document->windowTitle());
  connect(_document, &PalletDocument::titleChanged, this, &QWidget::setWindowTitle);
  connect(_document, &PalletDocument::modifiedChanged, this, &QWidget::setWindowModified);
  connect(_document, &PalletDocument::changed, _friction, &FrictionChart::setPallet);
  connect(_document, &PalletDocument::changed, this, [this] {
    // Whatever was asked about the previous pallet is no answer for this one: stop it (the core
    // stops inside the probe it steps) rather than show it under the edited pallet.
    const bool stopped = _service->pendingCount() > 0;
    if (stopped) {
      _cancelReason = tr("Cancelled: the pallet changed");
      _service->cancelAll();
      _cancelReason.clear();
    }
    _mapId = 0;
    _results->clear();
    _dials->resetRound();
    _replay->showPallet(_document->pallet());  // the pallet being edited, at rest
    _traces->clear();
    // What the status said was about the previous pallet ("Replay ready", a map's count).
    showStatus(stopped ? tr("Cancelled: the pallet changed. Dispatch to analyse this pallet.")
                       : tr("The pallet changed. Dispatch to analyse it."));
  });
  connect(_picker, &ScenarioPicker::scenarioLoaded, this, [this](const pb::Scenario& s) {
    _dials->setSpeed(s.suggested_profile.target_speed_mps);
    _dials->setAccel(s.suggested_profile.accel_mps2);
  });

  // Dials, replay, traces and results.
  connect(_dials, &DialPanel::dispatchRequested, this,
          [this](const pb::ConveyorProfile& profile) { dispatch(profile, true, true); });
  connect(_dials, &DialPanel::dialsChanged, _results, &ResultsPanel::setDialledPoint);
  connect(_replay, &ReplayPanel::timeChanged, _traces, &TracePlots::setCursorTime);
  connect(_traces, &TracePlots::timeRequested, _replay->player(), &ReplayPlayer::setTime);
  connect(_replay->player(), &ReplayPlayer::playingChanged, this, [this](bool playing) {
    const ReplayPlayer* p = _replay->player();
    if (!playing && p->time() >= p->endTime() && p->endTime() > p->startTime()) {
      _dials->replayFinished();
    }
  });
  wireAnalysis();
  buildMenus();
  _friction->setPallet(_document->pallet());
  _replay->showPallet(_document->pallet());
  resize(1600, 1000);
}

MainWindow::~MainWindow() = default;

void MainWindow::wireAnalysis() {
  connect(_service, &AnalysisService::progress, this, [this](RequestId, const QString& step) {
    _step = step;
    _stepClock.restart();
    showStatus(step + QStringLiteral("\u2026"));
  });
  connect(_service, &AnalysisService::axisFound, this,
          [this](RequestId id, pb::Axis axis, const pb::AxisLimit& limit) {
            if (id == _analyzeId) _results->setAxisFound(axis, limit);
          });
  connect(
      _service, &AnalysisService::counted, this,
      [this](RequestId, int done, int planned, bool exact) {
        const double elapsed =
            _stepClock.isValid() ? static_cast<double>(_stepClock.elapsed()) / 1000.0 : 0.0;
        showStatus(progressText(_step, done, planned, exact, elapsed) + QStringLiteral("\u2026"));
      });
  connect(_service, &AnalysisService::analyzed, this,
          [this](RequestId id, const pb::SafetyResult& result) {
            _results->setResult(result);
            _dials->setEnvelope(result);
            if (id == _analyzeId) {
              _analyzeDone = true;
              maybeFinishDispatch();
            }
          });
  connect(_service, &AnalysisService::solved, this, [this](RequestId id, const SolvePtr& solve) {
    _replay->setReplay(solve->replay);
    _traces->setReplay(solve->replay);
    _results->setReplay(solve->replay);
    const auto& failure = solve->replay.failure;
    _dials->setOutcome(
        solve->sim.outcome == pb::Outcome::safe,
        failure ? failure->mode : pb::FailureMode::no_failure,
        failure ? pb::slide_kind(*failure, solve->replay.pallet) : pb::SlideKind::item_slid);
    if (id == _solveId) {
      _solveDone = true;
      maybeFinishDispatch();
    }
  });
  connect(_service, &AnalysisService::failureMapReady, this,
          [this](RequestId id, const FailureMapPtr& map) {
            if (id != _mapId) return;  // a map of an earlier dispatch
            _mapId = 0;
            _results->mapView()->setMap(*map);
            showStatus(tr("Failure map: %1 simulations in %2 s")
                           .arg(map->sims)
                           .arg(map->wall_ms / 1000.0, 0, 'f', 1));
          });
  connect(_service, &AnalysisService::failed, this, [this](RequestId id, const QString& message) {
    _results->showError(message);
    showStatus(message);
    if (id == _solveId || id == _analyzeId) {
      if (id == _solveId) _solveDone = true;
      if (id == _analyzeId) _analyzeDone = true;
      _dispatchOk = false;
      _dispatchMessage = message;
      maybeFinishDispatch();
    }
  });
  connect(_service, &AnalysisService::cancelled, this, [this](RequestId id) {
    if (id == _solveId || id == _analyzeId) {
      if (id == _solveId) _solveDone = true;
      if (id == _analyzeId) _analyzeDone = true;
      _dispatchOk = false;
      _dispatchMessage = _cancelReason.isEmpty() ? tr("Cancelled") : _cancelReason;
      maybeFinishDispatch();
    }
  });
}

bool MainWindow::enableAutosave(const QString& directory) {
  if (_autosave == nullptr) _autosave = new Autosave(_document, directory, 2000, this);
  return _files->offerRecovery(directory);
}

bool MainWindow::loadScenario(const QString& slug) {
  return _picker->loadSlug(slug);
}

void MainWindow::dispatch(const pb::ConveyorProfile& profile, bool analyze, bool map) {
  if (!_document->isValid()) {  // nothing is simulated for a pallet validation refuses
    const pb::PalletConfig& pallet = _document->pallet();
    const auto& diagnostics = _document->diagnostics();
    const auto first = std::find_if(diagnostics.begin(), diagnostics.end(), [](const auto& d) {
      return d.severity == pb::Severity::error;
    });
    const QString why =
        tr("Not dispatched: the pallet is not valid. %1 (see the stack builder's findings)")
            .arg(describe_finding(*first, stacks_of(pallet)));
    _dials->refuseDispatch(why);
    showStatus(why);
    emit dispatchFinished(false, why);
    return;
  }
  _service->cancelAll();
  _dispatchOk = true;
  _dispatchMessage.clear();
  _solveDone = false;
  _solveId = _service->solve(_document->pallet(), profile);
  _analyzeDone = !analyze;
  if (analyze) {
    // The closed-form estimate at once (a fraction of a millisecond), marked provisional until
    // the analysis replaces it; set first, so that an answer from the cache always wins.
    if (!_estimator) {
      pb::AnalyzerOptions o = _service->options();  // the same line and search, no simulation
      o.fidelity = pb::Fidelity::closed_form;
      _estimator = std::make_unique<pb::Analyzer>(o);
    }
    if (auto estimate = _estimator->analyze(_document->pallet())) {
      _results->setProvisional(*estimate.value);
    }
  }
  _analyzeId = analyze ? _service->analyze(_document->pallet()) : 0;
  // The failure map comes last (the slowest); the dispatch does not wait for it.
  _mapId = map ? _service->failureMap(_document->pallet()) : 0;
  _cancel->setEnabled(true);
}

void MainWindow::maybeFinishDispatch() {
  if (!_solveDone || !_analyzeDone) return;
  _cancel->setEnabled(_service->pendingCount() > 0);
  if (_dispatchOk) {
    showStatus(tr("Replay ready"));
    if (_replay->hasReplay()) _replay->player()->play();
  }
  const RequestId solved = _solveId;
  _solveId = _analyzeId = 0;
  if (solved != 0) emit dispatchFinished(_dispatchOk, _dispatchMessage);
}

void MainWindow::buildMenus() {
  QMenu* file = _files->fileMenu();
  menuBar()->addMenu(file);
  file->addSeparator();
  file->addAction(tr("Open &Replay\u2026"), this, &MainWindow::openReplay);
  file->addAction(tr("&Export Replay\u2026"), this, &MainWindow::exportReplay);
  file->addAction(tr("Export &Frame as PNG\u2026"), this, &MainWindow::exportFrame);
  file->addSeparator();
  QAction* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);
  menuBar()->addMenu(_files->editMenu());
  QMenu* replay = menuBar()->addMenu(tr("&Replay"));
  replay->addAction(_replay->playAction());
  replay->addAction(_replay->stepBackAction());
  replay->addAction(_replay->stepForwardAction());
  replay->addAction(_replay->goToStartAction());
  replay->addAction(_replay->goToEndAction());
  QMenu* view = menuBar()->addMenu(tr("&View"));
  for (QDockWidget* d : findChildren<QDockWidget*>()) view->addAction(d->toggleViewAction());
}

void MainWindow::openReplay() {
  const QString path = QFileDialog::getOpenFileName(this, tr("Open Replay"), QString(),
                                                    tr("Replay JSON (*.json);;All files (*)"));
  if (path.isEmpty()) return;
  const QString error = _replay->openReplayFile(path);
  if (!error.isEmpty()) {
    QMessageBox::warning(this, tr("Open Replay"), error);
    return;
  }
  _traces->setReplay(_replay->replay());
  _results->setReplay(_replay->replay());
  showStatus(tr("Replay %1 opened (inspecting, not re-simulated)").arg(path));
}

void MainWindow::exportReplay() {
  const QString path =
      QFileDialog::getSaveFileName(this, tr("Export Replay"), QStringLiteral("replay.json"),
                                   tr("Replay JSON (*.json);;Traces as CSV (*.csv)"));
  if (path.isEmpty()) return;
  const QString error = _replay->exportReplay(path);
  if (!error.isEmpty()) QMessageBox::warning(this, tr("Export Replay"), error);
}

void MainWindow::exportFrame() {
  const QString path = QFileDialog::getSaveFileName(this, tr("Export Frame"),
                                                    QStringLiteral("frame.png"), tr("PNG (*.png)"));
  if (path.isEmpty()) return;
  const QString error = _replay->exportFramePng(path);
  if (!error.isEmpty()) QMessageBox::warning(this, tr("Export Frame"), error);
}

void MainWindow::showStatus(const QString& text) {
  _status->setText(text);
  _status->setToolTip(text);
}

QString MainWindow::statusText() const {
  return _status->text();
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (!_files->maybeSave()) {
    event->ignore();
    return;
  }
  _service->cancelAll();
  event->accept();
}

}  // namespace pb::ui
