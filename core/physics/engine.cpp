// SPDX-License-Identifier: MIT
#include "core/physics/engine.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include <mujoco/mjxmacro.h>

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

// How far boxes g1 and g2 overlap along the unit vector n: the sum of their extents along n less
// the distance of their centres along it (the separating-axis test's overlap). No contact of theirs
// with normal n can be deeper: moving one box that far along n parts them.
double box_overlap_along(const mjModel* m, const mjData* d, int g1, int g2, const mjtNum* n) {
  double extent = 0.0;
  for (const int g : {g1, g2}) {
    const mjtNum* axes = d->geom_xmat + 9 * g;  // row-major: box axis k is column k
    for (int k = 0; k < 3; ++k) {
      extent += m->geom_size[3 * g + k] *
                std::abs(axes[k] * n[0] + axes[3 + k] * n[1] + axes[6 + k] * n[2]);
    }
  }
  const mjtNum* p1 = d->geom_xpos + 3 * g1;
  const mjtNum* p2 = d->geom_xpos + 3 * g2;
  return extent -
         std::abs((p2[0] - p1[0]) * n[0] + (p2[1] - p1[1]) * n[1] + (p2[2] - p1[2]) * n[2]);
}

// MuJoCo 2.2.2's box-box collider can emit contacts far deeper than its boxes overlap between
// aligned stacked boxes (fixed upstream in 2026, google-deepmind/mujoco#3476): -3 cm to -1 m, and
// at a face's edge a few millimetres (a 96-carton column's settle: -9.3 mm between two cartons
// 0.03 mm into each other, which kicked the stack at 0.1 m/s). Drop a contact deeper than the cut
// or than the boxes' overlap along its normal (kPhantomContactSlack of rounding allowed).
int filtered_box_box(const mjModel* m, const mjData* d, mjContact* con, int g1, int g2,
                     mjtNum margin) {
  const int n = g_box_box(m, d, con, g1, g2, margin);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    const double depth = -con[i].dist;
    if (depth > kPhantomContactDepth ||
        (depth > kPhantomContactSlack &&
         depth > box_overlap_along(m, d, g1, g2, con[i].frame) + kPhantomContactSlack)) {
      g_phantoms_dropped.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (kept != i) con[kept] = con[i];
    ++kept;
  }
  return kept;
}

// MuJoCo 2.2.2's mjData holds, for its dual solvers (PGS, and the noslip pass), the njmax x njmax
// matrix A R = J M^-1 J' + R and its column indices: 12 njmax^2 bytes, most of a large load's
// mjData (210 of the 258 MB buffer of `bench scale`'s 96-carton brick). A primal solve (CG, Newton,
// ours) never reads or writes them (engine_core_constraint.c: mj_projectConstraint returns unless
// mj_isDual); only mj_resetData's memset and mj_copyData's memcpy touch them. So for a model that
// solves primal, make_data maps the buffer's span of those two arrays onto one small block of
// shared memory, over and over: the memset writes the same few pages again instead of faulting in
// hundreds of MB (first touch of fresh memory cost 0.3-2.4 s per 272 MB on this VM, clear_page 20 %
// of a brick 96 envelope), and the span's resident memory is kSharedSpanBytes. Each span is one
// anonymous memory file mapped ceil(span / kSharedSpanBytes) times; engine_free recognises the
// buffer and unmaps it.

struct DualMatrixSpan {
  std::size_t buffer_bytes = 0;    ///< the mjData buffer's size (mj_makeData asks for exactly this)
  std::size_t begin = 0, end = 0;  ///< efc_AR_colind's start and efc_AR's end in it
};

// The span of efc_AR_colind and efc_AR in an mjData buffer of `m`, laid out as engine_io.c lays
// it: mjxmacro.h's order, each array at the next 64-byte boundary.
DualMatrixSpan dual_matrix_span(const mjModel* m) {
  DualMatrixSpan span;
  std::size_t offset = 0;
  MJDATA_POINTERS_PREAMBLE(m)
#define X(type, name, nr, nc)                                                 \
  offset += (64 - offset % 64) % 64;                                          \
  if (std::strcmp(#name, "efc_AR_colind") == 0) span.begin = offset;          \
  offset += sizeof(type) * static_cast<std::size_t>(m->nr) * std::size_t(nc); \
  if (std::strcmp(#name, "efc_AR") == 0) span.end = offset;
  MJDATA_POINTERS
#undef X
  span.buffer_bytes = offset;
  return span;
}

bool solves_dual(const mjModel* m) {
  return m->opt.solver == mjSOL_PGS || m->opt.noslip_iterations > 0;
}

// The span make_data asks engine_malloc to share in the buffer it is about to allocate.
thread_local std::optional<DualMatrixSpan> t_share_span;

struct SharedBlock {
  void* base = nullptr;
  std::size_t bytes = 0;       ///< mapped
  std::size_t lo = 0, hi = 0;  ///< the offsets of the span mapped onto the chunk
};
std::mutex g_shared_mutex;
std::vector<SharedBlock> g_shared_blocks;
std::atomic<int> g_shared_count{0};

// A buffer of span.buffer_bytes whose page-aligned interior of [begin, end) is one chunk of
// shared memory mapped again and again; nullptr if the kernel refuses any step.
void* shared_span_alloc(const DualMatrixSpan& span) {
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  const std::size_t bytes = (span.buffer_bytes + page - 1) / page * page;
  void* base = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (base == MAP_FAILED) return nullptr;
  auto* first = static_cast<char*>(base);
  // The rest of the buffer is not asked for in huge pages, unlike engine_malloc's large blocks:
  // on this VM (Firecracker, its free memory returned to the host) a huge page faulted in afresh
  // cost 1.2-9 ms a MB against 0.7 in 4 KB pages, and on brick 96's envelope the system time went
  // 3.1-3.3 -> 1.0 s without them.
  char* lo = first + (span.begin + page - 1) / page * page;
  char* hi = first + span.end / page * page;
  const int fd = lo < hi ? memfd_create("pb-dual-matrix", MFD_CLOEXEC) : -1;
  bool mapped = fd >= 0 && ftruncate(fd, off_t(kSharedSpanBytes)) == 0;
  // MAP_POPULATE maps each page of the chunk at once rather than on mj_makeData's memset, one
  // fault a page: make_data of r7x10_1 (a 100 MB span) 330 -> 200 ms (session 40).
  for (char* at = lo; mapped && at < hi; at += kSharedSpanBytes) {
    const std::size_t n = std::min(kSharedSpanBytes, std::size_t(hi - at));
    mapped = mmap(at, n, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_FIXED | MAP_POPULATE, fd, 0) !=
             MAP_FAILED;
  }
  if (fd >= 0) close(fd);  // the mappings keep the memory file
  if (!mapped) {
    munmap(base, bytes);
    return nullptr;
  }
  std::lock_guard lock(g_shared_mutex);
  g_shared_blocks.push_back({base, bytes, std::size_t(lo - first), std::size_t(hi - first)});
  g_shared_count.fetch_add(1);
  return base;
}

// MuJoCo's allocator (mju_malloc), with two changes: an mjData buffer make_data asked to share
// (above), and a block of tens of megabytes asked for in huge pages (since the sharing, the buffer
// of a PGS model's data, and a large stack). Before the sharing, a 96-carton column's 380 MB
// buffer took 93,000 page faults, about 1.2 s of system time, to zero in 4 KB pages, and 0.4-0.8 s
// in 2 MB ones (core/README.md, "Where a large load's prepare goes"). Alignment and padding as
// MuJoCo's own (64 bytes); with the kernel's transparent huge pages off, madvise is a no-op.
void* engine_malloc(std::size_t size) {
  if (t_share_span && size == t_share_span->buffer_bytes) {
    const DualMatrixSpan span = *t_share_span;
    t_share_span.reset();
    if (void* block = shared_span_alloc(span)) return block;
  }
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

// The shared block whose buffer starts at `base`, or end(); g_shared_mutex held.
std::vector<SharedBlock>::iterator find_shared(const void* base) {
  return std::find_if(g_shared_blocks.begin(), g_shared_blocks.end(),
                      [&](const SharedBlock& b) { return b.base == base; });
}

std::optional<SharedBlock> shared_block(const void* buffer) {
  if (buffer == nullptr || g_shared_count.load() == 0) return std::nullopt;
  std::lock_guard lock(g_shared_mutex);
  const auto it = find_shared(buffer);
  return it == g_shared_blocks.end() ? std::nullopt : std::optional<SharedBlock>(*it);
}

void engine_free(void* block) {
  if (block != nullptr && g_shared_count.load() > 0) {
    std::lock_guard lock(g_shared_mutex);
    if (const auto it = find_shared(block); it != g_shared_blocks.end()) {
      munmap(it->base, it->bytes);
      g_shared_blocks.erase(it);
      g_shared_count.fetch_sub(1);
      return;
    }
  }
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
  init_engine();
  auto make = [&](const std::optional<DualMatrixSpan>& share) -> Result<DataPtr> {
    t_share_span = share;
    mjData* raw = nullptr;
    auto engine_error = guarded([&] { raw = mj_makeData(model); });
    t_share_span.reset();
    if (engine_error) return Result<DataPtr>::failure("", *engine_error);
    if (raw == nullptr) return Result<DataPtr>::failure("", "MuJoCo could not allocate its data");
    return Result<DataPtr>{DataPtr(raw), {}};
  };
  // The dual solvers' matrix shared where the model never uses it and it is worth a mapping.
  const DualMatrixSpan span = dual_matrix_span(model);
  if (solves_dual(model) || span.end - span.begin < 4 * kSharedSpanBytes) return make(std::nullopt);
  auto data = make(span);
  if (!data) return data;
  mjData* d = data.value->get();
  // The layout is checked, not assumed: had MuJoCo laid the buffer out otherwise, the shared
  // pages would hold other arrays, and the data is made again without them.
  const auto* buffer = static_cast<const char*>(d->buffer);
  if (reinterpret_cast<const char*>(d->efc_AR_colind) != buffer + span.begin ||
      reinterpret_cast<const char*>(d->efc_AR + std::size_t(model->njmax) * model->njmax) !=
          buffer + span.end ||
      std::size_t(d->nbuffer) != span.buffer_bytes) {
    data.value->reset();
    return make(std::nullopt);
  }
  // mj_makeData's memset mapped the chunk in again and again; reset_data never touches the span,
  // so its page-table entries go (the memory file keeps the chunk), and with them the span's
  // count in the resident set.
  if (const std::optional<SharedBlock> b = shared_block(d->buffer)) {
    madvise(static_cast<char*>(b->base) + b->lo, b->hi - b->lo, MADV_DONTNEED);
  }
  return data;
}

std::size_t shared_data_bytes(const mjData* data) {
  const std::optional<SharedBlock> b = shared_block(data->buffer);
  return b ? b->hi - b->lo - std::min(b->hi - b->lo, kSharedSpanBytes) : 0;
}

void reset_data(const mjModel* model, mjData* data) {
  const std::optional<SharedBlock> b = shared_block(data->buffer);
  if (!b) {
    mj_resetData(model, data);
    return;
  }
  // mj_resetData zeroes data->nbuffer bytes of the buffer, then sets its defaults (qpos0, the
  // mocap poses), all in arrays before the shared span: so it is given the buffer up to the span,
  // and the arrays after it are zeroed here. Bit for bit mj_resetData's data outside the span
  // (engine_test).
  const int whole = data->nbuffer;
  data->nbuffer = static_cast<int>(b->lo);
  mj_resetData(model, data);
  data->nbuffer = whole;
  std::memset(static_cast<char*>(data->buffer) + b->hi, 0, std::size_t(whole) - b->hi);
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
