// SPDX-License-Identifier: MIT
// The replay's clock: play/pause, step a frame, speed 1x / 1/2x / 1/4x, and automatic slow motion
// (1/4x) around the failure time. Headless: it only moves a time; ReplayView draws it.
#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>
#include <optional>

#include "core/analysis/replay.hpp"

namespace pb::ui {

class ReplayPlayer : public QObject {
  Q_OBJECT

 public:
  /// Slow motion runs from this long before the failure ...
  static constexpr double kSlowBeforeS = 0.5;
  /// ... to this long after it: a failed replay follows the wreck after the failure
  /// (Analyzer::solve), and the first second of it is the moment a supervisor wants to see.
  static constexpr double kSlowAfterS = 1.5;
  /// The slow-motion rate (a fraction of real time).
  static constexpr double kSlowRate = 0.25;

  explicit ReplayPlayer(QObject* parent = nullptr);

  /// Starts over at the replay's first frame, paused. Keeps the speed and the slow-motion choice.
  void setReplay(const pb::Replay& replay);
  double startTime() const { return _start; }
  double endTime() const { return _end; }
  double hz() const { return _hz; }
  /// The failure time of a failed replay.
  std::optional<double> failureTime() const { return _failure; }

  double time() const { return _time; }
  bool isPlaying() const { return _playing; }
  /// 1, 0.5 or 0.25 (any positive value is accepted).
  double speed() const { return _speed; }
  bool autoSlowMotion() const { return _autoSlow; }
  /// The rate at which the replay advances now (simulated s per wall s).
  double rate() const { return rateAt(_time, _speed, _autoSlow, _failure); }
  /// True while the automatic slow motion holds the rate below the chosen speed.
  bool inSlowMotion() const { return rate() < _speed; }

  /// The playback rate at replay time `t`: `speed`, or at most kSlowRate within
  /// [failure - kSlowBeforeS, failure + kSlowAfterS] when `autoSlow` is on.
  static double rateAt(double t, double speed, bool autoSlow, std::optional<double> failure);

  /// Advances the clock by `wallSeconds` of real time at the current rate (the timer calls this;
  /// tests call it directly). Stops, paused, at the end.
  void advance(double wallSeconds);

 public slots:
  void play();
  void pause();
  void togglePlay();
  /// Clamped to [startTime, endTime].
  void setTime(double t);
  /// Moves `frames` frames (of 1 / hz) forward or back from the current time, landing on the
  /// frame grid; pauses.
  void step(int frames);
  void setSpeed(double speed);
  void setAutoSlowMotion(bool on);

 signals:
  void timeChanged(double t);
  void playingChanged(bool playing);
  /// The effective rate changed (speed chosen, or slow motion entered or left).
  void rateChanged(double rate);

 private:
  void tick();
  void emitRateIfChanged();

  double _start = 0.0, _end = 0.0, _hz = 30.0, _time = 0.0;
  std::optional<double> _failure;
  bool _playing = false;
  double _speed = 1.0;
  bool _autoSlow = true;
  double _lastRate = 1.0;
  QTimer _timer;
  QElapsedTimer _wall;
};

}  // namespace pb::ui
