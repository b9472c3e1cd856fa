// SPDX-License-Identifier: MIT
#include "ui/models/analysis_service.hpp"

#include <QMetaObject>
#include <QStringList>
#include <exception>
#include <utility>

#include "core/base/text.hpp"
#include "core/contract/fingerprint.hpp"

namespace pb::ui {

namespace {

/// "<what>: <pointer>: <message>; ..." from the errors of a failed core call.
QString describeFailure(const QString& what, const pb::Diagnostics& diagnostics) {
  QStringList parts;
  for (const pb::Diagnostic& d : pb::condensed(pb::errors_of(diagnostics))) {
    parts << QString::fromStdString(pb::to_string(d));
  }
  if (parts.isEmpty()) parts << QStringLiteral("the core gave no reason");
  return what + QStringLiteral(": ") + parts.join(QStringLiteral("; "));
}

void registerMetaTypes() {
  qRegisterMetaType<pb::ui::RequestId>("pb::ui::RequestId");
  qRegisterMetaType<pb::SafetyResult>();
  qRegisterMetaType<pb::Axis>();
  qRegisterMetaType<pb::AxisLimit>();
  qRegisterMetaType<pb::ui::SolvePtr>();
  qRegisterMetaType<pb::ui::EnvelopePtr>();
  qRegisterMetaType<pb::ui::FailureMapPtr>();
}

}  // namespace

AnalysisService::AnalysisService(pb::AnalyzerOptions options, QObject* parent)
    : QObject(parent), _analyzer(std::make_unique<pb::Analyzer>(std::move(options))) {
  registerMetaTypes();
  // One thread, kept for the service's life: requests run in order on one Analyzer.
  _pool.setMaxThreadCount(1);
  _pool.setExpiryTimeout(-1);
  _analyzer->set_cancel(&_stopRunning);
  _analyzer->set_progress([this](int done, int planned) { reportCount(done, planned); });
  _analyzer->set_axis_found(
      [this](pb::Axis axis, const pb::AxisLimit& limit) { reportAxis(axis, limit); });
}

AnalysisService::~AnalysisService() {
  {
    std::lock_guard lock(_mutex);
    _cancelled.insert(_pending.begin(), _pending.end());
    if (_running != 0) _stopRunning = true;
  }
  _pool.clear();
  _pool.waitForDone();
}

std::function<void()> AnalysisService::prepareOrFail(pb::Analyzer& analyzer, RequestId id,
                                                     const pb::PalletConfig& config) {
  reportProgress(id, tr("Compiling and settling the pallet"));
  auto prepared = analyzer.prepare(config);
  if (prepared) return {};
  QString message = describeFailure(tr("The pallet cannot be simulated"), prepared.diagnostics);
  return [this, id, message] { emit failed(id, message); };
}

RequestId AnalysisService::analyze(const pb::PalletConfig& config) {
  return submit([this, config](pb::Analyzer& analyzer, RequestId id) -> std::function<void()> {
    if (auto failure = prepareOrFail(analyzer, id, config)) return failure;
    reportProgress(id, tr("Searching the safe envelope"));
    _countExact = false;
    auto result = analyzer.analyze(config);
    if (!result) {
      QString message = describeFailure(tr("The analysis failed"), result.diagnostics);
      return [this, id, message] { emit failed(id, message); };
    }
    return [this, id, value = std::move(*result.value)] { emit analyzed(id, value); };
  });
}

RequestId AnalysisService::envelope(const pb::PalletConfig& config) {
  return submit([this, config](pb::Analyzer& analyzer, RequestId id) -> std::function<void()> {
    if (auto failure = prepareOrFail(analyzer, id, config)) return failure;
    reportProgress(id, tr("Searching the safe envelope"));
    _countExact = false;
    auto result = analyzer.envelope(config);
    if (!result) {
      QString message = describeFailure(tr("The envelope search failed"), result.diagnostics);
      return [this, id, message] { emit failed(id, message); };
    }
    EnvelopePtr value = std::make_shared<const pb::Envelope>(std::move(*result.value));
    return [this, id, value] { emit envelopeReady(id, value); };
  });
}

RequestId AnalysisService::solve(const pb::PalletConfig& config, const pb::ConveyorProfile& profile,
                                 double replay_hz) {
  return submit([this, config, profile, replay_hz](pb::Analyzer& analyzer,
                                                   RequestId id) -> std::function<void()> {
    if (auto failure = prepareOrFail(analyzer, id, config)) return failure;
    reportProgress(id, tr("Simulating the profile"));
    auto result = analyzer.solve(config, profile, replay_hz);
    if (!result) {
      QString message = describeFailure(tr("The profile cannot be simulated"), result.diagnostics);
      return [this, id, message] { emit failed(id, message); };
    }
    if (result->sim.outcome == pb::Outcome::unstable) {
      QString message = tr("The simulation became numerically unstable at t = %1 s, so this run "
                           "has no verdict: %2")
                            .arg(result->sim.sim_time_s, 0, 'f', 3)
                            .arg(QString::fromStdString(result->sim.reason));
      return [this, id, message] { emit failed(id, message); };
    }
    SolvePtr value = std::make_shared<const pb::Solve>(std::move(*result.value));
    return [this, id, value] { emit solved(id, value); };
  });
}

namespace {

// What a failure map depends on besides the analyzer's options: the pallet and the grid.
std::string mapKey(const pb::PalletConfig& config, const pb::MapOptions& o) {
  std::string key = pb::config_fingerprint(config) + "|" + std::to_string(o.n_speeds) + "x" +
                    std::to_string(o.n_accels);
  for (const auto* grid : {&o.speeds_mps, &o.accels_mps2}) {
    key += "|";
    for (double v : *grid) key += pb::short_number(v) + ",";
  }
  return key;
}

constexpr std::size_t kCachedMaps = 16;

}  // namespace

RequestId AnalysisService::failureMap(const pb::PalletConfig& config,
                                      const pb::MapOptions& options) {
  const std::string key = mapKey(config, options);
  if (auto it = _maps.find(key); it != _maps.end()) {  // computed before: answered at once
    const RequestId id = _nextId++;
    _pending.insert(id);
    FailureMapPtr value = it->second;
    QMetaObject::invokeMethod(
        this,
        [this, id, value] { finish(id, [this, id, value] { emit failureMapReady(id, value); }); },
        Qt::QueuedConnection);
    return id;
  }
  return submit(
      [this, config, options, key](pb::Analyzer& analyzer, RequestId id) -> std::function<void()> {
        if (auto failure = prepareOrFail(analyzer, id, config)) return failure;
        reportProgress(id, tr("Mapping speed against acceleration"));
        _countExact = true;
        auto result = analyzer.failure_map(config, options);
        if (!result) {
          QString message = describeFailure(tr("The failure map failed"), result.diagnostics);
          return [this, id, message] { emit failed(id, message); };
        }
        FailureMapPtr value = std::make_shared<const pb::FailureMap>(std::move(*result.value));
        // On the GUI thread: kept for the next request of the same pallet and grid (a map with
        // cells that had no verdict is not kept: the next request tries again).
        return [this, id, value, key] {
          if (value->unstable_cells == 0) {
            if (_maps.size() >= kCachedMaps) _maps.clear();
            _maps.emplace(key, value);
          }
          emit failureMapReady(id, value);
        };
      });
}

void AnalysisService::cancel(RequestId id) {
  if (_pending.erase(id) == 0) return;
  {
    std::lock_guard lock(_mutex);
    _cancelled.insert(id);
    if (_running == id) _stopRunning = true;  // stop the simulation it is stepping
  }
  emit cancelled(id);
}

void AnalysisService::cancelAll() {
  const std::set<RequestId> pending = _pending;
  for (RequestId id : pending) cancel(id);
}

RequestId AnalysisService::submit(Job job) {
  const RequestId id = _nextId++;
  _pending.insert(id);
  pb::Analyzer* analyzer = _analyzer.get();
  _pool.start([this, id, analyzer, job = std::move(job)] {
    {
      std::lock_guard lock(_mutex);
      if (_cancelled.contains(id)) {
        _cancelled.erase(id);
        return;
      }
      _running = id;
      _stopRunning = false;
    }
    struct NotRunning {
      AnalysisService* service;
      ~NotRunning() {
        std::lock_guard lock(service->_mutex);
        service->_running = 0;
      }
    } not_running{this};
    std::function<void()> emitResult;
    try {
      emitResult = job(*analyzer, id);
    } catch (const std::exception& e) {
      // The core throws nothing by contract; a console must survive even an out-of-memory.
      QString message =
          tr("Internal error in the physics core: %1").arg(QString::fromUtf8(e.what()));
      emitResult = [this, id, message] { emit failed(id, message); };
    } catch (...) {
      QString message = tr("Internal error in the physics core (unknown exception)");
      emitResult = [this, id, message] { emit failed(id, message); };
    }
    QMetaObject::invokeMethod(
        this, [this, id, emitResult] { finish(id, emitResult); }, Qt::QueuedConnection);
  });
  return id;
}

void AnalysisService::finish(RequestId id, const std::function<void()>& emitResult) {
  if (_pending.erase(id) == 0) {  // cancelled while it ran: drop the result
    std::lock_guard lock(_mutex);
    _cancelled.erase(id);
    return;
  }
  emitResult();
}

void AnalysisService::reportProgress(RequestId id, const QString& step) {
  QMetaObject::invokeMethod(
      this,
      [this, id, step] {
        if (_pending.contains(id)) emit progress(id, step);
      },
      Qt::QueuedConnection);
}

void AnalysisService::queueForRunning(const std::function<void(RequestId)>& emitFor) {
  RequestId id = 0;
  {
    std::lock_guard lock(_mutex);
    id = _running;
  }
  if (id == 0) return;
  QMetaObject::invokeMethod(
      this,
      [this, id, emitFor] {
        if (_pending.contains(id)) emitFor(id);
      },
      Qt::QueuedConnection);
}

void AnalysisService::reportCount(int done, int planned) {
  const bool exact = _countExact.load();
  queueForRunning(
      [this, done, planned, exact](RequestId id) { emit counted(id, done, planned, exact); });
}

void AnalysisService::reportAxis(pb::Axis axis, const pb::AxisLimit& limit) {
  queueForRunning([this, axis, limit](RequestId id) { emit axisFound(id, axis, limit); });
}

QString progressText(const QString& step, int done, int planned, bool exact, double elapsed_s) {
  QString text =
      exact
          ? AnalysisService::tr("%1: %2 of %3 simulations").arg(step).arg(done).arg(planned)
          : AnalysisService::tr("%1: %2 of about %3 simulations").arg(step).arg(done).arg(planned);
  if (done >= 2 && elapsed_s >= 0.5 && planned > done) {
    const double left = elapsed_s / done * (planned - done);
    text += left < 1.0 ? AnalysisService::tr(", less than a second left")
                       : AnalysisService::tr(", about %1 s left").arg(qRound(left));
  }
  return text;
}

}  // namespace pb::ui
