// SPDX-License-Identifier: MIT
// The MuJoCo 2.2.2 engine, guarded: RAII for models and data, MJCF compiled from memory, engine
// errors turned into values in the calling thread, the box-box phantom-contact filter, and the
// checks that turn MuJoCo's silent failures (buffer overflow, NaN resets) into a reason.
// Facts behind each guard: core/README.md, "MuJoCo 2.2.2 facts the code relies on".
#pragma once

#include <mujoco/mujoco.h>

#include <cstddef>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/base/diagnostic.hpp"

namespace pb {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

/// Box-box contacts deeper than this are MuJoCo 2.2.2's phantom contacts (real ones here are
/// <= 3 mm deep, phantom ones 1 cm to 1 m) and are dropped.
inline constexpr double kPhantomContactDepth = 0.01;
/// So is one deeper than its two boxes overlap along its normal, by more than this (rounding):
/// no real contact can be (phantom ones of a few millimetres come at a face's edge).
inline constexpr double kPhantomContactSlack = 1e-4;

/// Installs, once per process and before any other MuJoCo call of the core: the error handler
/// (an engine error unwinds to the guarded call in the calling thread instead of exiting the
/// process), the warning handler (records the text per thread instead of printing), and the
/// box-box depth filter. Every function below calls it; calling it again is free.
void init_engine();

/// How many box-box contacts the filter has dropped in this process (for tests and diagnostics).
long long phantom_contacts_dropped();

/// An engine error raised inside MuJoCo (mju_error). Caught by guarded(); never leaves the core.
struct EngineError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Compiles MJCF text from memory (through a virtual file system; no temporary files).
Result<ModelPtr> compile_mjcf(std::string_view xml);

/// A fresh mjData for `model`, or the engine's error (e.g. its stack does not fit). Where the
/// model solves primal (not PGS, no noslip pass) the buffer's span of the dual solvers' njmax x
/// njmax matrix and its indices, which such a solve never reads, is one 2 MB block of memory
/// mapped over and over (engine.cpp: dual_matrix_span): most of a large load's mjData, so it
/// costs neither the memory nor the time to fault it in. A model whose solver is later switched
/// to PGS or given a noslip pass needs data made again.
Result<DataPtr> make_data(const mjModel* model);

/// The block of memory make_data maps a primal model's dual-solver span onto, bytes.
inline constexpr std::size_t kSharedSpanBytes = std::size_t{2} << 20;

/// Of `data`'s buffer, the bytes that make_data mapped onto shared memory beyond the one block it
/// takes: what its nbuffer overstates its resident memory by (0 for data made otherwise).
std::size_t shared_data_bytes(const mjData* data);

/// mj_resetData, except that it leaves make_data's shared span alone: mj_resetData would write
/// all of it, faulting every page of it in again (and counting each in the resident set).
void reset_data(const mjModel* model, mjData* data);

/// Runs `fn` and returns the engine's error message if MuJoCo raised one (the data it was using
/// must then be reset before reuse: MuJoCo leaves its stack pointer raised).
template <class F>
std::optional<std::string> guarded(F&& fn) {
  init_engine();
  try {
    fn();
  } catch (const EngineError& e) {
    return std::string("MuJoCo error: ") + e.what();
  }
  return std::nullopt;
}

/// Why the data can no longer be trusted, or nullopt: any contact or constraint buffer overflow,
/// a bad (NaN or huge) qpos, qvel, qacc or ctrl (MuJoCo silently resets the data after those), a
/// near-singular inertia, or a non-finite state. Checked after every run of steps. The reason
/// carries no time: after a divergence MuJoCo has already reset the clock, so callers add theirs.
std::optional<std::string> instability_reason(const mjModel* model, const mjData* data);
/// Whether a failure came from a contact or constraint buffer that overflowed (the words
/// instability_reason uses) or from MuJoCo's stack running out: a scene sized too small for what
/// happened, which larger buffers cure.
bool mentions_buffer_overflow(const Diagnostics& diagnostics);

/// The last warning text MuJoCo raised in this thread ("" if none). MuJoCo 2.2.2 formats warnings
/// in one static buffer, so under concurrent warnings the text may be garbled; decisions use the
/// per-mjData counters (instability_reason), never this text.
std::string last_engine_warning();

}  // namespace pb
