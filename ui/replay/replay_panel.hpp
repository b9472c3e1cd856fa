// SPDX-License-Identifier: MIT
// The replay panel: the 3D ReplayView (or, without OpenGL, a sentence saying so) over the transport
// controls, driven by one ReplayPlayer. Opens saved replay files and exports the replay (JSON) and
// the current frame (PNG).
//
// Wiring (MainWindow): setReplay() with a solve's replay; timeChanged() drives the trace plots'
// cursor; actions() (play/pause Space, step back Left, step forward Right) go in the Replay menu.
#pragma once

#include <QAction>
#include <QImage>
#include <QString>
#include <QWidget>

#include "core/analysis/replay.hpp"

class QLabel;

namespace pb::ui {

class ReplayControls;
class ReplayPlayer;
class ReplayView;

class ReplayPanel : public QWidget {
  Q_OBJECT

 public:
  /// Probes OpenGL (ReplayView::probeOpenGl) and builds the 3D view only if a context can be had.
  explicit ReplayPanel(QWidget* parent = nullptr);

  void setReplay(const pb::Replay& replay);
  /// Shows `pallet` as built, at rest (pb::as_built_replay), until the next replay: the pallet
  /// being edited, not a simulation. No replay to play or export meanwhile.
  void showPallet(const pb::PalletConfig& pallet);
  const pb::Replay& replay() const { return _replay; }
  /// A simulated replay is shown (not the as-built preview).
  bool hasReplay() const { return !_preview && !_replay.frames.empty(); }
  bool showsPreview() const { return _preview; }

  /// Reads a replay file (what `palletballet-cli solve --replay` and exportReplay write). Empty
  /// on success, else what is wrong, for a person (the current replay stays).
  QString openReplayFile(const QString& path);
  /// Writes the replay atomically: a path ending in ".csv" gets its traces as CSV
  /// (TracePlots::csv: what the trace plots show, one row per frame), any other the replay's JSON.
  /// Empty on success, else why not.
  QString exportReplay(const QString& path) const;
  /// Writes the frame on screen as PNG. Empty on success, else why not.
  QString exportFramePng(const QString& path);
  /// The frame on screen (the 3D view's framebuffer; without OpenGL, the panel's message).
  QImage grabFrame();

  /// Null when OpenGL is unavailable.
  ReplayView* view() const { return _view; }
  /// Empty while OpenGL works; otherwise the sentence shown instead of the scene.
  QString glProblem() const { return _glProblem; }
  ReplayPlayer* player() const { return _player; }
  ReplayControls* controls() const { return _controls; }
  QAction* playAction() const { return _playAction; }
  QAction* stepBackAction() const { return _backAction; }
  QAction* stepForwardAction() const { return _forwardAction; }
  QAction* goToStartAction() const { return _startAction; }
  QAction* goToEndAction() const { return _endAction; }

 signals:
  /// The replay cursor moved (playing, stepping or seeking).
  void timeChanged(double t);
  /// A new replay is shown.
  void replayChanged();

 private:
  void show(const pb::Replay& replay, bool preview);

  pb::Replay _replay;
  bool _preview = false;
  ReplayView* _view = nullptr;
  QLabel* _noGl = nullptr;
  QString _glProblem;
  ReplayPlayer* _player;
  ReplayControls* _controls;
  QAction* _playAction;
  QAction* _backAction;
  QAction* _forwardAction;
  QAction* _startAction;
  QAction* _endAction;
};

}  // namespace pb::ui
