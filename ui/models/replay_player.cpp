// SPDX-License-Identifier: MIT
#include "ui/models/replay_player.hpp"

#include <algorithm>
#include <cmath>

namespace pb::ui {

namespace {
constexpr int kTickMs = 16;  ///< about 60 updates a second
}

ReplayPlayer::ReplayPlayer(QObject* parent) : QObject(parent) {
  _timer.setInterval(kTickMs);
  _timer.setTimerType(Qt::PreciseTimer);
  connect(&_timer, &QTimer::timeout, this, &ReplayPlayer::tick);
}

void ReplayPlayer::setReplay(const pb::Replay& replay) {
  pause();
  _start = replay.frames.empty() ? 0.0 : replay.frames.front().t;
  _end = replay.frames.empty() ? 0.0 : replay.frames.back().t;
  _hz = replay.hz > 0.0 ? replay.hz : 30.0;
  _failure.reset();
  if (replay.failure) _failure = replay.failure->time_s;
  _time = _start;
  emit timeChanged(_time);
  emitRateIfChanged();
}

double ReplayPlayer::rateAt(double t, double speed, bool autoSlow, std::optional<double> failure) {
  if (autoSlow && failure && t >= *failure - kSlowBeforeS && t <= *failure + kSlowAfterS) {
    return std::min(speed, kSlowRate);
  }
  return speed;
}

void ReplayPlayer::advance(double wallSeconds) {
  if (!(wallSeconds > 0.0)) return;
  // Piecewise exact: the rate changes only where the slow-motion window starts and ends.
  double left = wallSeconds;
  double t = _time;
  const bool window = _autoSlow && _failure && kSlowRate < _speed;
  const double s0 = window ? *_failure - kSlowBeforeS : 0.0;
  const double s1 = window ? *_failure + kSlowAfterS : 0.0;
  while (left > 0.0 && t < _end) {
    const double r = rateAt(t, _speed, _autoSlow, _failure);
    double boundary = _end;
    if (window && t < s0) boundary = std::min(_end, s0);
    if (window && t >= s0 && t <= s1) boundary = std::min(_end, std::nextafter(s1, _end + 1.0));
    const double need = (boundary - t) / r;
    if (need >= left) {
      t += r * left;
      left = 0.0;
    } else {
      t = boundary;
      left -= need;
    }
  }
  setTime(t);
  if (_time >= _end) pause();
}

void ReplayPlayer::play() {
  if (_playing || _end <= _start) return;
  if (_time >= _end) setTime(_start);  // play again from the start
  _playing = true;
  _wall.start();
  _timer.start();
  emit playingChanged(true);
}

void ReplayPlayer::pause() {
  if (!_playing) return;
  _playing = false;
  _timer.stop();
  emit playingChanged(false);
}

void ReplayPlayer::togglePlay() {
  _playing ? pause() : play();
}

void ReplayPlayer::setTime(double t) {
  const double clamped = std::isnan(t) ? _start : std::clamp(t, _start, std::max(_start, _end));
  if (clamped == _time) return;
  _time = clamped;
  emit timeChanged(_time);
  emitRateIfChanged();
}

void ReplayPlayer::step(int frames) {
  pause();
  const double dt = 1.0 / _hz;
  // The frame grid k / hz (from t = 0, as the core resamples); the last frame may be off grid.
  const double k = _time / dt;
  const double kNear = std::round(k);
  const bool onGrid = std::abs(k - kNear) < 1e-6;
  double target;
  if (frames > 0) {
    target = ((onGrid ? kNear : std::floor(k)) + frames) * dt;
  } else if (frames < 0) {
    target = ((onGrid ? kNear : std::ceil(k)) + frames) * dt;
  } else {
    return;
  }
  // Stepping forward past the last grid frame lands on the last frame itself.
  setTime(target > _end ? _end : target);
}

void ReplayPlayer::setSpeed(double speed) {
  if (!(speed > 0.0) || speed == _speed) return;
  _speed = speed;
  emitRateIfChanged();
}

void ReplayPlayer::setAutoSlowMotion(bool on) {
  if (on == _autoSlow) return;
  _autoSlow = on;
  emitRateIfChanged();
}

void ReplayPlayer::tick() {
  const double elapsed = static_cast<double>(_wall.restart()) / 1000.0;
  advance(elapsed);
}

void ReplayPlayer::emitRateIfChanged() {
  const double now = rate();
  if (now == _lastRate) return;
  _lastRate = now;
  emit rateChanged(now);
}

}  // namespace pb::ui
