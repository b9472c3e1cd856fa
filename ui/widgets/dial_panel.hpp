// SPDX-License-Identifier: MIT
// The dial panel: speed and start-up acceleration dials with numeric entry, a Dispatch button, and
// the game (ui/dial_game.hpp): the envelope stays hidden until the replay ends, then it is painted
// on the dials (safe / marginal / failing arcs) with the score.
//
// Wiring (MainWindow):
//   dispatchRequested(profile)      -> AnalysisService::solve(pallet, profile) and, meanwhile,
//                                      AnalysisService::analyze(pallet)
//   AnalysisService::analyzed       -> setEnvelope(result)        (kept hidden)
//   AnalysisService::solved         -> setOutcome(survived, mode, how) (and the replay starts)
//   replay ended (ReplayControls)   -> replayFinished()           (reveals envelope + score)
//   scoreRevealed(score)            -> status bar / results panel, if wanted
//   dialsChanged(speed, accel)      -> ResultsPanel::setDialledPoint (the heatmap's marker)
//   the pallet changed              -> resetRound() (a new pallet hides the old envelope)
#pragma once

#include <QDial>
#include <QWidget>
#include <optional>

#include "core/analysis/envelope.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/contract/safety_result.hpp"
#include "ui/models/dial_game.hpp"

class QDoubleSpinBox;
class QLabel;
class QPushButton;

namespace pb::ui {

/// A QDial that can paint the solver's envelope as coloured arcs around its rim.
class EnvelopeDial : public QDial {
  Q_OBJECT

 public:
  /// The range [`min_value`, `max_value`] in physical units, `steps_per_unit` the dial's integer
  /// resolution.
  EnvelopeDial(double min_value, double max_value, int steps_per_unit, QWidget* parent = nullptr);

  double physicalValue() const;
  void setPhysicalValue(double value);
  double minPhysical() const { return _min; }
  double maxPhysical() const { return _max; }
  int stepsPerUnit() const { return _steps; }
  /// Paints safe / marginal / failing arcs for this limit; nullopt paints none.
  void setLimit(std::optional<double> limit);
  std::optional<double> limit() const { return _limit; }
  /// The widget point on the arcs' centre line at physical value `value` (for tests).
  QPointF arcPoint(double value) const;
  /// Arc colours, by zone.
  static QColor zoneColor(DialZone zone);

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  /// The fraction of the dial's sweep at physical value `value`.
  double fraction(double value) const;

  double _min, _max;
  int _steps;
  std::optional<double> _limit;
};

class DialPanel : public QWidget {
  Q_OBJECT

 public:
  /// The dials span the analysed range (the search's speed and start-up ranges: `palletballet
  /// --profile-*`, the search and the failure map use the same one), so every dialled point is one
  /// the limits speak about.
  explicit DialPanel(const pb::SearchConfig& range = {}, QWidget* parent = nullptr);

  /// The profile the dials describe: accel_hold to the dialled speed at the dialled acceleration,
  /// held 2 s after the ramp (the game's dispatch).
  ConveyorProfile profile() const;
  double speed() const;
  double accel() const;
  const DialGame& game() const { return _game; }

  EnvelopeDial* speedDial() const { return _speedDial; }
  EnvelopeDial* accelDial() const { return _accelDial; }
  QDoubleSpinBox* speedSpin() const { return _speedSpin; }
  QDoubleSpinBox* accelSpin() const { return _accelSpin; }
  QPushButton* dispatchButton() const { return _dispatch; }
  /// The score / status line ("Envelope hidden until the replay ends", "Dialed in: 91 %").
  QString statusText() const;
  /// The solver's limits once revealed.
  QString limitsText() const;

 public slots:
  void setSpeed(double speed_mps);
  void setAccel(double accel_mps2);
  /// Presses Dispatch: starts a round and emits dispatchRequested(profile()).
  void dispatch();
  /// The solver's envelope for the pallet; hidden until the round is revealed.
  void setEnvelope(const pb::SafetyResult& envelope);
  /// The dispatch ran: survived, or failed with `mode` (a top_item_slide as `how` says).
  void setOutcome(bool survived, pb::FailureMode mode,
                  pb::SlideKind how = pb::SlideKind::item_slid);
  /// The replay of the dispatch ended: reveals the envelope and the score once all is in.
  void replayFinished();
  /// Same as replayFinished() (the name the task used).
  void revealEnvelope() { replayFinished(); }
  /// Forgets the round and hides the envelope (e.g. the pallet changed).
  void resetRound();
  /// The dispatch was refused (an invalid pallet): the round is off and the status says `why`
  /// until the next dispatch or reset.
  void refuseDispatch(const QString& why);

 signals:
  void dispatchRequested(const pb::ConveyorProfile& profile);
  void dialsChanged(double speed_mps, double accel_mps2);
  void scoreRevealed(const pb::ui::DialScore& score);

 private:
  void refresh();

  DialGame _game;
  bool _announced = false;  ///< scoreRevealed emitted for this round
  QString _refused;         ///< why the last dispatch was refused; empty otherwise
  double _speed = -1.0;     ///< last values announced by dialsChanged
  double _accel = -1.0;
  EnvelopeDial* _speedDial;
  EnvelopeDial* _accelDial;
  QDoubleSpinBox* _speedSpin;
  QDoubleSpinBox* _accelSpin;
  QPushButton* _dispatch;
  QLabel* _status;
  QLabel* _limits;
};

}  // namespace pb::ui
