#pragma once
/// @file mpi_dataset.hpp
/// `taskmap-mpi dataset`: the maps and manifest of `taskmap dataset`, jobs handed out to ranks.

#include "build_command.hpp"
#include "mpi_common.hpp"

namespace taskmap::cli {

/// Collective. Rank 0 plans, skips maps finished earlier, hands out the other jobs largest
/// first (task_farm.hpp) and rewrites DIR/manifest.json as results come in; each rank writes
/// the maps it builds. Returns the exit code (1 when a job failed).
int runMpiDataset(const MpiWorld& world, const DatasetArgs& args);

}  // namespace taskmap::cli
