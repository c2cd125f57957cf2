#pragma once
/// @file build_params.hpp
/// The build parameters a map stores (/sampling params_json, mapstore/SCHEMA.md): one
/// definition, written by buildMap and assembleMap and read back by whoever needs the options a
/// map was built with (re-simulation of a planned grasp, reach --map). Every JSON key is named
/// once, in build_params.cpp.

#include <optional>
#include <string>

#include "taskmap/builder/map_builder.hpp"

namespace taskmap {

/// Every build option that can change a map, as stored with it.
///
/// options holds the stored fields; the ones a map does not store (they do not change it:
/// threads, check_size, block_size) keep their defaults. options.sampler.approach_axis is the
/// hand's (palm frame, unit), options.simulation.grasp_mode is always set (the option's, else
/// the hand sidecar's), options.simulation.standoff is the standoff in force for fingertip grasps
/// (metres, resolveStandoff) and the default for palm grasps, and hold_filter holds its defaults
/// when the filter is off (only an enabled filter's parameters are stored).
/// options.extra_params_json holds the keys this struct does not name (a JSON object, keys
/// sorted), e.g. the mesh repair a CLI build records or an import's provenance.
struct BuildParams {
  BuildOptions options;  ///< the stored options (see above)
  std::string object;    ///< the object mesh file as the build was given it ("" = not recorded)
  std::optional<double> scale;  ///< mesh scale, file units to metres (not recorded: nullopt)
  std::string hand;             ///< the hand URDF (path or bundled name) ("" = not recorded)
};

/// The parameters of a build of `hand` with `options` (the inputs object, scale, hand and
/// anything else of options.extra_params_json taken from there). Pure: loads nothing.
BuildParams buildParamsOf(const BuildOptions& options, const HandModel& hand);

/// As the JSON object a map stores (keys sorted, doubles in shortest round-trip form): the same
/// bytes buildMap has always written for the same options.
std::string buildParamsJson(const BuildParams& params);

/// Reads params_json back. Keys a map does not hold keep their defaults (a map of an earlier
/// version, an import); a string that is not a JSON object reads as all defaults. Throws Error
/// naming the key when a value has the wrong type or an unknown name ("the map's build parameter
/// 'sampler' ...").
BuildParams buildParamsFromJson(const std::string& json);

}  // namespace taskmap
