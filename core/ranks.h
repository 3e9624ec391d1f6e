// The processes of one gearmc job (MPI, Message Passing Interface standard 3.1): started by
// `mpirun -n K`, gearmc runs as K ranks that split the Monte-Carlo work into contiguous blocks
// and send their partial results to rank 0, which merges them in a fixed order and alone writes
// the outputs. Started without mpirun, gearmc is one process and never touches MPI.
//
// Every exchange here is collective (all ranks call it in the same order) and carries each rank's
// status: when the work of any rank threw, every rank throws the error of the lowest failing rank
// (an InputError stays an InputError with the same message), so all ranks end with the same exit
// code and only rank 0 prints it. Payloads are opaque bytes (core/bytes.h); messages of any
// size are sent in pieces of at most 1 GiB.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace gearmc {

class Ranks {
 public:
  // The single process (rank 0 of 1), without MPI.
  Ranks() = default;
  // The ranks of MPI's world communicator; MpiSession must be alive.
  static Ranks world();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_root() const { return rank_ == 0; }

  // The contiguous share [begin, end) of `n` items (blocks, grid points) of rank `r`: item i goes
  // to the rank r with begin(r) <= i < end(r), begin(r) = floor(r n / size). Shares differ by at
  // most one item and follow the item order.
  struct Share {
    std::uint64_t begin = 0, end = 0;
  };
  static Share share_of(std::uint64_t n, int r, int size);
  Share share(std::uint64_t n, int r) const { return share_of(n, r, size_); }
  Share share(std::uint64_t n) const { return share_of(n, rank_, size_); }

  // A binary-tree reduction toward rank 0 that keeps the rank order: every rank runs `work`;
  // then at steps s = 1, 2, 4, … rank r with r mod 2s = s sends serialize() (its state, covering
  // the ranks [r, r + s) by then) to rank r − s, which passes it to absorb(); so a rank absorbs
  // the states of the ranks right after its own range, in increasing order, and rank 0 ends with
  // the state of all ranks after ceil(log2 size) steps (not size − 1 sequential receives). An
  // error on any rank (in work, serialize or absorb) is thrown on every rank (the lowest failing
  // rank's).
  void reduce_to_root(const std::function<void()>& work,
                      const std::function<std::string()>& serialize,
                      const std::function<void(std::string_view)>& absorb) const;

  // Runs `work` on every rank; when it threw on any rank, throws that error on every rank (the
  // lowest failing rank's). For set-up steps that only some ranks do (rank 0 opens the output
  // folder) before work that all ranks do.
  void agree(const std::function<void()>& work) const;

  // Each rank's bytes from `produce`, on rank 0 in rank order (other ranks get an empty vector).
  std::vector<std::string> gather(const std::function<std::string()>& produce) const;
  // Same, on every rank.
  std::vector<std::string> all_gather(const std::function<std::string()>& produce) const;

 private:
  Ranks(int rank, int size) : rank_(rank), size_(size) {}
  int rank_ = 0, size_ = 1;
};

// MPI_Init / MPI_Finalize around main(), only when the process was started by an MPI launcher
// (mpirun/mpiexec set OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_SIZE); otherwise nothing.
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  // Whether MPI was initialised by this session.
  static bool active();
};

}  // namespace gearmc
