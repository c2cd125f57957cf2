#pragma once
/// @file map_file_build.hpp
/// A map build from files to a file: what `taskmap build` (and `taskmap-mpi build`, and Python's
/// `taskmap.build`) do around buildMap. The options are named as the command line's; the hand
/// may be a bundled hand's name ("barrett": dataDir()/hands/barrett/barrett.urdf); the output is
/// written atomically, and only when the build found grasps and was not stopped.

#include <atomic>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// Whether the built grasps are labelled with the physics hold test (validate stage,
/// docs/VALIDATION.md) before the map is written.
enum class HoldValidation {
  kOff,          ///< no labels (default)
  kLabel,        ///< `--validate`: label every stored grasp (/grasps/hold)
  kKeepHolding,  ///< `--validate --keep-holding`: store only the grasps that hold
};

/// A build from an object file and a hand to a map file. Units: metres (the mesh's file units
/// times mesh.scale), frames: the object's.
struct FileBuildOptions {
  /// object mesh file (any format assimp reads), or a bundled object name ("basket")
  std::string object;
  /// hand URDF (read with its <stem>.hand.json sidecar), or a bundled hand name ("barrett")
  std::string hand;
  std::string output;    ///< task map to write (.h5): a new file or an earlier task map
  MeshLoadOptions mesh;  ///< scale (file units -> m), repair and wrap of the object
  /// sampler, valid, trials, seed, threads, friction, cone edges, grasp mode and standoff,
  /// keep_invalid, cluster, hold filter, check_size (`--allow-size` is false);
  /// extra_params_json is set by planFileBuild (the object, scale, hand and repair recorded)
  BuildOptions build;
  bool timestamp = false;  ///< store the current time as created_utc (else SOURCE_DATE_EPOCH)
  HoldValidation validation = HoldValidation::kOff;  ///< label the grasps before writing
  bool force = false;  ///< replace an existing output that is not a task map (never an input)
};

/// A build ready to run: validated options, the resolved object mesh and hand URDF.
struct FileBuildPlan {
  BuildOptions options;   ///< validated, with the inputs in extra_params_json
  std::string object;     ///< the object as a mesh path (bundled names resolved)
  std::string hand_urdf;  ///< the hand as a URDF path (bundled names resolved)
};

/// Validates the options (output directory exists, ranges, mesh repair), resolves the object
/// (a file, or a bundled name; naming the closest files when neither) and the hand, and refuses an
/// output that is an input or not a task map (unless force). Loads nothing. Throws Error naming the
/// option or file.
FileBuildPlan planFileBuild(const FileBuildOptions& options);

/// Refuses a standoff (options.simulation.standoff >= 0) when the grasp mode in force (the
/// option's, else the hand's) is not fingertip. `hand_path` names the hand in the message.
void checkGraspOptions(const BuildOptions& options, const HandModel& hand,
                       const std::string& hand_path);

/// What the physics hold test found (HoldValidation other than kOff).
struct HoldLabels {
  std::size_t tested = 0;    ///< grasps tested
  std::size_t holding = 0;   ///< of them, grasps that hold
  double cpu_seconds = 0.0;  ///< CPU time of the test, s
  std::size_t before = 0;    ///< grasps in the map before kKeepHolding
  std::size_t kept = 0;      ///< grasps stored (== before unless kKeepHolding)
};

/// Labels `map`'s grasps with the physics hold test (the protocol with `build`'s integrator) on
/// `build.threads` threads (0: all cores) and, with kKeepHolding, keeps only those that hold
/// (re-clustered with `build.clustering`). Returns nothing for kOff, and nothing (the map
/// unchanged) when *stop became true during the test (nullptr: never stopped). Throws Error
/// when kKeepHolding keeps no grasp ("nothing written").
std::optional<HoldLabels> labelHolds(HoldValidation validation, const BuildOptions& build,
                                     const HandModel& hand, const std::atomic<bool>* stop,
                                     TaskMapData* map);

/// Result of a file build.
struct FileBuildResult {
  BuildResult build;                     ///< status, message, the map (as written) and timing
  bool written = false;                  ///< the output was written (complete or budget exhausted)
  double write_seconds = 0.0;            ///< writing the map, wall seconds
  std::optional<HoldLabels> validation;  ///< with HoldValidation other than kOff
  int threads = 0;                       ///< worker threads used (buildThreadCount)
};

/// One file build in two steps, so a caller can look at the hand before the trials (the CLI
/// prints its warnings). Holds the output's run lock (`<output>.lock`: a second build of the
/// same output refuses with the holder's PID) from construction to destruction.
class MapFileBuild {
 public:
  /// planFileBuild, then the lock, the hand (and checkGraspOptions). Throws Error.
  explicit MapFileBuild(FileBuildOptions options);
  ~MapFileBuild();
  MapFileBuild(const MapFileBuild&) = delete;
  MapFileBuild& operator=(const MapFileBuild&) = delete;

  const FileBuildOptions& request() const { return request_; }     ///< as given
  const BuildOptions& options() const { return plan_.options; }    ///< validated
  const std::string& handUrdf() const { return plan_.hand_urdf; }  ///< resolved URDF
  const HandModel& hand() const;                                   ///< loaded hand

  /// Loads the object (at most once; unless options.check_size is false, an implausible size
  /// is refused right after the mesh is read, before its repair). Throws Error naming the file.
  const ObjectModel& loadObject();

  /// Loads the object if not yet, builds (control: progress, interval, stop), labels the grasps
  /// when asked, and writes the map unless the build was stopped (kInterrupted) or found no
  /// grasp (kNoGrasps): then nothing is written. Throws Error on failures (nothing written).
  FileBuildResult run(const BuildControl& control = {});

 private:
  struct Impl;
  FileBuildOptions request_;
  FileBuildPlan plan_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace taskmap
