// MPI for `mpirun -np K slidespec ...`: built only with -DSLIDESPEC_MPI=ON.
#pragma once

#include <string>
#include <vector>

#include "slidespec/run.hpp"

namespace slidespec::cli {

/// MPI_COMM_WORLD for the life of the process: initialised on construction, finalised on
/// destruction. Runs spread every chunk of realizations over its ranks (RunSession).
class MpiWorld final : public Communicator {
 public:
  MpiWorld(int& argc, char**& argv);
  ~MpiWorld() override;
  MpiWorld(const MpiWorld&) = delete;
  MpiWorld& operator=(const MpiWorld&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::string> all_gather(const std::string& mine) const override;
  bool any(bool mine) const override;
  /// Ranks on this machine: the cores are shared among them.
  int ranks_on_this_node() const { return local_size_; }
  /// Ends every rank: for a failure on one rank that the others cannot see.
  [[noreturn]] void abort(int status) const;

 private:
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

}  // namespace slidespec::cli
