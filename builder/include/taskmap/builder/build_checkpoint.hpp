#pragma once
/// @file build_checkpoint.hpp
/// Finished blocks of trials of one build, saved beside its output so that a killed build
/// restarts where it stopped. The file starts with the build's identity (buildIdentity); each
/// block follows as one record (length, SHA-256, encodeTrialBlock bytes) appended and flushed
/// as the block arrives, so a kill loses at most the record being written.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "taskmap/builder/trial_block.hpp"

namespace taskmap {

/// A string that differs whenever the trials or the map of a build could differ: the object
/// file's SHA-256, the hand URDF's SHA-256, every stored build parameter (BuildOptions, incl.
/// extra_params_json) and `block_trials`, the trials per checkpointed block.
std::string buildIdentity(const ObjectModel& object, const HandModel& hand,
                          const BuildOptions& options, std::uint64_t block_trials);

/// The checkpoint file of one build.
class BuildCheckpoint {
 public:
  /// Opens (creates) the checkpoint at path for the build `identity` whose grasps have
  /// `joints` joint values. An existing file of the same identity is read: its intact records
  /// are kept (a torn or corrupted tail is dropped, loadNote() says so) and the file is
  /// rewritten with them atomically; a file of another build is replaced. Throws Error naming
  /// the path when it cannot be written.
  BuildCheckpoint(std::string path, std::string identity, std::size_t joints);
  ~BuildCheckpoint();
  BuildCheckpoint(const BuildCheckpoint&) = delete;
  BuildCheckpoint& operator=(const BuildCheckpoint&) = delete;

  /// Blocks read from an earlier run (in file order), moved out.
  std::vector<TrialBlock> takeLoaded();
  /// What opening found: "" for a new checkpoint, else one line for the user.
  const std::string& loadNote() const { return note_; }
  /// Appends one finished block and flushes it to the operating system. Throws Error.
  void append(const TrialBlock& block);
  /// Closes and deletes the file (after the map was written).
  void remove();
  /// The file's path.
  const std::string& path() const { return path_; }

 private:
  void load();
  void writeHeaderAndRecords(const std::vector<std::string>& records);
  std::string path_, identity_, note_;
  std::size_t joints_;
  std::vector<TrialBlock> loaded_;
  std::FILE* file_ = nullptr;
};

}  // namespace taskmap
