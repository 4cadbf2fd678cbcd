// sylva-mpi: one render split across MPI ranks, `mpirun -n N sylva-mpi SCENE -o OUT.exr`.
//
// A separate binary rather than `sylva render --mpi`: linking MPI into `sylva` would make every
// use of the everyday command (tests, compare, tree export) load libmpi and, run outside mpirun,
// start an MPI singleton (slow, and noisy where no network is configured); and `sylva` must build
// where OpenMPI is absent. This file is the only one that includes mpi.h.
//
// Every rank loads the scene and builds its BVH. The work is split into --chunks chunks (render/
// chunk.h: by bands of rows or by sample ranges) handed out dynamically: each worker asks rank 0
// for a chunk, renders it, and sends the film back with its next request, so a slow node takes
// fewer chunks. Rank 0 hands out work from its main thread (the only thread that calls MPI) and
// renders chunks itself on a second thread; it assembles the films in chunk order
// (ChunkAssembler) — bit-identical to a single-process render for any N — and writes the EXR and
// PNG. Every chunk it receives is also kept as a partial file in OUT.exr.parts/ (removed on
// success): if a rank dies, mpirun ends the job with a message naming it, and the chunks already
// finished can be merged or completed with `sylva render --chunk i/N` + `sylva merge`.
//
// `sylva-mpi --study STUDY.toml [-o DIR]` renders a detection study's frames over the ranks instead
// (mpi_study.cpp, the only other file that includes mpi.h).

#include "app/mpi/mpi_study.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/output_paths.h"
#include "pipeline/render_call.h"
#include "render/chunk.h"
#include "render/session.h"

#include <fmt/core.h>
#include <mpi.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

namespace sylva {

namespace {

constexpr int kTagWork = 1;    // worker → rank 0: [int32 finished chunk or -1] + film bytes
constexpr int kTagAssign = 2;  // rank 0 → worker: int32 next chunk, or -1: no more work

struct MpiOptions {
  RenderRequest request;
  std::string exr, png;
  std::string split = "tiles";
  int chunks = 0;
  bool denoise = false;
  bool quiet = false;
};

// The chunks not handed out yet, shared by rank 0's coordinator and its own render thread.
class ChunkQueue {
 public:
  explicit ChunkQueue(int count) {
    for (int i = 0; i < count; ++i) queue_.push_back(i);
  }
  int take() {
    std::lock_guard lock(mutex_);
    if (queue_.empty()) return -1;
    const int i = queue_.front();
    queue_.pop_front();
    return i;
  }
  void clear() {
    std::lock_guard lock(mutex_);
    queue_.clear();
  }

 private:
  std::mutex mutex_;
  std::deque<int> queue_;
};

struct Context {
  RenderSettings settings;
  ChunkSplit split;
  int chunks;
  std::string key;
  std::map<std::string, std::string> job_fields;
  std::string chunks_by_rank;  // rank 0's summary: " 3 5 …"
};

Film render_chunk(Renderer& renderer, const Context& ctx, int index) {
  const ChunkWork work =
      chunk_work({index, ctx.chunks, ctx.split}, ctx.settings.width, ctx.settings.height, ctx.settings.spp);
  Film film = renderer.make_film(work.region, work.samples.first);
  renderer.render(film, work.region, work.samples);
  return film;
}

void worker(Renderer& renderer, const Context& ctx) {
  std::string message(sizeof(int32_t), '\0');
  int32_t done = -1;
  while (true) {
    std::memcpy(message.data(), &done, sizeof(done));
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, kTagWork, MPI_COMM_WORLD);
    int32_t next = -1;
    MPI_Recv(&next, 1, MPI_INT32_T, 0, kTagAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (next < 0) return;
    const Film film = render_chunk(renderer, ctx, next);
    std::ostringstream out;
    out.write(reinterpret_cast<const char*>(&next), sizeof(next));
    film.write(out, ctx.key);
    message = std::move(out).str();
    if (message.size() > static_cast<size_t>(INT32_MAX))
      throw Error(fmt::format("chunk {} is larger than one MPI message (2 GiB): use more --chunks", next));
    done = next;
  }
}

// Rank 0's side of the other ranks' work loop: takes each finished chunk (keep(index, film, rank))
// and hands out the next, until every other rank has been told there is none left.
template <typename Keep>
void serve_ranks(ChunkQueue& queue, int ranks, const std::string& key, const Keep& keep) {
  int active = ranks - 1;
  std::vector<char> buffer;
  while (active > 0) {
    int ready = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kTagWork, MPI_COMM_WORLD, &ready, &status);
    if (!ready) {
      // Polling with a sleep: a blocking receive would spin a core that rank 0's renderer needs.
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      continue;
    }
    int bytes = 0;
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    buffer.resize(static_cast<size_t>(bytes));
    MPI_Recv(buffer.data(), bytes, MPI_BYTE, status.MPI_SOURCE, kTagWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    int32_t finished = -1;
    std::memcpy(&finished, buffer.data(), sizeof(finished));
    if (finished >= 0) {
      std::istringstream in(std::string(buffer.begin() + sizeof(int32_t), buffer.end()));
      keep(finished, Film::read(in, key, fmt::format("chunk {} from rank {}", finished, status.MPI_SOURCE)),
           status.MPI_SOURCE);
    }
    const int32_t next = queue.take();
    MPI_Send(&next, 1, MPI_INT32_T, status.MPI_SOURCE, kTagAssign, MPI_COMM_WORLD);
    if (next < 0) --active;
  }
}

// Rank 0: hands out the chunks, renders some itself, and assembles the film in chunk order.
Film coordinator(Renderer& renderer, Context& ctx, const MpiOptions& opt, int ranks) {
  ChunkQueue queue(ctx.chunks);
  const RenderSettings& s = ctx.settings;
  ChunkAssembler assembler(s.width, s.height, renderer.film_channels(), ctx.chunks);
  const std::filesystem::path spool = opt.exr + ".parts";
  std::filesystem::create_directories(spool);
  std::mutex assembler_mutex;
  std::vector<int> chunks_by_rank(static_cast<size_t>(ranks), 0);
  auto keep = [&](int index, Film film, int rank) {
    PartialHeader header{ctx.key, {index, ctx.chunks, ctx.split}, s.spp, ctx.job_fields};
    save_partial(spool / fmt::format("chunk.{}.of.{}.part", index, ctx.chunks), header, film);
    std::lock_guard lock(assembler_mutex);
    assembler.add(index, std::move(film));
    ++chunks_by_rank[static_cast<size_t>(rank)];
  };
  // Rank 0 renders too, on its own thread (which makes no MPI calls).
  std::exception_ptr local_error;
  std::thread local([&] {
    try {
      for (int i = queue.take(); i >= 0; i = queue.take()) keep(i, render_chunk(renderer, ctx, i), 0);
    } catch (...) {
      local_error = std::current_exception();
    }
  });
  // An error here (a foreign film, a failed spool write) must not leave the local thread running:
  // stop handing out chunks, let it finish the one it has, then report.
  try {
    serve_ranks(queue, ranks, ctx.key, keep);
  } catch (...) {
    queue.clear();
    local.join();
    throw;
  }
  local.join();
  if (local_error) std::rethrow_exception(local_error);
  for (int r = 0; r < ranks; ++r) ctx.chunks_by_rank += fmt::format(" {}", chunks_by_rank[static_cast<size_t>(r)]);
  return assembler.film();
}

int run(const MpiOptions& opt, int rank, int ranks) {
  const auto t0 = std::chrono::steady_clock::now();
  RenderCallOptions call;
  call.request = opt.request;
  call.exr = opt.exr;
  call.png = opt.png;
  call.memory_check = false;
  call.denoise = opt.denoise;  // after the merge, on rank 0, as sylva render --denoise does
  // The film is made over the ranks (in place of a session: no checkpoint); rank 0 writes it.
  Context ctx{{}, opt.split == "samples" ? ChunkSplit::samples : ChunkSplit::tiles, 0, {}, {}, {}};
  call.seams.film_source = [&](Renderer& renderer, RenderObserver&) { return coordinator(renderer, ctx, opt, ranks); };
  // Every rank loads the scene and checks the outputs against its inputs, so all fail alike
  // (docs/robustness.md).
  RenderObserver silent;
  const LoadedScene loaded = load_render(call, silent);
  ctx.settings = loaded.job.settings;
  const RenderSettings& s = ctx.settings;
  // Default: 8 chunks per rank (enough to balance uneven ranks), capped by what the split allows.
  ctx.chunks = opt.chunks > 0 ? opt.chunks : std::min(8 * ranks, ctx.split == ChunkSplit::tiles ? s.height : s.spp);
  chunk_work({0, ctx.chunks, ctx.split}, s.width, s.height, s.spp);  // throws if a chunk would be empty
  ctx.key = checkpoint_key(loaded.job.file.content_hash, s);
  ctx.job_fields = describe_job(opt.request, s);
  if (rank != 0) {
    Renderer renderer(loaded.job.file.scene, *loaded.embree, s);
    worker(renderer, ctx);
    return 0;
  }
  const std::filesystem::path spool = opt.exr + ".parts";
  render_loaded(loaded, call, silent);
  std::filesystem::remove_all(spool);
  if (!opt.quiet)
    fmt::print(stderr, "wrote {}: {} chunks by {} over {} ranks (chunks per rank:{}) in {:.2f} s\n", opt.exr,
               ctx.chunks, to_string(ctx.split), ranks, ctx.chunks_by_rank,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

}  // namespace

}  // namespace sylva

int main(int argc, char** argv) {
  sylva::use_huge_pages(argv);
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);

  sylva::MpiOptions opt;
  sylva::RenderRequest& req = opt.request;
  CLI::App app{"sylva-mpi: one render split across MPI ranks (mpirun -n N sylva-mpi SCENE -o OUT.exr)"};
  app.set_version_flag("--version", SYLVA_VERSION);
  app.add_option("scene", req.source.file, "Scene file (TOML); omit for the built-in default scene");
  app.add_option("-o,--output", opt.exr, "Output EXR (written by rank 0); with --study the output folder");
  std::string study;
  app.add_option("--study", study,
                 "Render the frames of a detection study (STUDY.toml, docs/studies.md) over the ranks, handed out one "
                 "at a time, into a folder every rank shares; finished frames are skipped")
      ->excludes("scene");
  app.add_option("--png", opt.png, "PNG preview of the visible band");
  app.add_option("--spp", req.spp, "Samples per pixel")->check(CLI::Range(1, 1 << 24));
  app.add_option("--res", req.res, "Resolution WIDTHxHEIGHT");
  app.add_option("--threads", req.threads, "Worker threads per rank (0 = all)")->check(CLI::Range(0, 4096));
  app.add_option("--seed", req.seed, "Random seed")->check(CLI::Range(int64_t{0}, INT64_MAX));
  app.add_option("--bands", req.bands, "Comma-separated bands, e.g. rgb,nir,S2A_B8");
  app.add_option("--max-depth", req.max_depth, "Maximum path depth")->check(CLI::Range(1, 1024));
  app.add_option("--quantity", req.quantity, "Band channels as radiance or reflectance (factor)")
      ->check(CLI::IsMember({"radiance", "reflectance"}));
  app.add_option("--isa", req.isa, "Embree's kernels, at most (as sylva render --isa; default avx2)")
      ->check(CLI::IsMember(sylva::embree_isa_names()));
  app.add_option("--split", opt.split, "Chunks are bands of rows (tiles, default) or sample ranges (samples)")
      ->check(CLI::IsMember({"samples", "tiles"}));
  app.add_option("--chunks", opt.chunks, "Number of chunks handed out (default: 8 per rank)")
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--set", req.overrides, "Override a key of the scene file: SECTION.KEY=VALUE (repeatable)")
      ->allow_extra_args(false);
  app.add_flag("--features", req.features,
               "Also write the denoiser's features and half-buffers (feature.*, even.*, odd.*; docs/denoise.md)");
  app.add_flag("--denoise", opt.denoise,
               "Denoise the merged image (implies --features): the beauty denoised, the noisy one kept as noisy.*");
  app.add_flag("-q,--quiet", opt.quiet, "No summary");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Every rank parsed the same arguments; rank 0 speaks for them.
    const int code = rank == 0 ? app.exit(e) : e.get_exit_code();
    MPI_Finalize();
    return code == 0 ? 0 : 2;
  }
  if (study.empty() && opt.exr.empty()) {
    if (rank == 0) fmt::print(stderr, "sylva-mpi: --output is required (the EXR, or with --study the folder)\n");
    MPI_Finalize();
    return 2;
  }
  try {
    if (!study.empty())
      sylva::run_study_over_ranks({study, opt.exr, req.threads, opt.quiet}, rank, ranks);
    else
      sylva::run(opt, rank, ranks);
  } catch (const std::exception& e) {
    fmt::print(stderr, "sylva-mpi: rank {} of {}: {}\n", rank, ranks, e.what());
    MPI_Abort(MPI_COMM_WORLD, 2);  // the other ranks would wait for this one forever
  }
  MPI_Finalize();
  return 0;
}
