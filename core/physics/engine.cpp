// SPDX-License-Identifier: MIT
#include "core/physics/engine.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>

#include <sys/mman.h>

namespace pb {

namespace {

thread_local std::string t_last_warning;
std::atomic<long long> g_phantoms_dropped{0};
mjfCollision g_box_box = nullptr;

[[noreturn]] void on_engine_error(const char* message) {
  throw EngineError(message);
}

void on_engine_warning(const char* message) {
  t_last_warning = message;
}

// MuJoCo 2.2.2's box-box collider can emit contacts of depth -3 cm to -1 m between aligned stacked
// boxes (fixed upstream in 2026, google-deepmind/mujoco#3476). Drop them.
int filtered_box_box(const mjModel* m, const mjData* d, mjContact* con, int g1, int g2,
                     mjtNum margin) {
  const int n = g_box_box(m, d, con, g1, g2, margin);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    if (con[i].dist < -kPhantomContactDepth) {
      g_phantoms_dropped.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (kept != i) con[kept] = con[i];
    ++kept;
  }
  return kept;
}

// MuJoCo's allocator (mju_malloc), with one change: a block of tens of megabytes is asked for in
// huge pages. MuJoCo 2.2.2 zeroes each mjData's whole buffer as it makes it (mj_resetData), and a
// large load's buffer is hundreds of MB (its njmax x njmax efc_AR): a 96-carton column's 380 MB
// took 93,000 page faults, about 1.2 s of system time, to zero in 4 KB pages, and 0.4-0.8 s in 2
// MB ones (core/README.md, "Where a large load's prepare goes"). Alignment and padding as MuJoCo's
// own (64 bytes); with the kernel's transparent huge pages off, madvise is a no-op.
void* engine_malloc(std::size_t size) {
  constexpr std::size_t kHugePage = std::size_t{2} << 20;
  constexpr std::size_t kHugeFrom = 16 * kHugePage;
  if (size >= kHugeFrom) {
    if (size > std::numeric_limits<std::size_t>::max() - kHugePage) return nullptr;
    const std::size_t padded = (size + kHugePage - 1) / kHugePage * kHugePage;
    void* block = std::aligned_alloc(kHugePage, padded);
    if (block != nullptr) madvise(block, padded, MADV_HUGEPAGE);
    return block;
  }
  return std::aligned_alloc(64, (size + 63) / 64 * 64);
}

void engine_free(void* block) {
  std::free(block);
}

struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    std::free(vfs);
  }
};

}  // namespace

void init_engine() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = on_engine_error;
    mju_user_warning = on_engine_warning;
    mju_user_malloc = engine_malloc;
    mju_user_free = engine_free;
    g_box_box = mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX];
    mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX] = filtered_box_box;
  });
}

long long phantom_contacts_dropped() {
  return g_phantoms_dropped.load();
}

std::string last_engine_warning() {
  return t_last_warning;
}

Result<ModelPtr> compile_mjcf(std::string_view xml) {
  init_engine();
  if (xml.empty()) return Result<ModelPtr>::failure("", "the MJCF text is empty");
  // mjVFS is about 2 MB: never on the stack. 2.2.2's mj_deleteFileVFS can loop forever, so the
  // whole VFS is deleted instead.
  std::unique_ptr<mjVFS, VfsDeleter> vfs(static_cast<mjVFS*>(std::malloc(sizeof(mjVFS))));
  if (!vfs) return Result<ModelPtr>::failure("", "out of memory for the MJCF file system");
  constexpr const char* kName = "scene.xml";
  std::optional<std::string> vfs_error = guarded([&] {
    mj_defaultVFS(vfs.get());
    if (mj_makeEmptyFileVFS(vfs.get(), kName, static_cast<int>(xml.size())) != 0) {
      throw EngineError("could not store the MJCF in MuJoCo's file system");
    }
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), kName)], xml.data(), xml.size());
  });
  if (vfs_error) return Result<ModelPtr>::failure("", *vfs_error);
  char error[1024] = "";
  mjModel* raw = nullptr;
  if (auto engine_error =
          guarded([&] { raw = mj_loadXML(kName, vfs.get(), error, sizeof error); })) {
    return Result<ModelPtr>::failure("", *engine_error);
  }
  if (raw == nullptr) {
    return Result<ModelPtr>::failure("",
                                     std::string("MuJoCo could not compile the scene: ") + error);
  }
  return Result<ModelPtr>{ModelPtr(raw), {}};
}

Result<DataPtr> make_data(const mjModel* model) {
  mjData* raw = nullptr;
  if (auto engine_error = guarded([&] { raw = mj_makeData(model); })) {
    return Result<DataPtr>::failure("", *engine_error);
  }
  if (raw == nullptr) return Result<DataPtr>::failure("", "MuJoCo could not allocate its data");
  return Result<DataPtr>{DataPtr(raw), {}};
}

bool mentions_buffer_overflow(const Diagnostics& diagnostics) {
  return std::any_of(diagnostics.begin(), diagnostics.end(), [](const Diagnostic& d) {
    // MuJoCo's own words when its stack (the solver's work arrays) runs out.
    return d.message.find("buffer overflowed") != std::string::npos ||
           d.message.find("Stack overflow") != std::string::npos;
  });
}

std::optional<std::string> instability_reason(const mjModel* m, const mjData* d) {
  struct Check {
    int warning;
    const char* what;
  };
  static constexpr Check kChecks[] = {
      {mjWARN_CONTACTFULL,
       "the contact buffer overflowed (nconmax too small): contacts were dropped"},
      {mjWARN_CNSTRFULL,
       "the constraint buffer overflowed (njmax too small): constraints were dropped"},
      {mjWARN_BADQACC,
       "the accelerations diverged (NaN or > 1e10) and MuJoCo reset the simulation"},
      {mjWARN_BADQVEL, "the velocities diverged (NaN or > 1e10) and MuJoCo reset the simulation"},
      {mjWARN_BADQPOS, "the positions diverged (NaN or > 1e10) and MuJoCo reset the simulation"},
      {mjWARN_BADCTRL, "a control was NaN or huge"},
      {mjWARN_INERTIA, "a body's inertia is (near) singular"},
  };
  for (const auto& c : kChecks) {
    if (d->warning[c.warning].number > 0) {
      return std::string(c.what) + " (" + std::to_string(d->warning[c.warning].number) +
             " time(s))";
    }
  }
  for (int i = 0; i < m->nq; ++i) {
    if (!std::isfinite(d->qpos[i])) return "a position became non-finite";
  }
  for (int i = 0; i < m->nv; ++i) {
    if (!std::isfinite(d->qvel[i])) return "a velocity became non-finite";
  }
  return std::nullopt;
}

}  // namespace pb
