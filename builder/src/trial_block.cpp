// Blocks of trial outcomes: byte encoding, and running [first, last) on the trial pool.
#include "taskmap/builder/trial_block.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <type_traits>

#include "taskmap/builder/sampler_choice.hpp"
#include "taskmap/builder/size_check.hpp"
#include "taskmap/core/error.hpp"
#include "trial_pool.hpp"

namespace taskmap {

std::uint64_t TrialBlock::valid() const {
  std::uint64_t n = 0;
  for (const TrialOutcome& t : trials) n += t.force_closure ? 1 : 0;
  return n;
}

namespace {

// Layout (host byte order): u64 first, u64 count, then per trial: u8 status, u8 flags
// (bit 0 force closure, bit 1 grasp stored), f64 epsilon, f64 volume, and for a stored grasp:
// f64[7] pose (x y z, quaternion w x y z as stored), u64 joints, f64[joints], u64 contacts, then
// per contact f64[3] point, f64[3] normal, f64 depth, i32 link.
constexpr std::uint8_t kFlagForceClosure = 1;
constexpr std::uint8_t kFlagGrasp = 2;
constexpr std::uint8_t kFlagUnbalanced = 4;
constexpr std::uint8_t kFlagPushed = 8;
constexpr std::uint8_t kFlagWeakSqueeze = 16;
constexpr std::uint8_t kFlagNotHolding = 32;

class Writer {
 public:
  template <typename T>
  void put(T v) {
    static_assert(std::is_trivially_copyable<T>::value, "plain values only");
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes_.append(p, sizeof v);
  }
  void putVector(const Eigen::Vector3d& v) {
    for (int i = 0; i < 3; ++i) put<double>(v[i]);
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

class Reader {
 public:
  Reader(const std::string& bytes, const std::string& what) : bytes_(bytes), what_(what) {}
  template <typename T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  Eigen::Vector3d getVector() {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = get<double>();
    return v;
  }
  // A count of items of at least min_bytes each that must fit in the rest of the bytes.
  std::uint64_t getCount(std::size_t min_bytes, const char* name) {
    const auto n = get<std::uint64_t>();
    if (n > (bytes_.size() - pos_) / min_bytes)
      fail(std::string(name) + " count " + std::to_string(n) + " exceeds the data");
    return n;
  }
  bool atEnd() const { return pos_ == bytes_.size(); }
  [[noreturn]] void fail(const std::string& problem) const {
    throw Error(what_ + ": malformed trial block at byte " + std::to_string(pos_) + ": " + problem);
  }

 private:
  void need(std::size_t n) const {
    if (bytes_.size() - pos_ < n) fail("truncated");
  }
  const std::string& bytes_;
  const std::string& what_;
  std::size_t pos_ = 0;
};

// A hold test's result: u8 status, u8 bits (1 holds, 2 margin exceeded, 4 robust), f64 max
// translation, rotation, push translation, rotation, initial penetration, i32 failed direction,
// i32 steps; then i32 tested, i32 held, f64 push translation, rotation, i64 steps, u64 variants,
// u8 per variant.
void encodeHold(const RobustHoldResult& r, Writer& w) {
  const HoldResult& n = r.nominal;
  w.put<std::uint8_t>(static_cast<std::uint8_t>(n.status));
  w.put<std::uint8_t>(static_cast<std::uint8_t>((n.holds ? 1 : 0) | (n.margin_exceeded ? 2 : 0) |
                                                (r.robust ? 4 : 0)));
  for (double v : {n.max_translation, n.max_rotation, n.push_translation, n.push_rotation,
                   n.initial_penetration})
    w.put<double>(v);
  w.put<std::int32_t>(n.failed_direction);
  w.put<std::int32_t>(n.steps);
  w.put<std::int32_t>(r.tested);
  w.put<std::int32_t>(r.held);
  w.put<double>(r.push_translation);
  w.put<double>(r.push_rotation);
  w.put<std::int64_t>(r.steps);
  w.put<std::uint64_t>(r.variant_held.size());
  for (std::uint8_t h : r.variant_held) w.put<std::uint8_t>(h);
}

RobustHoldResult decodeHold(Reader& r) {
  RobustHoldResult h;
  HoldResult& n = h.nominal;
  const auto status = r.get<std::uint8_t>();
  if (status > static_cast<std::uint8_t>(HoldStatus::kUnstable))
    r.fail("unknown hold status " + std::to_string(status));
  n.status = static_cast<HoldStatus>(status);
  const auto bits = r.get<std::uint8_t>();
  if ((bits & ~7) != 0) r.fail("unknown hold bits");
  n.holds = (bits & 1) != 0;
  n.margin_exceeded = (bits & 2) != 0;
  h.robust = (bits & 4) != 0;
  if (n.holds != (n.status == HoldStatus::kHolds)) r.fail("hold flag disagrees with its status");
  for (double* v : {&n.max_translation, &n.max_rotation, &n.push_translation, &n.push_rotation,
                    &n.initial_penetration})
    *v = r.get<double>();
  n.failed_direction = r.get<std::int32_t>();
  if (n.failed_direction < -1 || n.failed_direction > 5) r.fail("push direction out of range");
  n.steps = r.get<std::int32_t>();
  h.tested = r.get<std::int32_t>();
  h.held = r.get<std::int32_t>();
  h.push_translation = r.get<double>();
  h.push_rotation = r.get<double>();
  h.steps = r.get<std::int64_t>();
  const std::uint64_t variants = r.getCount(1, "variant");
  if (h.tested < 0 || h.held < 0 || h.held > h.tested ||
      static_cast<std::uint64_t>(h.tested) > variants)
    r.fail("hold variant counts out of range");
  h.variant_held.resize(variants);
  for (std::uint8_t& v : h.variant_held) {
    v = r.get<std::uint8_t>();
    if (v > 1 && v != 255) r.fail("variant label other than 0, 1 or 255");
  }
  const auto held = std::count(h.variant_held.begin(), h.variant_held.end(), std::uint8_t{1});
  if (held != h.held) r.fail("hold variant count disagrees with the variants held");
  if (h.robust && held != static_cast<long>(variants)) r.fail("robust without every variant");
  return h;
}

void encodeGrasp(const TrialGrasp& g, Writer& w) {
  // The pose's own numbers (not toVector7, which normalises): decoding gives the same bits.
  w.putVector(g.pose.position);
  const Eigen::Quaterniond& q = g.pose.orientation;
  for (double v : {q.w(), q.x(), q.y(), q.z()}) w.put<double>(v);
  w.put<std::uint64_t>(static_cast<std::uint64_t>(g.joints.size()));
  for (Eigen::Index i = 0; i < g.joints.size(); ++i) w.put<double>(g.joints[i]);
  w.put<std::uint64_t>(g.contacts.size());
  for (const Contact& c : g.contacts) {
    w.putVector(c.point);
    w.putVector(c.normal);
    w.put<double>(c.depth);
    w.put<std::int32_t>(c.link);
  }
  w.put<std::uint8_t>(g.hold ? 1 : 0);
  if (g.hold) encodeHold(*g.hold, w);
}

TrialGrasp decodeGrasp(Reader& r, std::size_t joints) {
  TrialGrasp g;
  g.pose.position = r.getVector();
  const auto qw = r.get<double>(), qx = r.get<double>(), qy = r.get<double>();
  g.pose.orientation = Eigen::Quaterniond(qw, qx, qy, r.get<double>());
  const std::uint64_t n = r.getCount(sizeof(double), "joint");
  if (n != joints)
    r.fail("grasp has " + std::to_string(n) + " joints, the hand " + std::to_string(joints));
  g.joints.resize(static_cast<Eigen::Index>(n));
  for (Eigen::Index i = 0; i < g.joints.size(); ++i) g.joints[i] = r.get<double>();
  constexpr std::size_t kContactBytes = 7 * sizeof(double) + sizeof(std::int32_t);
  const std::uint64_t contacts = r.getCount(kContactBytes, "contact");
  g.contacts.resize(contacts);
  for (Contact& c : g.contacts) {
    c.point = r.getVector();
    c.normal = r.getVector();
    c.depth = r.get<double>();
    c.link = r.get<std::int32_t>();
  }
  const auto hold = r.get<std::uint8_t>();
  if (hold > 1) r.fail("hold marker other than 0 or 1");
  if (hold == 1) g.hold = decodeHold(r);
  return g;
}

}  // namespace

std::string encodeTrialBlock(const TrialBlock& block) {
  Writer w;
  w.put<std::uint64_t>(block.first);
  w.put<std::uint64_t>(block.trials.size());
  for (const TrialOutcome& t : block.trials) {
    w.put<std::uint8_t>(static_cast<std::uint8_t>(t.status));
    const auto flags = static_cast<std::uint8_t>(
        (t.force_closure ? kFlagForceClosure : 0) | (t.grasp ? kFlagGrasp : 0) |
        (t.unbalanced ? kFlagUnbalanced : 0) | (t.pushed ? kFlagPushed : 0) |
        (t.weak_squeeze ? kFlagWeakSqueeze : 0) | (t.not_holding ? kFlagNotHolding : 0));
    w.put<std::uint8_t>(flags);
    w.put<double>(t.epsilon);
    w.put<double>(t.volume);
    if (t.grasp) encodeGrasp(*t.grasp, w);
  }
  return std::move(w.bytes());
}

TrialBlock decodeTrialBlock(const std::string& bytes, std::size_t joints, const std::string& what) {
  Reader r(bytes, what);
  TrialBlock block;
  block.first = r.get<std::uint64_t>();
  constexpr std::size_t kTrialBytes = 2 + 2 * sizeof(double);
  const std::uint64_t n = r.getCount(kTrialBytes, "trial");
  if (block.first > std::numeric_limits<std::uint64_t>::max() - n) r.fail("trial index overflow");
  block.trials.resize(n);
  const auto statuses = allGraspStatuses().size();
  for (TrialOutcome& t : block.trials) {
    const auto status = r.get<std::uint8_t>();
    if (status >= statuses) r.fail("unknown grasp status " + std::to_string(status));
    t.status = static_cast<GraspStatus>(status);
    const auto flags = r.get<std::uint8_t>();
    if ((flags & ~(kFlagForceClosure | kFlagGrasp | kFlagUnbalanced | kFlagPushed |
                   kFlagWeakSqueeze | kFlagNotHolding)) != 0)
      r.fail("unknown trial flags");
    t.force_closure = (flags & kFlagForceClosure) != 0;
    t.unbalanced = (flags & kFlagUnbalanced) != 0;
    if (t.unbalanced && (t.force_closure || t.status != GraspStatus::kOk))
      r.fail("unbalanced trial that is force closure or not status ok");
    t.pushed = (flags & kFlagPushed) != 0;
    if (t.pushed && (t.force_closure || t.unbalanced || t.status != GraspStatus::kOk))
      r.fail("pushed trial that is force closure, unbalanced or not status ok");
    t.weak_squeeze = (flags & kFlagWeakSqueeze) != 0;
    if (t.weak_squeeze &&
        (t.force_closure || t.unbalanced || t.pushed || t.status != GraspStatus::kOk))
      r.fail("weak-squeeze trial that is force closure, unbalanced, pushed or not status ok");
    t.not_holding = (flags & kFlagNotHolding) != 0;
    if (t.not_holding && (t.force_closure || t.unbalanced || t.pushed || t.weak_squeeze ||
                          t.status != GraspStatus::kOk))
      r.fail("not-holding trial that is force closure, refused earlier or not status ok");
    if (t.force_closure && t.status != GraspStatus::kOk) r.fail("force closure without status ok");
    t.epsilon = r.get<double>();
    t.volume = r.get<double>();
    if ((flags & kFlagGrasp) != 0) t.grasp = std::make_unique<TrialGrasp>(decodeGrasp(r, joints));
  }
  if (!r.atEnd()) r.fail("trailing bytes");
  return block;
}

struct TrialRunner::Impl {
  const BuildOptions options;
  const int threads;
  const Sampler sampler;
  const GraspSimulator simulator;
  const std::unique_ptr<const ClosingChecker> closing;
  const std::unique_ptr<const RobustHoldTester> hold;
  const Eigen::Vector3d com;
  const double torque_scale;
  BuildTiming timing;
  SamplerChoice choice;

  Impl(const ObjectModel& object, const HandModel& hand, const BuildOptions& o)
      : options(o),
        threads(detail::threadCount(o.threads)),
        sampler(object, detail::samplerOptionsFor(o, hand)),
        simulator(object, hand, o.simulation),
        closing(detail::makeClosingChecker(object, hand, o)),
        hold(detail::makeHoldTester(object, hand, o)),
        com(object.massProperties().center_of_mass),
        torque_scale(object.massProperties().torque_scale) {}
};

TrialRunner::TrialRunner(const ObjectModel& object, const HandModel& hand,
                         const BuildOptions& requested) {
  requested.validate();
  if (requested.check_size) requirePlausibleSize(object, hand);
  const auto t0 = detail::Clock::now();
  const SamplerChoice choice = chooseSampler(object, hand, requested);
  BuildOptions options = requested;
  options.sampler.kind = choice.kind;
  impl_ = std::make_unique<Impl>(object, hand, options);
  impl_->choice = choice;
  impl_->timing.setup_seconds = detail::secondsSince(t0);
}

const SamplerChoice& TrialRunner::samplerChoice() const {
  return impl_->choice;
}

TrialRunner::~TrialRunner() = default;

bool TrialRunner::run(std::uint64_t first, std::uint64_t last, TrialBlock* block,
                      const std::atomic<bool>* stop) {
  if (first >= last || last > impl_->options.max_trials)
    throw Error("TrialRunner::run: need first < last <= max_trials (" +
                std::to_string(impl_->options.max_trials) + "), got [" + std::to_string(first) +
                ", " + std::to_string(last) + ")");
  const auto t0 = detail::Clock::now();
  detail::Scheduler scheduler(first, last, detail::blockSize(impl_->options),
                              std::numeric_limits<std::uint64_t>::max());
  const ProgressCallback none;
  const detail::TrialPoolSetup setup{impl_->sampler,
                                     impl_->simulator,
                                     impl_->closing.get(),
                                     impl_->hold.get(),
                                     impl_->options,
                                     impl_->com,
                                     impl_->torque_scale,
                                     impl_->threads,
                                     stop,
                                     none,
                                     0.25};
  detail::runTrialPool(setup, scheduler, impl_->timing);
  impl_->timing.wall_seconds += detail::secondsSince(t0);
  if (scheduler.prefix() < scheduler.blockCount()) return false;
  block->first = first;
  block->trials.clear();
  block->trials.reserve(std::min<std::uint64_t>(last - first, 4096));  // grows past that
  for (TrialBlock& part : scheduler.takePrefixBlocks())
    for (TrialOutcome& t : part.trials) block->trials.push_back(std::move(t));
  return true;
}

const BuildTiming& TrialRunner::timing() const {
  return impl_->timing;
}

}  // namespace taskmap
