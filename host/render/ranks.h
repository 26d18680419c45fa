// The processes of one render (docs/design.md §8): under mpirun every rank renders its share of the same
// rounds and rank 0 alone writes the files. The only MPI the code base calls is behind this
// interface (ranks.cpp); a build without MPI (no BUNDLEPATH_HAS_MPI) is always one rank.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace bp {

class Ranks {
 public:
  Ranks() = default;  // one process: every collective below leaves its values as they are
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }

  // Every rank's values added into root's, in place there (others keep theirs); as many on each rank.
  void sum_to_root(std::vector<double>& values) const;
  void sum_to_root(std::vector<std::uint64_t>& values) const;
  // Returns once every rank has called it.
  void wait_for_all() const;
  // The largest of every rank's value, on every rank.
  int max_over_ranks(int value) const;
  // Root's value, on every rank.
  template <class T>
  void broadcast(T& value) const {
    static_assert(std::is_trivially_copyable_v<T>);
    broadcast_bytes(&value, sizeof value);
  }
  // "rank K: <its message>" of the lowest rank whose `failure` is not empty, on every rank; empty
  // where none failed.
  std::string first_failure(const std::string& failure) const;

 private:
  friend class RankSession;
  void broadcast_bytes(void* data, std::size_t bytes) const;
  int rank_ = 0, size_ = 1;
};

// This process's rank as the MPI launcher's environment gives it (0 where none started it), known
// before the job is joined: a bad command line is then reported by rank 0 alone.
int launched_rank();

// The MPI library this build renders ranks with ("Open MPI v4.1.4"); empty in a build without MPI.
std::string mpi_library();

// Joins the MPI job when an MPI launcher (mpirun) started this process -- MPI_Init here, MPI_Finalize
// when destroyed -- else one rank. The CLI holds one for the render.
class RankSession {
 public:
  // Throws UsageError when launched on several ranks by a build without MPI (each would render the
  // whole image and write the same files).
  RankSession();
  ~RankSession();
  RankSession(const RankSession&) = delete;
  RankSession& operator=(const RankSession&) = delete;
  const Ranks& ranks() const { return ranks_; }
  // Ends every rank with this exit code (MPI_Abort): for a failure one rank may meet alone, where the
  // others would wait for it in their next collective forever.
  [[noreturn]] void abort(int exit_code) const;

 private:
  Ranks ranks_;
  bool joined_ = false;
};

}  // namespace bp
