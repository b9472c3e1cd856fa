// SPDX-License-Identifier: MIT
// The console's main window. It only wires panels together; each panel is its own widget:
// scenario picker and stack builder (left), dials and results with the failure map (right), the
// replay with its controls over the trace plots (centre), the friction chart (bottom right).
#pragma once

#include <QElapsedTimer>
#include <QMainWindow>
#include <memory>
#include <optional>

#include "ui/models/analysis_service.hpp"

class QLabel;
class QPushButton;

namespace pb::ui {

class DialPanel;
class Autosave;
class FileActions;
class FrictionChart;
class PalletDocument;
class RecentFiles;
class ReplayPanel;
class ResultsPanel;
class ScenarioPicker;
class StackBuilderPanel;
class TracePlots;

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Keeps a recovery copy of unsaved work in `directory` (autosave.hpp) and offers what a console
  /// that died left there; true when lost work was restored (the caller then loads nothing else).
  /// The interactive console calls it; screenshots and tests do not.
  bool enableAutosave(const QString& directory);
  /// Loads a curated scenario into the document and its suggested profile into the dials.
  bool loadScenario(const QString& slug);
  /// Runs `profile` on the document's pallet (the replay starts when it arrives) and, with
  /// `analyze`, the SafetyResult meanwhile (as the Dispatch button does), then with `map` the
  /// failure map (not waited for). Ends with dispatchFinished().
  void dispatch(const pb::ConveyorProfile& profile, bool analyze = true, bool map = false);

  PalletDocument* document() const { return _document; }
  AnalysisService* service() const { return _service; }
  ReplayPanel* replayPanel() const { return _replay; }
  DialPanel* dialPanel() const { return _dials; }
  ResultsPanel* resultsPanel() const { return _results; }
  TracePlots* tracePlots() const { return _traces; }
  FrictionChart* frictionChart() const { return _friction; }
  StackBuilderPanel* stackBuilder() const { return _builder; }
  FileActions* fileActions() const { return _files; }
  /// The status line's text (progress, errors).
  QString statusText() const;

 signals:
  /// The dispatched profile's replay is shown (ok) or the run failed (`message` says why). With
  /// analysis, emitted once both the replay and the SafetyResult (or its failure) are in.
  void dispatchFinished(bool ok, const QString& message);

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  void buildMenus();
  void wireAnalysis();
  void openReplay();
  void exportReplay();
  void exportFrame();
  void showStatus(const QString& text);
  void maybeFinishDispatch();

  PalletDocument* _document;
  RecentFiles* _recent;
  FileActions* _files;
  Autosave* _autosave = nullptr;
  std::unique_ptr<pb::Analyzer> _estimator;  ///< the closed-form level, for the provisional answer
  AnalysisService* _service;
  ScenarioPicker* _picker;
  StackBuilderPanel* _builder;
  DialPanel* _dials;
  ResultsPanel* _results;
  ReplayPanel* _replay;
  TracePlots* _traces;
  FrictionChart* _friction;
  QLabel* _status;
  QPushButton* _cancel;

  // The dispatch in flight: its solve and (optional) analysis requests.
  RequestId _solveId = 0, _analyzeId = 0;
  RequestId _mapId = 0;   ///< the failure map of the latest dispatch, until it arrives
  QString _cancelReason;  ///< why requests are being cancelled, while they are
  bool _solveDone = true, _analyzeDone = true, _dispatchOk = true;
  QString _dispatchMessage;
  QString _step;             ///< what the service is doing (its last progress step)
  QElapsedTimer _stepClock;  ///< since that step began
};

}  // namespace pb::ui
