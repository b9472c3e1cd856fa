// SPDX-License-Identifier: MIT
// The replay's transport bar: step back, play/pause, step forward, speed (1x, 1/2x, 1/4x),
// automatic slow motion, camera preset, follow the failing item, the timeline and a time readout.
// It drives a ReplayPlayer and asks the view for camera changes through signals.
#pragma once

#include <QWidget>

#include "ui/replay/replay_view.hpp"

class QCheckBox;
class QComboBox;
class QLabel;
class QToolButton;

namespace pb::ui {

class ReplayPlayer;
class Timeline;

class ReplayControls : public QWidget {
  Q_OBJECT

 public:
  explicit ReplayControls(ReplayPlayer* player, QWidget* parent = nullptr);

  Timeline* timeline() const { return _timeline; }
  /// "t = 0.533 s of 1.200 s · failure at 1.200 s · slow motion 1/4x"
  QString readout() const;
  QComboBox* speedBox() const { return _speed; }

  /// The speeds offered, in the speed box's order.
  static constexpr double kSpeeds[] = {1.0, 0.5, 0.25};

 public slots:
  /// Re-reads the player's range and failure (after ReplayPlayer::setReplay).
  void refresh();

 signals:
  void presetRequested(pb::ui::CameraPreset preset);
  void followRequested(bool follow);

 private:
  void updateReadout();

  ReplayPlayer* _player;
  QToolButton* _back;
  QToolButton* _play;
  QToolButton* _forward;
  QComboBox* _speed;
  QCheckBox* _autoSlow;
  QComboBox* _preset;
  QCheckBox* _follow;
  Timeline* _timeline;
  QLabel* _readout;
};

}  // namespace pb::ui
