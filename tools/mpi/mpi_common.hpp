#pragma once
/// @file mpi_common.hpp
/// The MPI job as taskmap-mpi's commands see it (the only files that include mpi.h are in
/// tools/mpi/; the libraries stay MPI-free).

#include <cstdint>
#include <string>

namespace taskmap::cli {

/// This process's place in MPI_COMM_WORLD.
struct MpiWorld {
  int rank = 0;  ///< 0 is the coordinator
  int size = 1;  ///< number of ranks
};

/// Collective: true when every rank passes an empty `error`. Otherwise the lowest failing rank
/// prints "<label>: error: <its error>" (with its rank when not 0) and every rank gets false.
bool agreeAllOk(const MpiWorld& world, const std::string& error, const std::string& label);

}  // namespace taskmap::cli
