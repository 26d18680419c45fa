// MPI behind render/ranks.h; without BUNDLEPATH_HAS_MPI one rank, whose collectives do nothing.
#include "render/ranks.h"

#include "render/render_spec.h"

#include <algorithm>
#include <cstdlib>

#ifdef BUNDLEPATH_HAS_MPI
#include <mpi.h>
#endif

namespace bp {
namespace {

// The number of processes an MPI launcher started (Open MPI, MPICH/Hydra and PMIx launchers such as
// srun say so in the environment); 0: not started by one.
int launched_ranks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) return std::max(1, std::atoi(value));
  return std::getenv("PMIX_RANK") ? 1 : 0;
}

}  // namespace

int launched_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  return 0;
}

std::string mpi_library() {
#ifdef BUNDLEPATH_HAS_MPI
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(text, &length);  // callable before MPI_Init
  const std::string version(text, std::size_t(std::max(length, 0)));
  return version.substr(0, version.find_first_of(",\n"));
#else
  return "";
#endif
}

#ifdef BUNDLEPATH_HAS_MPI

void Ranks::sum_to_root(std::vector<double>& values) const {
  if (size_ == 1) return;
  MPI_Reduce(root() ? MPI_IN_PLACE : values.data(), values.data(), int(values.size()), MPI_DOUBLE, MPI_SUM, 0,
             MPI_COMM_WORLD);
}

void Ranks::sum_to_root(std::vector<std::uint64_t>& values) const {
  if (size_ == 1) return;
  MPI_Reduce(root() ? MPI_IN_PLACE : values.data(), values.data(), int(values.size()), MPI_UINT64_T, MPI_SUM, 0,
             MPI_COMM_WORLD);
}

void Ranks::wait_for_all() const {
  if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
}

int Ranks::max_over_ranks(int value) const {
  if (size_ == 1) return value;
  int out = value;
  MPI_Allreduce(&value, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

void Ranks::broadcast_bytes(void* data, std::size_t bytes) const {
  if (size_ > 1) MPI_Bcast(data, int(bytes), MPI_BYTE, 0, MPI_COMM_WORLD);
}

std::string Ranks::first_failure(const std::string& failure) const {
  if (size_ == 1) return failure;
  // The lowest failing rank: the largest of size - rank over the failing ones.
  const int failing = max_over_ranks(failure.empty() ? 0 : size_ - rank_);
  if (failing == 0) return "";
  const int from = size_ - failing;
  std::string text = rank_ == from ? "rank " + std::to_string(rank_) + ": " + failure : "";
  int length = int(text.size());
  MPI_Bcast(&length, 1, MPI_INT, from, MPI_COMM_WORLD);
  text.resize(std::size_t(length));
  MPI_Bcast(text.data(), length, MPI_CHAR, from, MPI_COMM_WORLD);
  return text;
}

RankSession::RankSession() {
  if (launched_ranks() == 0) return;
  int provided = 0;
  // Only the main thread calls MPI (a render's device threads never do).
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  joined_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &ranks_.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks_.size_);
}

RankSession::~RankSession() {
  if (joined_) MPI_Finalize();
}

void RankSession::abort(int exit_code) const {
  if (joined_ && ranks_.size() > 1) MPI_Abort(MPI_COMM_WORLD, exit_code);
  std::exit(exit_code);
}

#else  // one rank

void Ranks::sum_to_root(std::vector<double>&) const {}
void Ranks::sum_to_root(std::vector<std::uint64_t>&) const {}
void Ranks::wait_for_all() const {}
int Ranks::max_over_ranks(int value) const { return value; }
void Ranks::broadcast_bytes(void*, std::size_t) const {}
std::string Ranks::first_failure(const std::string& failure) const { return failure; }

RankSession::RankSession() {
  if (launched_ranks() > 1)
    throw UsageError("this bundlepath was built without MPI, so it cannot render on " +
                     std::to_string(launched_ranks()) + " ranks (install libopenmpi-dev and rebuild)");
}

RankSession::~RankSession() = default;

void RankSession::abort(int exit_code) const { std::exit(exit_code); }

#endif

}  // namespace bp
