#pragma once
// sylva-mpi --study: the frames of a detection study handed out over MPI ranks (mpi_study.cpp).

#include <filesystem>
#include <string>

namespace sylva {

struct MpiStudyOptions {
  std::string study;                 // the study file
  std::filesystem::path output_dir;  // empty: the study's `output`; shared by every rank
  int threads = 0;                   // per rank, 0 = all
  bool quiet = false;
};

// Every rank calls it (after MPI_Init): rank 0 hands out the frames and renders some, the others ask
// it for frames until none is left. Returns the exit code; throws sylva::Error for bad input.
int run_study_over_ranks(const MpiStudyOptions& options, int rank, int ranks);

}  // namespace sylva
