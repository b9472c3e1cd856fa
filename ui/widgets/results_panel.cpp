// SPDX-License-Identifier: MIT
#include "ui/widgets/results_panel.hpp"

#include <QLabel>
#include <QVBoxLayout>

#include "core/analysis/explain.hpp"
#include "core/base/text.hpp"
#include "ui/widgets/failure_map_view.hpp"

namespace pb::ui {

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}
QString num(double v, int decimals) {
  return QString::number(v, 'f', decimals);
}
/// A limit, never shown above itself (core/base/text.hpp).
QString limit(double v, int decimals) {
  return QString::fromStdString(pb::fixed_floor(v, decimals));
}

/// A failure mode in a supervisor's words (core/physics/detectors.hpp).
QString modeWords(FailureMode mode, SlideKind how) {
  const std::string_view words = pb::mode_words(mode, how);
  return QString::fromUtf8(words.data(), static_cast<qsizetype>(words.size()));
}

QColor gradeColor(char letter) {
  switch (letter) {
    case 'A':
      return {46, 160, 67};
    case 'B':
      return {60, 120, 200};
    case 'C':
      return {230, 150, 0};
    default:
      return {200, 30, 30};
  }
}

}  // namespace

ResultsPanel::ResultsPanel(QWidget* parent) : QWidget(parent) {
  _grade = new QLabel(this);
  _grade->setTextFormat(Qt::RichText);
  _grade->setWordWrap(true);
  _limits = new QLabel(this);
  _limits->setTextFormat(Qt::RichText);
  _limits->setWordWrap(true);
  _reason = new QLabel(this);
  _reason->setWordWrap(true);
  _dispatch = new QLabel(this);
  _dispatch->setWordWrap(true);
  _map = new FailureMapView(this);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(_grade);
  layout->addWidget(_limits);
  layout->addWidget(_reason);
  layout->addWidget(_dispatch);
  layout->addWidget(_map, 1);
  clear();
}

QString ResultsPanel::gradeText() const {
  return _grade->text();
}
QString ResultsPanel::limitsText() const {
  return _limits->text();
}
QString ResultsPanel::reasonText() const {
  return _reason->text();
}
QString ResultsPanel::dispatchText() const {
  return _dispatch->text();
}

void ResultsPanel::clear() {
  _provisional = false;
  _grade->setText(tr("<b>No analysis yet</b>"));
  _limits->clear();
  _reason->clear();
  _dispatch->clear();
  _map->clear();
}

void ResultsPanel::showError(const QString& message) {
  _provisional = false;
  _grade->setText(tr("<span style='color:#c81e1e'><b>Could not analyse this pallet</b></span>"));
  _limits->clear();
  _reason->setText(message);
}

void ResultsPanel::setProvisional(const SafetyResult& estimate) {
  _estimate = estimate;
  _simulated.clear();
  showProvisional();
}

void ResultsPanel::setAxisFound(Axis axis, const AxisLimit& limit) {
  if (!_provisional) return;
  switch (axis) {
    case Axis::accel:
      _estimate.max_accel_mps2 = limit.limit;
      _estimate.accel_mode = limit.mode;
      break;
    case Axis::decel:
      _estimate.max_decel_mps2 = limit.limit;
      _estimate.decel_mode = limit.mode;
      break;
    case Axis::lateral:
      _estimate.max_lateral_g = limit.limit;
      _estimate.lateral_mode = limit.mode;
      break;
    case Axis::speed:
      return;  // the speed combines the e-stop and the curve: it waits for the analysis
  }
  _simulated.insert(axis);
  showProvisional();
}

void ResultsPanel::showProvisional() {
  setResult(_estimate);
  _provisional = true;
  const SafetyResult& r = _estimate;
  if (r.verdict == Verdict::reject || r.dominant_failure_mode == FailureMode::cannot_stand) {
    _limits->setText(tr("<i>Provisional: the closed-form estimate, before any simulation; the "
                        "analysis replaces it.</i><br>") +
                     _limits->text());
    return;
  }
  // Each limit simulated so far in bold, the others marked as the estimate.
  const auto value = [&](Axis axis, double v, int decimals, const QString& unit) {
    const QString n = limit(v, decimals) + QStringLiteral(" ") + unit;
    return _simulated.contains(axis) ? QStringLiteral("<b>%1</b>").arg(n)
                                     : QStringLiteral("<i>\u2248%1</i>").arg(n);
  };
  _limits->setText(
      tr("<i>Provisional: %1 of 3 limits simulated so far (bold); \u2248 marks the closed-form "
         "estimate (for loads whose cartons can move it can be a few tenths off either way), "
         "which the analysis replaces.</i><br>Speed up to %2 · start-up up to %3 · stops up to "
         "%4 · curves up to %5")
          .arg(static_cast<int>(_simulated.size()))
          .arg(value(Axis::speed, r.max_speed_mps, 2, tr("m/s")),
               value(Axis::accel, r.max_accel_mps2, 1, tr("m/s²")),
               value(Axis::decel, r.max_decel_mps2, 1, tr("m/s²")),
               value(Axis::lateral, r.max_lateral_g, 2, tr("g"))));
}

void ResultsPanel::setResult(const SafetyResult& r) {
  _provisional = false;
  const Grade g = grade(r);
  // A build defect has no limits to compare with the table, so it gets no comparison line.
  const QString basis =
      r.dominant_failure_mode == FailureMode::cannot_stand
          ? QString()
          : QStringLiteral("<br><small>%1</small>")
                .arg(tr("The grade compares this pallet with the fixed table the line runs "
                        "today: %1 m/s, start-up %2 m/s².")
                         .arg(num(kTableSpeedMps, 1), num(kTableAccelMps2, 1)));
  _grade->setText(QStringLiteral("<span style='font-size:20pt; color:%1'><b>%2</b></span> "
                                 "<span style='font-size:14pt'><b>%3</b></span><br>%4%5")
                      .arg(gradeColor(g.letter).name(), QString(QChar::fromLatin1(g.letter)),
                           q(g.label).toHtmlEscaped(), q(g.advice).toHtmlEscaped(), basis));
  if (r.dominant_failure_mode == FailureMode::cannot_stand) {
    _limits->setText(
        tr("<b>Build defect:</b> the load cannot stand on a still belt, so no "
           "conveyor limit is given. Re-stack it and analyse again."));
  } else if (r.verdict == Verdict::reject) {
    _limits->setText(tr("No safe motion: <b>%1</b> even at the gentlest setting.")
                         .arg(modeWords(r.dominant_failure_mode, r.dominant_slide)));
  } else {
    _limits->setText(
        tr("Speed up to <b>%1 m/s</b> (set by %2) · start-up up to <b>%3 m/s²</b> · stops "
           "up to <b>%4 m/s²</b> · curves up to <b>%5 g</b><br>First to go: <b>%6</b> · margin "
           "%7 % · %8")
            .arg(limit(r.max_speed_mps, 2),
                 QString::fromUtf8(pb::governor_words(r.speed_governed_by)),
                 limit(r.max_accel_mps2, 2), limit(r.max_decel_mps2, 2), limit(r.max_lateral_g, 3),
                 modeWords(r.dominant_failure_mode, r.dominant_slide), num(r.margin_pct, 0))
            .arg(r.sims_run > 0 ? tr("%1 simulations").arg(r.sims_run)
                                : tr("cached: this pallet was analysed before")));
  }
  _reason->setText(q(r.reason));
}

void ResultsPanel::setReplay(const Replay& replay) {
  if (replay.outcome == "failed" && replay.failure) {
    _dispatch->setText(
        tr("Last dispatch: %1")
            .arg(q(explain_failure(replay.pallet, replay.profile, *replay.failure))));
  } else if (replay.outcome == "safe") {
    _dispatch->setText(
        tr("Last dispatch: survived %1 m/s at %2 m/s² start-up.")
            .arg(num(replay.profile.target_speed_mps, 2), num(replay.profile.accel_mps2, 2)));
  } else {
    _dispatch->setText(tr("Last dispatch: the solver went unstable; no verdict."));
  }
}

void ResultsPanel::setDialledPoint(double speed_mps, double accel_mps2) {
  _map->setDialledPoint(speed_mps, accel_mps2);
}

}  // namespace pb::ui
