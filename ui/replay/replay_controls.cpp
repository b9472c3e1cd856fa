// SPDX-License-Identifier: MIT
#include "ui/replay/replay_controls.hpp"

#include <QCheckBox>
#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QStyle>
#include <QToolButton>
#include <QVBoxLayout>

#include "ui/models/replay_player.hpp"
#include "ui/widgets/timeline.hpp"

namespace pb::ui {

namespace {

QString speedLabel(double s) {
  if (s == 1.0) return QStringLiteral("1\u00d7");
  if (s == 0.5) return QStringLiteral("\u00bd\u00d7");
  if (s == 0.25) return QStringLiteral("\u00bc\u00d7");
  return QStringLiteral("%1\u00d7").arg(s);
}

QToolButton* toolButton(QWidget* parent, QStyle::StandardPixmap icon, const QString& tip) {
  auto* b = new QToolButton(parent);
  b->setIcon(parent->style()->standardIcon(icon));
  b->setToolTip(tip);
  b->setAutoRaise(true);
  return b;
}

}  // namespace

ReplayControls::ReplayControls(ReplayPlayer* player, QWidget* parent)
    : QWidget(parent), _player(player) {
  _back = toolButton(this, QStyle::SP_MediaSeekBackward, tr("Back one frame (\u2190)"));
  _play = toolButton(this, QStyle::SP_MediaPlay, tr("Play / pause (Space)"));
  _forward = toolButton(this, QStyle::SP_MediaSeekForward, tr("Forward one frame (\u2192)"));
  _speed = new QComboBox(this);
  for (double s : kSpeeds) _speed->addItem(speedLabel(s), s);
  _speed->setToolTip(tr("Playback speed"));
  _autoSlow = new QCheckBox(tr("Slow motion at failure"), this);
  _autoSlow->setToolTip(
      tr("Play at \u00bc\u00d7 from %1 s before the failure").arg(ReplayPlayer::kSlowBeforeS));
  _autoSlow->setChecked(player->autoSlowMotion());
  _preset = new QComboBox(this);
  _preset->addItem(tr("Iso view"), static_cast<int>(CameraPreset::iso));
  _preset->addItem(tr("Front"), static_cast<int>(CameraPreset::front));
  _preset->addItem(tr("Side"), static_cast<int>(CameraPreset::side));
  _preset->addItem(tr("Top"), static_cast<int>(CameraPreset::top));
  _preset->setToolTip(tr("Camera preset"));
  _follow = new QCheckBox(tr("Follow failing item"), this);
  _follow->setToolTip(tr("Keep the camera on the item that failed first"));
  _timeline = new Timeline(this);
  _timeline->setToolTip(
      tr("Click or drag to move through the replay; the red mark is the failure (Home: start, "
         "End: end)"));
  _readout = new QLabel(this);
  _readout->setTextInteractionFlags(Qt::TextSelectableByMouse);

  auto* row = new QHBoxLayout;
  row->setContentsMargins(0, 0, 0, 0);
  row->addWidget(_back);
  row->addWidget(_play);
  row->addWidget(_forward);
  row->addWidget(_speed);
  row->addWidget(_autoSlow);
  row->addStretch(1);
  row->addWidget(_preset);
  row->addWidget(_follow);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(6, 2, 6, 2);
  layout->setSpacing(2);
  layout->addWidget(_timeline);
  layout->addLayout(row);
  layout->addWidget(_readout);

  connect(_back, &QToolButton::clicked, player, [player] { player->step(-1); });
  connect(_forward, &QToolButton::clicked, player, [player] { player->step(1); });
  connect(_play, &QToolButton::clicked, player, &ReplayPlayer::togglePlay);
  connect(_speed, &QComboBox::currentIndexChanged, this,
          [this] { _player->setSpeed(_speed->currentData().toDouble()); });
  connect(_autoSlow, &QCheckBox::toggled, player, &ReplayPlayer::setAutoSlowMotion);
  connect(_preset, &QComboBox::currentIndexChanged, this, [this] {
    emit presetRequested(static_cast<CameraPreset>(_preset->currentData().toInt()));
  });
  connect(_follow, &QCheckBox::toggled, this, &ReplayControls::followRequested);
  connect(_timeline, &Timeline::seekRequested, player, [player](double t) {
    player->pause();
    player->setTime(t);
  });
  connect(player, &ReplayPlayer::timeChanged, this, [this](double t) {
    _timeline->setTime(t);
    updateReadout();
  });
  connect(player, &ReplayPlayer::rateChanged, this, &ReplayControls::updateReadout);
  connect(player, &ReplayPlayer::playingChanged, this, [this](bool playing) {
    _play->setIcon(style()->standardIcon(playing ? QStyle::SP_MediaPause : QStyle::SP_MediaPlay));
    updateReadout();
  });
  refresh();
}

void ReplayControls::refresh() {
  _timeline->setRange(_player->startTime(), _player->endTime());
  _timeline->setFailureTime(_player->failureTime());
  if (const auto f = _player->failureTime()) {
    _timeline->setSlowBand(
        std::pair{*f - ReplayPlayer::kSlowBeforeS, *f + ReplayPlayer::kSlowAfterS});
  } else {
    _timeline->setSlowBand(std::nullopt);
  }
  _timeline->setTime(_player->time());
  const bool any = _player->endTime() > _player->startTime();
  for (QWidget* w : {static_cast<QWidget*>(_back), static_cast<QWidget*>(_play),
                     static_cast<QWidget*>(_forward), static_cast<QWidget*>(_timeline)}) {
    w->setEnabled(any);
  }
  updateReadout();
}

QString ReplayControls::readout() const {
  if (_player->endTime() <= _player->startTime())
    return tr("No replay yet: dispatch a profile or open a replay file");
  QString text =
      tr("t = %1 s of %2 s").arg(_player->time(), 0, 'f', 3).arg(_player->endTime(), 0, 'f', 3);
  if (const auto f = _player->failureTime()) {
    text += tr(" \u00b7 failure at %1 s").arg(*f, 0, 'f', 3);
  } else {
    text += tr(" \u00b7 no failure");
  }
  if (_player->inSlowMotion()) {
    text += tr(" \u00b7 slow motion %1").arg(speedLabel(_player->rate()));
  } else {
    text += QStringLiteral(" \u00b7 %1").arg(speedLabel(_player->rate()));
  }
  return text;
}

void ReplayControls::updateReadout() {
  _readout->setText(readout());
}

}  // namespace pb::ui
