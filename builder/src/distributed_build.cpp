// A map build spread over processes, without the transport (builder/distributed_build.hpp).
#include "taskmap/builder/distributed_build.hpp"

#include <algorithm>
#include <chrono>

#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {

BuildRank::BuildRank(const FileBuildOptions& options, bool coordinator)
    : request_(options), plan_(planFileBuild(options)) {
  if (coordinator) lock_.emplace(options.output + ".lock", "output '" + options.output + "'");
  object_ = std::make_unique<ObjectModel>(ObjectModel::load(plan_.object, options.mesh));
  hand_ = std::make_unique<HandModel>(HandModel::load(plan_.hand_urdf));
  checkGraspOptions(plan_.options, *hand_, plan_.hand_urdf);
  runner_ = std::make_unique<TrialRunner>(*object_, *hand_, plan_.options);
  // The map records the sampler the trials ran, and the checkpoint's identity reads it.
  plan_.options.sampler.kind = runner_->samplerChoice().kind;
}

std::string BuildRank::runBlock(std::uint64_t b, std::uint64_t block_trials) const {
  const std::uint64_t first = b * block_trials;
  const std::uint64_t last = std::min(first + block_trials, plan_.options.max_trials);
  TrialBlock block;
  runner_->run(first, last, &block);
  return encodeTrialBlock(block);
}

DistributedBuild::DistributedBuild(const BuildRank& rank, std::uint64_t block_trials)
    : rank_(rank),
      ledger_(rank.plan().options.max_trials, block_trials, rank.plan().options.valid_target),
      checkpoint_(rank.request().output + ".ckpt",
                  buildIdentity(rank.object(), rank.hand(), rank.plan().options, block_trials),
                  rank.hand().jointNames().size()) {
  for (TrialBlock& b : checkpoint_.takeLoaded()) resumed_ += ledger_.record(std::move(b)) ? 1 : 0;
}

void DistributedBuild::accept(std::uint64_t b, const std::string& bytes) {
  TrialBlock block = decodeTrialBlock(bytes, rank_.hand().jointNames().size(),
                                      "result of block " + std::to_string(b));
  if (block.first != ledger_.blockFirst(b) || !ledger_.fits(block))
    throw Error("internal: block " + std::to_string(b) + " came back with other trials");
  simulated_ += block.trials.size();
  checkpoint_.append(block);
  ledger_.record(std::move(block));
}

BuildProgress DistributedBuild::progress(double elapsed_seconds) const {
  BuildProgress p;
  p.trials_done = ledger_.trialsDone();
  p.valid_found = ledger_.validFound();
  p.valid_target = rank_.plan().options.valid_target;
  p.max_trials = rank_.plan().options.max_trials;
  p.elapsed_seconds = elapsed_seconds;
  p.blocks_done = ledger_.blocksDone();
  p.blocks_total = ledger_.blockCount();
  return p;
}

FileBuildResult DistributedBuild::finish(const BuildTiming& timing) {
  const BuildOptions& options = rank_.plan().options;
  FileBuildResult r;
  r.threads = buildThreadCount(options.threads);
  r.build = assembleMap(rank_.object(), rank_.hand(), options, ledger_.takePrefix(), false, timing);
  r.build.sampler_choice = rank_.samplerChoice();
  if (r.build.status == BuildStatus::kNoGrasps) {
    checkpoint_.remove();
    return r;
  }
  if (rank_.request().timestamp) r.build.map.created_utc = mapCreationTime(true);
  r.validation =
      labelHolds(rank_.request().validation, options, rank_.hand(), nullptr, &r.build.map);
  const auto t_write = std::chrono::steady_clock::now();
  writeMap(rank_.request().output, r.build.map);
  checkpoint_.remove();
  r.write_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_write).count();
  r.written = true;
  return r;
}

}  // namespace taskmap
