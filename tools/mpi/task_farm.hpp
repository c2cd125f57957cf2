#pragma once
/// @file task_farm.hpp
/// Dynamic hand-out of numbered tasks over the ranks of an MPI job: rank 0 gives the next task
/// to whichever rank asks (and runs tasks itself on a second thread); each rank returns its
/// result bytes with its next request. Used by `build` (task = block of trials) and `dataset`
/// (task = one map). Only rank 0's main thread calls MPI (MPI_THREAD_FUNNELED).

#include <cstdint>
#include <functional>
#include <string>

#include "mpi_common.hpp"

namespace taskmap::cli {

/// What the farm does with tasks. next/accept/tick are called on rank 0's main thread only;
/// run on every rank (on rank 0 from a second thread, concurrently with the others).
struct FarmTasks {
  /// Rank 0: the next task to hand out; false when there is none (now or ever: the farm ends
  /// once no task is running and next() says false).
  std::function<bool(std::uint64_t* task)> next;
  /// Runs one task, returns its result.
  std::function<std::string(std::uint64_t task)> run;
  /// Rank 0: a finished task's result (in completion order).
  std::function<void(std::uint64_t task, std::string result)> accept;
  /// Rank 0: called about every 250 ms and once at the end (progress); may be empty.
  std::function<void()> tick;
};

/// Collective: runs tasks until rank 0's next() has nothing more and every task handed out has
/// come back. Exceptions from run/accept propagate (the caller aborts the job).
/// Test hook: TASKMAP_MPI_FAULT="<rank>:<n>" makes that rank (not 0) kill itself with SIGKILL
/// when handed its (n+1)-th task, as a crashed node would.
void runFarm(const MpiWorld& world, const FarmTasks& tasks);

}  // namespace taskmap::cli
