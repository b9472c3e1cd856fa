// SPDX-License-Identifier: MIT
// The results panel: the SafetyResult in words a supervisor reads at a glance (a grade, the
// limits, the governing mode, "Reject and re-wrap" when no motion is safe, the reason sentence),
// the last dispatch explained in one sentence, and the failure map (FailureMapView).
//
// Wiring (MainWindow):
//   AnalysisService::analyzed(result)  -> setResult(result)
//   AnalysisService::solved(solve)     -> setReplay(solve->replay)   (the dispatch sentence)
//   the failure map arrives            -> mapView()->setGrid(...) / setMap(...)
//   DialPanel::dialsChanged(v, a)      -> setDialledPoint(v, a)
//   AnalysisService::failed(message)   -> showError(message)
//   the pallet changed                 -> clear()
#pragma once

#include <QString>
#include <QWidget>
#include <set>

#include "core/analysis/envelope.hpp"
#include "core/analysis/replay.hpp"
#include "core/contract/safety_result.hpp"

class QLabel;

namespace pb::ui {

class FailureMapView;

class ResultsPanel : public QWidget {
  Q_OBJECT

 public:
  explicit ResultsPanel(QWidget* parent = nullptr);

  FailureMapView* mapView() const { return _map; }
  QString gradeText() const;
  QString limitsText() const;
  QString reasonText() const;
  QString dispatchText() const;
  /// True while the limits shown are the closed-form estimate (setProvisional), not the analysis.
  bool isProvisional() const { return _provisional; }

 public slots:
  void setResult(const pb::SafetyResult& result);
  /// The closed-form estimate, known within a millisecond (fidelity closed_form: no simulation),
  /// shown at once and marked provisional until setResult() replaces it with the analysis.
  void setProvisional(const pb::SafetyResult& estimate);
  /// One simulated limit while the estimate is shown: it replaces that axis's estimate (start-up,
  /// stop or curve; the speed waits for the analysis). Ignored once the analysis is shown.
  void setAxisFound(pb::Axis axis, const pb::AxisLimit& limit);
  /// Explains the dispatch the replay recorded ("top item slid: needs mu 0.41, has 0.32 at -22 C").
  void setReplay(const pb::Replay& replay);
  void setDialledPoint(double speed_mps, double accel_mps2);
  /// A failed request: shown in place of the grade, for a person.
  void showError(const QString& message);
  void clear();

 private:
  QLabel* _grade;
  QLabel* _limits;
  QLabel* _reason;
  QLabel* _dispatch;
  FailureMapView* _map;
  bool _provisional = false;
  pb::SafetyResult _estimate;  ///< while provisional: the estimate, with the axes simulated so far
  std::set<pb::Axis> _simulated;
  /// Shows _estimate marked provisional, each limit as estimated or simulated.
  void showProvisional();
};

}  // namespace pb::ui
