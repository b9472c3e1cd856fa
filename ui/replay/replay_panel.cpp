// SPDX-License-Identifier: MIT
#include "ui/replay/replay_panel.hpp"

#include <QFile>
#include <QLabel>
#include <QSaveFile>
#include <QVBoxLayout>

#include "core/contract/json_io.hpp"
#include "ui/models/replay_player.hpp"
#include "ui/replay/replay_controls.hpp"
#include "ui/replay/replay_view.hpp"
#include "ui/widgets/trace_plots.hpp"

namespace pb::ui {

ReplayPanel::ReplayPanel(QWidget* parent) : QWidget(parent), _player(new ReplayPlayer(this)) {
  _glProblem = ReplayView::probeOpenGl();
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(0);
  if (_glProblem.isEmpty()) {
    _view = new ReplayView(this);
    layout->addWidget(_view, 1);
  } else {
    // A QOpenGLWidget whose context fails cannot paint at all: say why in its place.
    _noGl = new QLabel(_glProblem, this);
    _noGl->setObjectName(QStringLiteral("replayNoOpenGl"));
    _noGl->setAlignment(Qt::AlignCenter);
    _noGl->setWordWrap(true);
    _noGl->setMinimumSize(320, 240);
    _noGl->setFrameShape(QFrame::StyledPanel);
    layout->addWidget(_noGl, 1);
  }
  _controls = new ReplayControls(_player, this);
  layout->addWidget(_controls);

  _playAction = new QAction(tr("Play / Pause"), this);
  _playAction->setShortcut(QKeySequence(Qt::Key_Space));
  _backAction = new QAction(tr("Back One Frame"), this);
  _backAction->setShortcut(QKeySequence(Qt::Key_Left));
  _forwardAction = new QAction(tr("Forward One Frame"), this);
  _forwardAction->setShortcut(QKeySequence(Qt::Key_Right));
  connect(_playAction, &QAction::triggered, _player, &ReplayPlayer::togglePlay);
  connect(_backAction, &QAction::triggered, _player, [this] { _player->step(-1); });
  connect(_forwardAction, &QAction::triggered, _player, [this] { _player->step(1); });
  _startAction = new QAction(tr("Go to Start"), this);
  _startAction->setShortcut(QKeySequence(Qt::Key_Home));
  _endAction = new QAction(tr("Go to End"), this);
  _endAction->setShortcut(QKeySequence(Qt::Key_End));
  connect(_startAction, &QAction::triggered, _player, [this] {
    _player->pause();
    _player->setTime(_player->startTime());
  });
  connect(_endAction, &QAction::triggered, _player, [this] {
    _player->pause();
    _player->setTime(_player->endTime());
  });

  connect(_player, &ReplayPlayer::timeChanged, this, [this](double t) {
    if (_view != nullptr) _view->setTime(t);
    emit timeChanged(t);
  });
  if (_view != nullptr) {
    connect(_controls, &ReplayControls::presetRequested, _view, &ReplayView::setPreset);
    connect(_controls, &ReplayControls::followRequested, _view, &ReplayView::setFollowFailure);
  }
}

void ReplayPanel::setReplay(const pb::Replay& replay) {
  show(replay, false);
}

void ReplayPanel::showPallet(const pb::PalletConfig& pallet) {
  show(pb::as_built_replay(pallet), true);
}

void ReplayPanel::show(const pb::Replay& replay, bool preview) {
  _replay = replay;
  _preview = preview;
  if (_view != nullptr) _view->setReplay(_replay);
  _player->setReplay(_replay);
  _controls->refresh();
  _controls->setEnabled(!preview);
  emit replayChanged();
}

QString ReplayPanel::openReplayFile(const QString& path) {
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly)) {
    return tr("Cannot open %1: %2").arg(path, file.errorString());
  }
  const QByteArray bytes = file.read(qint64(pb::kMaxDocumentBytes) + 1);  // parse_json refuses more
  auto json = pb::parse_json(std::string_view(bytes.constData(), bytes.size()));
  QStringList errors;
  if (json) {
    auto replay = pb::replay_from_json(*json);
    if (replay) {
      setReplay(*replay);
      return {};
    }
    for (const auto& d : pb::errors_of(replay.diagnostics)) {
      errors << QString::fromStdString(pb::to_string(d));
    }
  } else {
    for (const auto& d : pb::errors_of(json.diagnostics)) {
      errors << QString::fromStdString(pb::to_string(d));
    }
  }
  return tr("%1 is not a replay file: %2").arg(path, errors.join(QStringLiteral("; ")));
}

QString ReplayPanel::exportReplay(const QString& path) const {
  if (!hasReplay()) return tr("There is no replay to export yet.");
  QSaveFile file(path);
  if (!file.open(QIODevice::WriteOnly)) {
    return tr("Cannot write %1: %2").arg(path, file.errorString());
  }
  const QByteArray text =
      path.endsWith(QStringLiteral(".csv"), Qt::CaseInsensitive)
          ? TracePlots::csv(_replay)
          : QByteArray::fromStdString(pb::replay_to_json(_replay).dump() + "\n");
  file.write(text);
  if (!file.commit()) return tr("Cannot write %1: %2").arg(path, file.errorString());
  return {};
}

QImage ReplayPanel::grabFrame() {
  if (_view != nullptr) return _view->grabFramebuffer();
  return _noGl->grab().toImage();
}

QString ReplayPanel::exportFramePng(const QString& path) {
  const QImage image = grabFrame();
  if (image.isNull()) return tr("The frame could not be captured.");
  if (!image.save(path, "PNG")) return tr("Cannot write the PNG %1.").arg(path);
  return {};
}

}  // namespace pb::ui
