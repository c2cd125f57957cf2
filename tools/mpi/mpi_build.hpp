#pragma once
/// @file mpi_build.hpp
/// `taskmap-mpi build`: the map of `taskmap build`, built by every rank of an MPI job.

#include <cstdint>

#include "build_command.hpp"
#include "mpi_common.hpp"

namespace taskmap::cli {

/// Collective over MPI_COMM_WORLD. Rank 0 writes args.output (and the checkpoint
/// args.output + ".ckpt" while it runs). Returns the exit code; throws Error on rank 0's
/// failures after set-up (the caller aborts the job).
/// @param block_trials trials per block handed to a rank (>= 1); changes neither the map nor
/// anything stored, only the checkpoint's granularity.
int runMpiBuild(const MpiWorld& world, const BuildArgs& args, std::uint64_t block_trials);

}  // namespace taskmap::cli
