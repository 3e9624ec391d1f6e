// MPI point-to-point and broadcast under the collective, status-carrying exchanges of ranks.h.
#include "core/ranks.h"

#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "core/bytes.h"
#include "core/input_error.h"

namespace gearmc {
namespace {

bool g_active = false;

constexpr std::size_t kPiece = std::size_t{1} << 30;  // bytes per MPI message at most
constexpr int kTag = 18;

enum class Status : std::uint8_t { kOk = 0, kInputError = 1, kError = 2 };

// A rank's message: status byte, then payload (ok) or the error text.
std::string run_and_wrap(const std::function<std::string()>& produce) {
  std::string message(1, static_cast<char>(Status::kOk));
  try {
    message += produce();
  } catch (const InputError& e) {
    message.assign(1, static_cast<char>(Status::kInputError));
    message += e.what();
  } catch (const std::exception& e) {
    message.assign(1, static_cast<char>(Status::kError));
    message += e.what();
  }
  return message;
}

void send_bytes(const std::string& bytes, int to) {
  const std::uint64_t n = bytes.size();
  MPI_Send(&n, 1, MPI_UINT64_T, to, kTag, MPI_COMM_WORLD);
  for (std::size_t at = 0; at < bytes.size(); at += kPiece) {
    const std::size_t len = std::min(kPiece, bytes.size() - at);
    MPI_Send(bytes.data() + at, static_cast<int>(len), MPI_BYTE, to, kTag, MPI_COMM_WORLD);
  }
}

std::string receive_bytes(int from) {
  std::uint64_t n = 0;
  MPI_Recv(&n, 1, MPI_UINT64_T, from, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::string bytes(n, '\0');
  for (std::size_t at = 0; at < bytes.size(); at += kPiece) {
    const std::size_t len = std::min(kPiece, bytes.size() - at);
    MPI_Recv(bytes.data() + at, static_cast<int>(len), MPI_BYTE, from, kTag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
  }
  return bytes;
}

void broadcast_bytes(std::string& bytes) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  std::uint64_t n = bytes.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  if (rank != 0) bytes.assign(n, '\0');
  for (std::size_t at = 0; at < bytes.size(); at += kPiece) {
    const std::size_t len = std::min(kPiece, bytes.size() - at);
    MPI_Bcast(bytes.data() + at, static_cast<int>(len), MPI_BYTE, 0, MPI_COMM_WORLD);
  }
}

[[noreturn]] void rethrow(Status status, const std::string& text) {
  if (status == Status::kInputError) throw InputError({}, text);
  throw std::runtime_error(text);
}

}  // namespace

Ranks Ranks::world() {
  if (!g_active) return Ranks();
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return Ranks(rank, size);
}

Ranks::Share Ranks::share_of(std::uint64_t n, int r, int size) {
  // floor(r n / size) without overflow for any n below 2^63 and size below 2^31.
  const auto at = [&](std::uint64_t q) {
    const std::uint64_t k = static_cast<std::uint64_t>(size);
    return (n / k) * q + (n % k) * q / k;
  };
  return {at(static_cast<std::uint64_t>(r)), at(static_cast<std::uint64_t>(r) + 1)};
}

std::vector<std::string> Ranks::gather(const std::function<std::string()>& produce) const {
  std::string mine = run_and_wrap(produce);
  std::vector<std::string> all;
  std::string verdict;  // rank 0's finding, sent to all: status byte + error text
  if (size_ == 1) {
    all.push_back(std::move(mine));
  } else if (rank_ == 0) {
    all.push_back(std::move(mine));
    for (int r = 1; r < size_; ++r) all.push_back(receive_bytes(r));
  } else {
    send_bytes(mine, 0);
  }
  if (rank_ == 0) {
    verdict.assign(1, static_cast<char>(Status::kOk));
    for (const std::string& m : all) {
      if (static_cast<Status>(m[0]) != Status::kOk) {
        verdict = m;
        break;
      }
    }
  }
  if (size_ > 1) broadcast_bytes(verdict);
  const auto status = static_cast<Status>(verdict[0]);
  if (status != Status::kOk) rethrow(status, verdict.substr(1));
  for (std::string& m : all) m.erase(0, 1);
  return all;
}

std::vector<std::string> Ranks::all_gather(const std::function<std::string()>& produce) const {
  std::vector<std::string> all = gather(produce);
  if (size_ == 1) return all;
  std::string packed;
  if (rank_ == 0) {
    ByteWriter w(packed);
    for (const std::string& m : all) w.put_text(m);
  }
  broadcast_bytes(packed);
  if (rank_ != 0) {
    ByteReader r(packed);
    for (int k = 0; k < size_; ++k) all.push_back(r.get_text());
  }
  return all;
}

void Ranks::reduce_to_root(const std::function<void()>& work,
                           const std::function<std::string()>& serialize,
                           const std::function<void(std::string_view)>& absorb) const {
  // The first error met: this rank's, else that of the lowest rank absorbed.
  std::string verdict(1, static_cast<char>(Status::kOk));
  const auto guarded = [&](const std::function<void()>& f) {
    if (static_cast<Status>(verdict[0]) != Status::kOk) return;
    verdict = run_and_wrap([&] {
      f();
      return std::string();
    });
  };
  guarded(work);
  for (int step = 1; step < size_; step *= 2) {
    if (rank_ % (2 * step) == step) {
      std::string message;
      guarded([&] { message = serialize(); });
      send_bytes(static_cast<Status>(verdict[0]) == Status::kOk ? verdict + message : verdict,
                 rank_ - step);
      break;
    }
    if (rank_ + step < size_) {
      const std::string message = receive_bytes(rank_ + step);
      if (static_cast<Status>(verdict[0]) != Status::kOk) continue;  // a lower rank failed
      if (static_cast<Status>(message[0]) != Status::kOk) {
        verdict = message;
        continue;
      }
      guarded([&] { absorb(std::string_view(message).substr(1)); });
    }
  }
  if (size_ > 1) broadcast_bytes(verdict);
  const auto status = static_cast<Status>(verdict[0]);
  if (status != Status::kOk) rethrow(status, verdict.substr(1));
}

void Ranks::agree(const std::function<void()>& work) const {
  gather([&] {
    work();
    return std::string();
  });
}

MpiSession::MpiSession(int* argc, char*** argv) {
  const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr ||
                        std::getenv("PMIX_RANK") != nullptr || std::getenv("PMI_SIZE") != nullptr;
  if (!launched) return;
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_active = true;
}

MpiSession::~MpiSession() {
  if (g_active) MPI_Finalize();
  g_active = false;
}

bool MpiSession::active() { return g_active; }

}  // namespace gearmc
