// SPDX-License-Identifier: MIT
// The console's one door to the physics core: every core call runs on a worker thread, in the
// order it was asked for, and its result comes back to the GUI thread as an immutable value.
#pragma once

#include <QObject>
#include <QString>
#include <QThreadPool>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>

#include "core/analysis/analyzer.hpp"

namespace pb::ui {

/// Identifies one request to the service; never 0.
using RequestId = quint64;
/// Results shared between panels without copies; nobody may change them.
using SolvePtr = std::shared_ptr<const pb::Solve>;
using EnvelopePtr = std::shared_ptr<const pb::Envelope>;
using FailureMapPtr = std::shared_ptr<const pb::FailureMap>;

/// Runs pb::Analyzer calls on one worker thread of a private QThreadPool (the Analyzer is not
/// thread-safe, so requests run one at a time, in order, and share its cache). The GUI thread
/// never waits on the core.
///
/// Every request gets a non-zero id and ends with exactly one of analyzed / envelopeReady /
/// solved, failed, or cancelled; progress() reports what the worker is doing meanwhile. All of
/// these are emitted on the service's (GUI) thread. A cancelled request's result is dropped; a
/// request that has not started is skipped, and one that is running is stopped inside the
/// simulation it is stepping (core/base/cancel.hpp: within a step of every probe of a search or a
/// map), so the worker is free for the next request at once.
class AnalysisService : public QObject {
  Q_OBJECT

 public:
  explicit AnalysisService(pb::AnalyzerOptions options = {}, QObject* parent = nullptr);
  /// The options its Analyzer was made with (fixed for the service's life).
  const pb::AnalyzerOptions& options() const { return _analyzer->options(); }
  /// Cancels every request and waits for the core call that is running, if any, to end.
  ~AnalysisService() override;

  /// The SafetyResult of a pallet (cached by the Analyzer). Ends with analyzed() or failed().
  RequestId analyze(const pb::PalletConfig& config);
  /// The envelope with its probes. Ends with envelopeReady() or failed().
  RequestId envelope(const pb::PalletConfig& config);
  /// One profile from rest, with its replay. Ends with solved(), or failed() if the run was
  /// numerically unstable (an unstable run has no verdict to show).
  RequestId solve(const pb::PalletConfig& config, const pb::ConveyorProfile& profile,
                  double replay_hz = 30.0);

  /// The speed x start-up-acceleration failure map (one batched call over `options.threads`
  /// workers). Ends with failureMapReady() or failed(). A map of the same pallet (fingerprint) and
  /// grid computed before is answered from the service's cache, without simulating.
  RequestId failureMap(const pb::PalletConfig& config, const pb::MapOptions& options = {});

  /// Drops the request's result; it ends with cancelled(). Unknown or finished ids are ignored.
  void cancel(RequestId id);
  /// Cancels every request not yet ended.
  void cancelAll();
  /// Number of requests not yet ended (queued or running).
  int pendingCount() const { return static_cast<int>(_pending.size()); }

 signals:
  /// The worker moved on to `step` ("Compiling and settling the pallet", ...).
  void progress(pb::ui::RequestId id, const QString& step);
  /// Simulations of the running request that have ended, of those planned: `exact` for a failure
  /// map (its cells), an estimate for a search (pb::Analyzer::set_progress).
  void counted(pb::ui::RequestId id, int done, int planned, bool exact);
  /// One limit of the running request's envelope search (start-up, stop or curve), as soon as its
  /// search ended: before analyzed() or envelopeReady() (pb::Analyzer::set_axis_found).
  void axisFound(pb::ui::RequestId id, pb::Axis axis, const pb::AxisLimit& limit);
  void analyzed(pb::ui::RequestId id, const pb::SafetyResult& result);
  void envelopeReady(pb::ui::RequestId id, const pb::ui::EnvelopePtr& envelope);
  void solved(pb::ui::RequestId id, const pb::ui::SolvePtr& solve);
  void failureMapReady(pb::ui::RequestId id, const pb::ui::FailureMapPtr& map);
  /// The core refused the input, or the engine failed or went unstable: `message` says what to
  /// change, for a person.
  void failed(pb::ui::RequestId id, const QString& message);
  void cancelled(pb::ui::RequestId id);

 private:
  /// Work done on the worker thread; returns what to run back on the GUI thread.
  using Job = std::function<std::function<void()>(pb::Analyzer&, RequestId)>;
  RequestId submit(Job job);
  /// Runs on the GUI thread: emits the request's end unless it was cancelled meanwhile.
  void finish(RequestId id, const std::function<void()>& emitResult);
  void reportProgress(RequestId id, const QString& step);
  /// From any thread: runs `emitFor(id)` on the GUI thread for the request running now, if it has
  /// not ended by then.
  void queueForRunning(const std::function<void(RequestId)>& emitFor);
  /// From the threads that run simulations: queues counted() for the running request.
  void reportCount(int done, int planned);
  /// From the axis threads: queues axisFound() for the running request.
  void reportAxis(pb::Axis axis, const pb::AxisLimit& limit);
  /// Compiles and settles the pallet (cached by the analyzer): empty if it can be simulated,
  /// otherwise what delivers the failure.
  std::function<void()> prepareOrFail(pb::Analyzer& analyzer, RequestId id,
                                      const pb::PalletConfig& config);

  std::unique_ptr<pb::Analyzer> _analyzer;  ///< used by the worker thread only
  mutable std::mutex _mutex;                ///< guards _cancelled and _running
  std::set<RequestId> _cancelled;
  RequestId _running = 0;                      ///< the request the worker runs now (0: none)
  pb::CancelFlag _stopRunning{false};          ///< set to stop it; the analyzer's runs check it
  std::atomic<bool> _countExact{false};        ///< the running request's plan is exact (a map)
  std::set<RequestId> _pending;                ///< GUI thread only
  std::map<std::string, FailureMapPtr> _maps;  ///< GUI thread only: by pallet and grid
  RequestId _nextId = 1;
  QThreadPool _pool;  ///< declared last: destroyed (and drained) first
};

/// The status line for a running request: "Searching the safe envelope: 5 of about 12
/// simulations, about 3 s left" (the time left once two simulations have ended and half a second
/// has passed: their pace so far times what is left).
QString progressText(const QString& step, int done, int planned, bool exact, double elapsed_s);

}  // namespace pb::ui

Q_DECLARE_METATYPE(pb::SafetyResult)
Q_DECLARE_METATYPE(pb::Axis)
Q_DECLARE_METATYPE(pb::AxisLimit)
Q_DECLARE_METATYPE(pb::ui::SolvePtr)
Q_DECLARE_METATYPE(pb::ui::EnvelopePtr)
Q_DECLARE_METATYPE(pb::ui::FailureMapPtr)
