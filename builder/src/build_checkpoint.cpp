// Checkpoint of finished trial blocks: header "taskmap-checkpoint 1\n", u64 identity length,
// identity, then records of u64 payload length, 64 hex digits SHA-256 of the payload, payload
// (encodeTrialBlock). Host byte order: read back by the same build of taskmap on one cluster.
#include "taskmap/builder/build_checkpoint.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>

#include "params_json.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

constexpr char kMagic[] = "taskmap-checkpoint 1\n";
constexpr std::size_t kMagicSize = sizeof kMagic - 1;
constexpr std::size_t kHashSize = 64;

void putU64(std::string& out, std::uint64_t v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

bool getU64(const std::string& in, std::size_t* pos, std::uint64_t* v) {
  if (in.size() - *pos < sizeof *v) return false;
  std::memcpy(v, in.data() + *pos, sizeof *v);
  *pos += sizeof *v;
  return true;
}

std::string record(const std::string& payload) {
  std::string r;
  putU64(r, payload.size());
  r += sha256Hex(payload);
  r += payload;
  return r;
}

std::string readWhole(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

std::string buildIdentity(const ObjectModel& object, const HandModel& hand,
                          const BuildOptions& options, std::uint64_t block_trials) {
  return "object " + object.sourceSha256() + "\nhand " + hand.urdfSha256() + "\nblock_trials " +
         std::to_string(block_trials) + "\nparams " + detail::paramsJson(options, hand) + "\n";
}

BuildCheckpoint::BuildCheckpoint(std::string path, std::string identity, std::size_t joints)
    : path_(std::move(path)), identity_(std::move(identity)), joints_(joints) {
  load();
}

BuildCheckpoint::~BuildCheckpoint() {
  if (file_ != nullptr) std::fclose(file_);
}

void BuildCheckpoint::load() {
  std::vector<std::string> records;
  if (std::filesystem::exists(path_)) {
    const std::string bytes = readWhole(path_);
    std::size_t pos = kMagicSize;
    std::uint64_t n = 0;
    const bool ours = bytes.compare(0, kMagicSize, kMagic) == 0 && getU64(bytes, &pos, &n) &&
                      n == identity_.size() && bytes.compare(pos, n, identity_) == 0;
    if (!ours) {
      note_ = "checkpoint '" + path_ +
              "' belongs to another build (different inputs or options); "
              "starting over";
    } else {
      pos += n;
      std::uint64_t trials = 0;
      while (pos < bytes.size()) {
        std::uint64_t size = 0;
        if (!getU64(bytes, &pos, &size) || bytes.size() - pos < kHashSize ||
            size > bytes.size() - pos - kHashSize)
          break;
        const std::string hash = bytes.substr(pos, kHashSize);
        std::string payload = bytes.substr(pos + kHashSize, size);
        if (sha256Hex(payload) != hash) break;
        try {
          loaded_.push_back(decodeTrialBlock(payload, joints_, "checkpoint '" + path_ + "'"));
        } catch (const Error&) {
          break;
        }
        trials += loaded_.back().trials.size();
        records.push_back(record(payload));
        pos += kHashSize + size;
      }
      note_ = "resuming from checkpoint '" + path_ + "': " + std::to_string(loaded_.size()) +
              " blocks (" + std::to_string(trials) + " trials) already done";
      if (pos < bytes.size())
        note_ += "; dropped a damaged tail of " + std::to_string(bytes.size() - pos) + " bytes";
    }
  }
  writeHeaderAndRecords(records);
}

void BuildCheckpoint::writeHeaderAndRecords(const std::vector<std::string>& records) {
  std::string bytes(kMagic, kMagicSize);
  putU64(bytes, identity_.size());
  bytes += identity_;
  for (const std::string& r : records) bytes += r;
  writeFileAtomically(path_, bytes, "cannot write checkpoint '" + path_ + "'");
  file_ = std::fopen(path_.c_str(), "ab");
  if (file_ == nullptr)
    throw Error("cannot append to checkpoint '" + path_ + "': " + std::strerror(errno));
}

std::vector<TrialBlock> BuildCheckpoint::takeLoaded() {
  return std::move(loaded_);
}

void BuildCheckpoint::append(const TrialBlock& block) {
  if (file_ == nullptr) throw Error("checkpoint '" + path_ + "' is closed");
  const std::string r = record(encodeTrialBlock(block));
  if (std::fwrite(r.data(), 1, r.size(), file_) != r.size() || std::fflush(file_) != 0)
    throw Error("cannot append to checkpoint '" + path_ + "': " + std::strerror(errno) +
                " (disk full?)");
}

void BuildCheckpoint::remove() {
  if (file_ != nullptr) std::fclose(file_);
  file_ = nullptr;
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

}  // namespace taskmap
