// sylva-mpi --study: a detection study's frames handed out one at a time over MPI ranks
// (docs/studies.md, "On a cluster"). Every rank plans the same study (pipeline/study.h) and renders
// the frames rank 0 hands it into the output folder, which every rank must share; a frame's bits
// do not depend on the rank that renders it, and finished frames are skipped, so the result is
// that of `sylva study` and running again resumes. As in sylva_mpi.cpp, rank 0's main thread is
// the only one that calls MPI: it answers the other ranks while a second thread renders frames.

#include "app/mpi/mpi_study.h"

#include "pipeline/study.h"

#include <fmt/core.h>
#include <mpi.h>

#include <array>
#include <chrono>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace sylva {

namespace {

constexpr int kTagAsk = 11;    // rank → 0: [frames rendered, frames skipped] so far; asks for a frame
constexpr int kTagFrame = 12;  // 0 → rank: int64 frame index, or -1: no more frames

// The frames not handed out yet: indices in plan order.
class FrameQueue {
 public:
  explicit FrameQueue(size_t count) : count_(count) {}
  std::optional<size_t> take() {
    std::lock_guard lock(mutex_);
    if (next_ >= count_) return std::nullopt;
    return next_++;
  }
  void clear() {
    std::lock_guard lock(mutex_);
    next_ = count_;
  }

 private:
  std::mutex mutex_;
  size_t next_ = 0, count_;
};

// The other ranks' requests until each has been told there is no frame left; their last counts.
std::vector<std::array<int64_t, 2>> serve_frames(FrameQueue& queue, int ranks) {
  std::vector<std::array<int64_t, 2>> counts(static_cast<size_t>(ranks), {0, 0});
  int active = ranks - 1;
  while (active > 0) {
    int ready = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kTagAsk, MPI_COMM_WORLD, &ready, &status);
    if (!ready) {
      // Polling with a sleep: a blocking receive would spin a core that rank 0's frames need.
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      continue;
    }
    std::array<int64_t, 2> done{};
    MPI_Recv(done.data(), 2, MPI_INT64_T, status.MPI_SOURCE, kTagAsk, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    counts[static_cast<size_t>(status.MPI_SOURCE)] = done;
    const std::optional<size_t> frame = queue.take();
    const int64_t next = frame ? static_cast<int64_t>(*frame) : -1;
    MPI_Send(&next, 1, MPI_INT64_T, status.MPI_SOURCE, kTagFrame, MPI_COMM_WORLD);
    if (next < 0) --active;
  }
  return counts;
}

// A worker rank's frames: each asked of rank 0, reporting what this rank has done so far.
std::optional<size_t> ask_for_frame(const std::array<int64_t, 2>& done) {
  MPI_Send(done.data(), 2, MPI_INT64_T, 0, kTagAsk, MPI_COMM_WORLD);
  int64_t next = -1;
  MPI_Recv(&next, 1, MPI_INT64_T, 0, kTagFrame, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return next < 0 ? std::nullopt : std::optional<size_t>(static_cast<size_t>(next));
}

}  // namespace

int run_study_over_ranks(const MpiStudyOptions& opt, int rank, int ranks) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudySpec spec = load_study(opt.study);
  StudyRunOptions run;
  run.output_dir = opt.output_dir;
  run.threads = opt.threads;
  RenderObserver silent;
  if (rank != 0) {
    // Each request reports this rank's frames so far; the last one (answered "none") all of them.
    std::array<int64_t, 2> done{0, 0};  // rendered, skipped
    run.next_frame = [&] { return ask_for_frame(done); };
    run_study(spec, run, silent, [&](const StudyProgress& p) {
      done = {static_cast<int64_t>(p.rendered), static_cast<int64_t>(p.skipped)};
    });
    return 0;
  }
  FrameQueue queue(design_values(spec).size());
  run.next_frame = [&] { return queue.take(); };
  StudyResult local;
  std::exception_ptr local_error;
  std::thread renderer([&] {
    try {
      local = run_study(spec, run, silent);
    } catch (...) {
      local_error = std::current_exception();
    }
  });
  std::vector<std::array<int64_t, 2>> counts;
  try {
    counts = serve_frames(queue, ranks);
  } catch (...) {
    queue.clear();
    renderer.join();
    throw;
  }
  renderer.join();
  if (local_error) std::rethrow_exception(local_error);
  counts[0] = {static_cast<int64_t>(local.rendered), static_cast<int64_t>(local.skipped)};
  if (!opt.quiet) {
    int64_t rendered = 0, skipped = 0;
    std::string per_rank;
    for (const auto& [r, s] : counts) {
      rendered += r;
      skipped += s;
      per_rank += fmt::format(" {}", r);
    }
    fmt::print(
        stderr,
        "sylva-mpi study: {} frames, {} rendered (per rank:{}), {} skipped over {} ranks in {:.1f} s; manifest {}\n",
        local.frames.size(), rendered, per_rank, skipped, ranks,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), local.manifest_json.string());
  }
  return 0;
}

}  // namespace sylva
