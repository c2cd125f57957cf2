#include "task_farm.hpp"

#include <mpi.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <limits>
#include <optional>
#include <thread>

#include "taskmap/core/error.hpp"

namespace taskmap::cli {
namespace {

constexpr int kTagResult = 11;  // rank -> 0: u64 task, result bytes (nothing: first request)
constexpr int kTagTask = 12;    // 0 -> rank: u64 task; kStop ends the rank's loop
constexpr std::uint64_t kStop = std::numeric_limits<std::uint64_t>::max();

bool faultNow(int rank, std::uint64_t tasks_done) {
  const char* fault = std::getenv("TASKMAP_MPI_FAULT");
  if (fault == nullptr) return false;
  int r = -1;
  unsigned long long n = 0;
  return std::sscanf(fault, "%d:%llu", &r, &n) == 2 && r == rank && tasks_done == n;
}

void workerLoop(const MpiWorld& world, const FarmTasks& tasks) {
  std::string message;  // u64 task + result; empty on the first request
  for (std::uint64_t done = 0;; ++done) {
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, kTagResult,
             MPI_COMM_WORLD);
    std::uint64_t task = kStop;
    MPI_Recv(&task, 1, MPI_UINT64_T, 0, kTagTask, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (task == kStop) return;
    if (faultNow(world.rank, done)) std::raise(SIGKILL);
    const std::string result = tasks.run(task);
    if (result.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()) - sizeof task)
      throw Error("a task's result exceeds 2 GiB; use smaller blocks (--block-trials)");
    message.assign(reinterpret_cast<const char*>(&task), sizeof task);
    message += result;
  }
}

// Rank 0's loop: local task on a second thread, requests from the other ranks.
class Coordinator {
 public:
  Coordinator(const MpiWorld& world, const FarmTasks& tasks) : world_(world), tasks_(tasks) {}

  void run() {
    auto last_tick = std::chrono::steady_clock::now();
    int active = world_.size - 1;  // ranks not yet told to stop
    for (;;) {
      bool busy = pollLocal();
      busy = serveRank(&active) || busy;
      if (!local_ && active == 0) break;
      const auto now = std::chrono::steady_clock::now();
      if (now - last_tick > std::chrono::milliseconds(250)) {
        if (tasks_.tick) tasks_.tick();
        last_tick = now;
      }
      // Polling every 200 us costs rank 0 a few percent of one core and a waiting rank at most
      // 200 us a block (blocks last tens of milliseconds).
      if (!busy && world_.size > 1) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (tasks_.tick) tasks_.tick();
  }

 private:
  // Collects the local task when finished and starts the next. True when something happened.
  bool pollLocal() {
    bool happened = false;
    if (local_) {
      // Alone, rank 0 has no messages to watch: it waits for its own task (no polling).
      const auto wait =
          world_.size == 1 ? std::chrono::milliseconds(250) : std::chrono::milliseconds(0);
      if (local_->wait_for(wait) != std::future_status::ready) return false;
      std::string result = local_->get();  // rethrows the task's exception
      local_.reset();
      tasks_.accept(local_task_, std::move(result));
      happened = true;
    }
    if (!tasks_.next(&local_task_)) return happened;
    const std::uint64_t task = local_task_;
    local_ = std::async(std::launch::async, [this, task] { return tasks_.run(task); });
    return true;
  }

  // Answers one waiting rank: accepts its result, sends the next task or stop.
  bool serveRank(int* active) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kTagResult, MPI_COMM_WORLD, &flag, &status);
    if (flag == 0) return false;
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::string bytes(static_cast<std::size_t>(count), '\0');
    MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, kTagResult, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    std::uint64_t task = kStop;
    if (bytes.size() >= sizeof task) {
      std::memcpy(&task, bytes.data(), sizeof task);
      tasks_.accept(task, bytes.substr(sizeof task));
    } else if (!bytes.empty()) {
      throw Error("malformed message from rank " + std::to_string(status.MPI_SOURCE));
    }
    if (!tasks_.next(&task)) {
      task = kStop;
      --*active;
    }
    MPI_Send(&task, 1, MPI_UINT64_T, status.MPI_SOURCE, kTagTask, MPI_COMM_WORLD);
    return true;
  }

  const MpiWorld& world_;
  const FarmTasks& tasks_;
  std::optional<std::future<std::string>> local_;
  std::uint64_t local_task_ = 0;
};

}  // namespace

void runFarm(const MpiWorld& world, const FarmTasks& tasks) {
  if (world.rank == 0) {
    Coordinator(world, tasks).run();
  } else {
    workerLoop(world, tasks);
  }
}

}  // namespace taskmap::cli
