// The hold test (docs/VALIDATION.md): MuJoCo runs DexGraspBench's force-closure protocol on
// one grasp. Steps: place (start state, penetration check), close (pregrasp -> grasp ->
// squeeze), push (six directions from the same closed state).
#include "taskmap/validate/hold_test.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <mujoco/mujoco.h>

#include "mjcf_model.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// The object's convex pieces, kept for the process: decomposing a YCB scan takes 6 to 25 s, and
/// a map validated twice (or a build that validates after a validation) pays it once. Keyed by
/// the mesh's exact content and the decomposition options; the last kPieceCacheSize objects.
class PieceCache {
 public:
  /// The pieces of `mesh`, computed or from the cache; *hit tells which.
  ConvexPieces get(const TriangleMesh& mesh, const ConvexPiecesOptions& o, const std::string& what,
                   bool* hit) {
    const std::uint64_t key = hashOf(mesh, o);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const Entry& e : entries_)
        if (e.key == key && e.max_pieces == o.max_pieces && e.max_faces == o.max_faces &&
            e.convex_tolerance == o.convex_tolerance && e.wrap == o.wrap &&
            e.mesh.vertices == mesh.vertices && e.mesh.faces == mesh.faces) {
          *hit = true;
          return e.pieces;
        }
    }
    *hit = false;
    ConvexPieces pieces = convexPieces(mesh, o, what);  // outside the lock: may take seconds
    std::lock_guard<std::mutex> lock(mutex_);
    if (entries_.size() >= kPieceCacheSize) entries_.erase(entries_.begin());
    entries_.push_back(
        Entry{key, o.max_pieces, o.max_faces, o.convex_tolerance, o.wrap, mesh, pieces});
    return pieces;
  }

 private:
  static constexpr std::size_t kPieceCacheSize = 8;
  struct Entry {
    std::uint64_t key;
    int max_pieces, max_faces;
    double convex_tolerance;
    bool wrap;
    TriangleMesh mesh;
    ConvexPieces pieces;
  };
  /// FNV-1a over the vertex and face bytes and the options.
  static std::uint64_t hashOf(const TriangleMesh& mesh, const ConvexPiecesOptions& o) {
    std::uint64_t h = 1469598103934665603ULL;
    auto mix = [&h](const void* data, std::size_t n) {
      const auto* b = static_cast<const unsigned char*>(data);
      for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ULL;
    };
    for (const auto& v : mesh.vertices) mix(v.data(), sizeof(double) * 3);
    for (const auto& f : mesh.faces) mix(f.data(), sizeof(int) * 3);
    mix(&o.max_pieces, sizeof o.max_pieces);
    mix(&o.max_faces, sizeof o.max_faces);
    return h;
  }
  std::mutex mutex_;
  std::vector<Entry> entries_;
};

PieceCache& pieceCache() {
  static PieceCache cache;
  return cache;
}

/// MuJoCo's fatal errors become exceptions (its default handler exits the process); its
/// warnings are read from mjData::warning instead of being written to MUJOCO_LOG.TXT.
void installHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = [](const char* msg) { throw Error(std::string("MuJoCo: ") + msg); };
    mju_user_warning = [](const char*) {};
  });
}

/// Compiles MJCF text held in memory.
mjModel* compileMjcf(const std::string& xml) {
  static std::mutex mutex;  // the XML parser keeps global state
  std::lock_guard<std::mutex> lock(mutex);
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "taskmap_hold_test.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    throw Error("hold test: MuJoCo's virtual file system refused the model");
  const int slot = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[slot], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!m) throw Error(std::string("hold test: MuJoCo refused the model: ") + error);
  return m;
}

struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

/// Copies what the next step depends on (time, state, controls, applied forces, the solver's
/// warm start): stepping on from the copy gives the same numbers as from the original, without
/// copying MuJoCo's whole arena as mj_copyData does.
void copyState(const mjModel* m, mjData* to, const mjData* from) {
  to->time = from->time;
  std::memcpy(to->qpos, from->qpos, sizeof(mjtNum) * static_cast<std::size_t>(m->nq));
  std::memcpy(to->qvel, from->qvel, sizeof(mjtNum) * static_cast<std::size_t>(m->nv));
  std::memcpy(to->qacc_warmstart, from->qacc_warmstart,
              sizeof(mjtNum) * static_cast<std::size_t>(m->nv));
  std::memcpy(to->qfrc_applied, from->qfrc_applied,
              sizeof(mjtNum) * static_cast<std::size_t>(m->nv));
  std::memcpy(to->xfrc_applied, from->xfrc_applied,
              sizeof(mjtNum) * 6 * static_cast<std::size_t>(m->nbody));
  if (m->na > 0) std::memcpy(to->act, from->act, sizeof(mjtNum) * static_cast<std::size_t>(m->na));
  if (m->nu > 0)
    std::memcpy(to->ctrl, from->ctrl, sizeof(mjtNum) * static_cast<std::size_t>(m->nu));
  for (int w = 0; w < mjNWARNING; ++w) to->warning[w] = from->warning[w];
}

}  // namespace

void HoldTestOptions::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw Error(std::string("hold test option ") + name + " must be a positive number");
  };
  positive(object_mass, "object_mass");
  positive(sliding_friction, "sliding_friction");
  positive(timestep, "timestep");
  positive(impratio, "impratio");
  positive(kp_revolute, "kp_revolute");
  positive(kp_prismatic, "kp_prismatic");
  positive(link_density, "link_density");
  positive(jaw_force, "jaw_force");
  positive(push_duration, "push_duration");
  positive(max_translation, "max_translation");
  positive(max_rotation, "max_rotation");
  positive(max_penetration, "max_penetration");
  if (!(torsional_friction >= 0.0) || !(joint_damping >= 0.0) || !(prismatic_damping >= 0.0) ||
      !(push_per_mass >= 0.0))
    throw Error(
        "hold test options torsional_friction, joint_damping, prismatic_damping and "
        "push_per_mass must be >= 0");
  if (!(pregrasp_fraction >= 0.0 && pregrasp_fraction <= 1.0) || !(squeeze_fraction >= 1.0) ||
      !(squeeze_fraction <= 2.0))
    throw Error("hold test: pregrasp_fraction must be in [0, 1] and squeeze_fraction in [1, 2]");
  if (solver_iterations < 1) throw Error("hold test option solver_iterations must be >= 1");
  positive(solver_tolerance, "solver_tolerance");
  if (interpolation_stages < 1 || steps_per_stage < 1 || check_every < 1 || noslip_iterations < 0)
    throw Error("hold test: interpolation_stages, steps_per_stage and check_every must be >= 1");
  if (!(contact_patch >= 0.0)) throw Error("hold test option contact_patch must be >= 0 metres");
  if (object_max_pieces < 1 || object_max_pieces > 64)
    throw Error("hold test option object_max_pieces must be in [1, 64]");
  if (object_max_faces < 50 || object_max_faces > 5000)
    throw Error("hold test option object_max_faces must be in [50, 5000]");
  if (!(margin_translation >= 0.0) || !(margin_rotation >= 0.0))
    throw Error("hold test options margin_translation and margin_rotation must be >= 0 (0: off)");
  if (settle_window < 1) throw Error("hold test option settle_window must be >= 1");
  positive(settle_joint_speed, "settle_joint_speed");
  if (!(settle_envelope > 0.0 && settle_envelope <= 1.0))
    throw Error("hold test option settle_envelope must be in (0, 1]");
}

std::string physicsEngine() {
  const int v = mj_version();
  return "MuJoCo " + std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." +
         std::to_string(v % 10);
}

const char* integratorName(HoldTestOptions::Integrator integrator) {
  return integrator == HoldTestOptions::Integrator::kImplicit ? "implicit" : "implicitfast";
}

namespace {
/// Every integrator, the default first (integratorNames' order).
constexpr HoldTestOptions::Integrator kIntegrators[] = {HoldTestOptions::Integrator::kImplicit,
                                                        HoldTestOptions::Integrator::kImplicitFast};
}  // namespace

HoldTestOptions::Integrator integratorFromName(const std::string& name) {
  for (const auto i : kIntegrators)
    if (name == integratorName(i)) return i;
  throw Error("hold test integrator must be implicitfast or implicit, not '" + name + "'");
}

std::vector<std::string> integratorNames() {
  std::vector<std::string> names;
  for (const auto i : kIntegrators) names.emplace_back(integratorName(i));
  return names;
}

const char* holdStatusName(HoldStatus s) {
  switch (s) {
    case HoldStatus::kHolds:
      return "holds";
    case HoldStatus::kPenetration:
      return "penetration";
    case HoldStatus::kLostInClosing:
      return "lost_in_closing";
    case HoldStatus::kSlipped:
      return "slipped";
    case HoldStatus::kUnstable:
      return "unstable";
  }
  return "unknown";
}

const std::array<const char*, 6>& pushDirectionNames() {
  static const std::array<const char*, 6> names = {"-x", "+x", "-y", "+y", "-z", "+z"};
  return names;
}

struct HoldTester::Impl {
  HandModel hand;
  HoldTestOptions options;
  HoldModelInfo info;
  std::string xml;
  mjModel* model = nullptr;
  int object_body = -1;
  int object_qpos = -1;              // address of the free joint's 7 numbers
  std::vector<int> urdf_joint_qpos;  // per HandModel::joints(): qpos address, -1 if fixed
  std::vector<int> body_link;        // per MuJoCo body: index into HandModel::links(), or -1
  mutable std::mutex pool_mutex;     // simulation states reused across test() calls
  mutable std::vector<DataPtr> pool;

  DataPtr acquire() const {
    std::lock_guard<std::mutex> lock(pool_mutex);
    if (pool.empty()) return DataPtr(mj_makeData(model));
    DataPtr d = std::move(pool.back());
    pool.pop_back();
    return d;
  }
  void release(DataPtr d) const {
    std::lock_guard<std::mutex> lock(pool_mutex);
    pool.push_back(std::move(d));
  }

  ~Impl() {
    pool.clear();
    if (model) mj_deleteModel(model);
  }

  /// Object pose relative to its start: translation (m) and rotation (rad).
  std::pair<double, double> displacement(const mjData* d, const mjtNum* start) const {
    const mjtNum* q = d->qpos + object_qpos;
    const Eigen::Vector3d dp(q[0] - start[0], q[1] - start[1], q[2] - start[2]);
    const Eigen::Quaterniond a(start[3], start[4], start[5], start[6]);
    const Eigen::Quaterniond b(q[3], q[4], q[5], q[6]);
    return {dp.norm(), a.normalized().angularDistance(b.normalized())};
  }

  /// The fastest hand joint, rad/s (a slide's m/s times 10: a 10 cm lever).
  double handSpeed(const mjData* d) const {
    double fastest = 0.0;
    for (int j = 0; j < model->njnt; ++j) {
      const int type = model->jnt_type[j];
      if (type != mjJNT_HINGE && type != mjJNT_SLIDE) continue;
      const double v = std::abs(d->qvel[model->jnt_dofadr[j]]);
      fastest = std::max(fastest, type == mjJNT_SLIDE ? 10.0 * v : v);
    }
    return fastest;
  }

  bool finite(const mjData* d) const {
    for (int i = 0; i < model->nq; ++i)
      if (!std::isfinite(d->qpos[i])) return false;
    return d->warning[mjWARN_BADQACC].number == 0;
  }

  void place(mjData* d, const Pose& palm, const Eigen::VectorXd& q) const;
  double penetration(const mjData* d) const;
  /// Closing phase `phase` toward `to`; with `trace`, a sample after each stage.
  bool close(mjData* d, const Eigen::VectorXd& from, const Eigen::VectorXd& to, int* steps,
             const mjtNum* start, const char* phase, HoldTrace* trace) const;
  HoldResult push(mjData* d, const mjData* closed, const mjtNum* start, HoldResult r,
                  HoldTrace* trace) const;
  HoldResult run(const Pose& palm, const Eigen::VectorXd& joints, HoldTrace* trace) const;
  void record(const mjData* d, const mjtNum* start, const char* phase, int steps,
              HoldTrace* trace) const;
};

// A sample of the object's pose and of the force each hand link presses it with (normal force
// of each contact, mj_contactForce's first component, summed per link).
void HoldTester::Impl::record(const mjData* d, const mjtNum* start, const char* phase, int steps,
                              HoldTrace* trace) const {
  if (!trace) return;
  HoldTraceSample s;
  s.phase = phase;
  s.step = steps;
  std::tie(s.translation, s.rotation) = displacement(d, start);
  const mjtNum* q = d->qpos + object_qpos;
  s.offset = Eigen::Vector3d(q[0] - start[0], q[1] - start[1], q[2] - start[2]);
  std::map<int, double> force;
  for (int c = 0; c < d->ncon; ++c) {
    const mjContact& k = d->contact[c];
    const int b1 = model->geom_bodyid[k.geom1], b2 = model->geom_bodyid[k.geom2];
    if ((b1 == object_body) == (b2 == object_body)) continue;
    const int link = body_link[static_cast<std::size_t>(b1 == object_body ? b2 : b1)];
    if (link < 0) continue;
    mjtNum f[6];
    mj_contactForce(model, d, c, f);
    force[link] += f[0];
  }
  for (const auto& [link, f] : force) s.contacts.push_back({link, f});
  trace->samples.push_back(std::move(s));
}

void HoldTester::Impl::place(mjData* d, const Pose& palm, const Eigen::VectorXd& q) const {
  mj_resetData(model, d);
  const Eigen::Isometry3d object_in_palm = palm.toIsometry().inverse();
  const Eigen::Quaterniond r(object_in_palm.rotation());
  mjtNum* o = d->qpos + object_qpos;
  for (int k = 0; k < 3; ++k) o[k] = object_in_palm.translation()[k];
  o[3] = r.w(), o[4] = r.x(), o[5] = r.y(), o[6] = r.z();
  const Eigen::VectorXd all = hand.allJointValues(q);
  for (std::size_t j = 0; j < urdf_joint_qpos.size(); ++j)
    if (urdf_joint_qpos[j] >= 0) d->qpos[urdf_joint_qpos[j]] = all[static_cast<Eigen::Index>(j)];
  for (int a = 0; a < model->nu; ++a) d->ctrl[a] = q[a];
  mj_forward(model, d);
}

double HoldTester::Impl::penetration(const mjData* d) const {
  double deepest = 0.0;
  for (int c = 0; c < d->ncon; ++c) {
    const mjContact& k = d->contact[c];
    const bool a = model->geom_bodyid[k.geom1] == object_body;
    const bool b = model->geom_bodyid[k.geom2] == object_body;
    if (a != b) deepest = std::max(deepest, -static_cast<double>(k.dist));
  }
  return deepest;
}

bool HoldTester::Impl::close(mjData* d, const Eigen::VectorXd& from, const Eigen::VectorXd& to,
                             int* steps, const mjtNum* start, const char* phase,
                             HoldTrace* trace) const {
  const int n = options.interpolation_stages, m = options.steps_per_stage;
  for (int k = 1; k <= n; ++k) {
    for (int s = 0; s < m; ++s) {
      // Jaws closing from open move their targets every step (a gripper's speed-limited
      // closing): a stage's jump, with the stiff jaw drive, would kick the object that one jaw
      // touches first out of the open jaws.
      const double t = options.close_from_open ? (k - 1 + static_cast<double>(s + 1) / m) / n
                                               : static_cast<double>(k) / n;
      for (int a = 0; a < model->nu; ++a) d->ctrl[a] = from[a] + t * (to[a] - from[a]);
      mj_step(model, d);
    }
    *steps += options.steps_per_stage;
    if (!finite(d)) return false;
    record(d, start, phase, *steps, trace);
  }
  return true;
}

namespace {

/// Where the object is during a push, against its start and its closed state.
struct PushReading {
  double from_start_t = 0.0, from_start_r = 0.0;    // protocol: from the start, m and rad
  double from_closed_t = 0.0, from_closed_r = 0.0;  // margin: from the closed state
};

/// The object's drift over the last settle window and whether the push may end held: the drift
/// does not grow, and twice the drift over each of the `remaining` windows keeps every measure
/// inside its threshold (docs/VALIDATION.md, "Settled pushes").
struct SettleWatch {
  double last_t = -1.0, last_r = -1.0;  // drift of the previous window, -1 before the first
  Eigen::Vector3d where = Eigen::Vector3d::Zero();
  Eigen::Quaterniond turn = Eigen::Quaterniond::Identity();
  int steady_windows = 0;  // consecutive windows that passed

  /// A window ends at the object's pose p, q; `remaining` windows of the push are left; `hand`:
  /// the hand is slow enough (or not asked about).
  bool settled(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, const PushReading& r,
               double remaining, bool hand, const HoldTestOptions& o) {
    const double dt = (p - where).norm(), dr = turn.angularDistance(q);
    const bool steady = last_t >= 0.0 && dt <= last_t + 1e-9 && dr <= last_r + 1e-9 && hand &&
                        within(dt, dr, r, remaining, o);
    last_t = dt, last_r = dr, where = p, turn = q;
    steady_windows = steady ? steady_windows + 1 : 0;
    return steady_windows >= 2;
  }

  /// Twice the drift over every remaining window keeps the object inside the protocol's
  /// thresholds and, from its closed state, inside the settle envelope (a fraction of them, or
  /// the margin when smaller).
  static bool within(double dt, double dr, const PushReading& r, double remaining,
                     const HoldTestOptions& o) {
    const double reach_t = 2.0 * remaining * dt, reach_r = 2.0 * remaining * dr;
    if (r.from_start_t + reach_t >= o.max_translation) return false;
    if (r.from_start_r + reach_r >= o.max_rotation) return false;
    double envelope_t = o.settle_envelope * o.max_translation;
    double envelope_r = o.settle_envelope * o.max_rotation;
    if (o.margin_translation > 0.0) envelope_t = std::min(envelope_t, o.margin_translation);
    if (o.margin_rotation > 0.0) envelope_r = std::min(envelope_r, o.margin_rotation);
    return r.from_closed_t + reach_t < envelope_t && r.from_closed_r + reach_r < envelope_r;
  }
};

/// Whether a push whose object jitters in place (a chattering contact never comes to rest) or
/// creeps at a steady rate (MuJoCo's soft friction lets a pushed object slide slowly) may end
/// held: at the protocol's checks, the running maxima of the object's displacement and rotation
/// from its closed state grow, over the last check, by no more than 1.5 times their mean growth
/// since the first check (no acceleration), and twice the larger of the two over every check
/// left keeps them inside every threshold and the settle envelope (SettleWatch::within); two
/// checks in a row.
struct EnvelopeWatch {
  PushReading most;   // running maxima over the checks so far
  PushReading first;  // the maxima at the first check (the push's transient)
  int checks = 0, steady_checks = 0;

  bool settled(const PushReading& now, double remaining, const HoldTestOptions& o) {
    const PushReading before = most;
    most.from_start_t = std::max(most.from_start_t, now.from_start_t);
    most.from_start_r = std::max(most.from_start_r, now.from_start_r);
    most.from_closed_t = std::max(most.from_closed_t, now.from_closed_t);
    most.from_closed_r = std::max(most.from_closed_r, now.from_closed_r);
    if (++checks == 1) first = most;
    if (checks < 3) return false;
    const double gt = most.from_closed_t - before.from_closed_t;
    const double gr = most.from_closed_r - before.from_closed_r;
    const double mean_t = (most.from_closed_t - first.from_closed_t) / (checks - 1);
    const double mean_r = (most.from_closed_r - first.from_closed_r) / (checks - 1);
    const bool steady =
        gt <= 1.5 * mean_t + 1e-9 && gr <= 1.5 * mean_r + 1e-9 &&
        SettleWatch::within(std::max(gt, mean_t), std::max(gr, mean_r), most, remaining, o);
    steady_checks = steady ? steady_checks + 1 : 0;
    return steady_checks >= 2;
  }
};

Eigen::Vector3d objectPosition(const mjtNum* q) {
  return {q[0], q[1], q[2]};
}
Eigen::Quaterniond objectTurn(const mjtNum* q) {
  return Eigen::Quaterniond(q[3], q[4], q[5], q[6]).normalized();
}

}  // namespace

HoldResult HoldTester::Impl::push(mjData* d, const mjData* closed, const mjtNum* start,
                                  HoldResult r, HoldTrace* trace) const {
  const mjtNum* c = closed->qpos + object_qpos;
  const Eigen::Vector3d p0 = objectPosition(start), pc = objectPosition(c);
  const Eigen::Quaterniond q0 = objectTurn(start), qc = objectTurn(c);
  const bool lost_in_closing =
      (pc - p0).norm() >= options.max_translation || q0.angularDistance(qc) >= options.max_rotation;
  const int total = static_cast<int>(std::lround(options.push_duration / options.timestep));
  // The protocol's checks every check_every steps decide; with settle_stop the drift is also
  // measured every settle_window steps, and a settled push ends before its last check.
  const int every = options.settle_stop ? std::gcd(options.settle_window, options.check_every)
                                        : options.check_every;
  for (int dir = 0; dir < 6; ++dir) {
    copyState(model, d, closed);
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    axis[dir / 2] = dir % 2 == 0 ? -1.0 : 1.0;
    const Eigen::Vector3d f = options.push_per_mass * options.object_mass * (q0 * axis);
    for (int k = 0; k < 3; ++k) d->xfrc_applied[6 * object_body + k] = f[k];
    // At rest: short windows, the hand still. Bounded: the net drift from check to check
    // (a chattering contact that keeps the object in place never comes to rest).
    SettleWatch rest{-1.0, -1.0, pc, qc};
    EnvelopeWatch bounded;
    for (int done = 0; done < total;) {
      const int n = std::min(every, total - done);
      for (int s = 0; s < n; ++s) mj_step(model, d);
      done += n;
      r.steps += n;
      if (!finite(d)) {
        r.status = HoldStatus::kUnstable;
        r.failed_direction = dir;
        return r;
      }
      const mjtNum* q = d->qpos + object_qpos;
      const Eigen::Vector3d p = objectPosition(q);
      const Eigen::Quaterniond o = objectTurn(q);
      const PushReading now{(p - p0).norm(), q0.angularDistance(o), (p - pc).norm(),
                            qc.angularDistance(o)};
      const bool check = done % options.check_every == 0 || done == total;
      const auto left = [&](int window) { return static_cast<double>(total - done) / window; };
      const bool at_rest = options.settle_stop && done % options.settle_window == 0 &&
                           rest.settled(p, o, now, left(options.settle_window),
                                        handSpeed(d) < options.settle_joint_speed, options);
      const bool settled = at_rest || (options.settle_stop && check &&
                                       bounded.settled(now, left(options.check_every), options));
      if (!check && !settled) continue;
      record(d, start, pushDirectionNames()[static_cast<std::size_t>(dir)], r.steps, trace);
      r.max_translation = std::max(r.max_translation, now.from_start_t);
      r.max_rotation = std::max(r.max_rotation, now.from_start_r);
      r.push_translation = std::max(r.push_translation, now.from_closed_t);
      r.push_rotation = std::max(r.push_rotation, now.from_closed_r);
      const bool protocol =
          now.from_start_t >= options.max_translation || now.from_start_r >= options.max_rotation;
      const bool margin =
          (options.margin_translation > 0.0 && now.from_closed_t >= options.margin_translation) ||
          (options.margin_rotation > 0.0 && now.from_closed_r >= options.margin_rotation);
      if (check && (protocol || margin)) {
        r.status = lost_in_closing ? HoldStatus::kLostInClosing : HoldStatus::kSlipped;
        r.margin_exceeded = !protocol;
        r.failed_direction = dir;
        return r;
      }
      if (settled) break;
    }
  }
  r.status = HoldStatus::kHolds;
  r.holds = true;
  return r;
}

HoldTester::HoldTester(const HandModel& hand, const ObjectModel& object,
                       const HoldTestOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  installHandlers();
  Impl& s = *impl_;
  s.hand = hand;
  s.options = options;
  ConvexPiecesOptions po;
  po.max_pieces = options.object_max_pieces;
  po.max_faces = options.object_max_faces;
  bool cached = false;
  const ConvexPieces pieces =
      pieceCache().get(object.mesh(), po, "object '" + object.name() + "'", &cached);
  const detail::MjcfScene scene = detail::writeMjcf(hand, object, pieces, options);
  s.xml = scene.xml;
  s.model = compileMjcf(s.xml);
  s.object_body = mj_name2id(s.model, mjOBJ_BODY, detail::kObjectBody);
  s.object_qpos = s.model->jnt_qposadr[mj_name2id(s.model, mjOBJ_JOINT, detail::kObjectJoint)];
  for (const auto& j : hand.joints()) {
    const int id =
        j.type == JointType::kFixed ? -1 : mj_name2id(s.model, mjOBJ_JOINT, j.name.c_str());
    s.urdf_joint_qpos.push_back(id < 0 ? -1 : s.model->jnt_qposadr[id]);
  }
  s.body_link.assign(static_cast<std::size_t>(s.model->nbody), -1);
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    const int id = mj_name2id(s.model, mjOBJ_BODY, ("link_" + std::to_string(l)).c_str());
    if (id >= 0) s.body_link[static_cast<std::size_t>(id)] = static_cast<int>(l);
  }
  s.info.object_pieces = static_cast<int>(pieces.pieces.size());
  s.info.object_volume_error = pieces.volumeError();
  s.info.object_decomposed = pieces.decomposed;
  s.info.object_note = pieces.note;
  s.info.object_pieces_cached = cached;
  s.info.hand_bodies = scene.hand_bodies;
  s.info.hand_geoms = scene.hand_geoms;
  s.info.actuators = scene.actuators;
  s.info.mimic_constraints = scene.mimic_constraints;
  s.info.gripper_torque = scene.gripper_torque;
  s.info.hand_dynamics = scene.hand_dynamics;
}

HoldTester::~HoldTester() = default;
HoldTester::HoldTester(HoldTester&&) noexcept = default;
HoldTester& HoldTester::operator=(HoldTester&&) noexcept = default;

const HoldModelInfo& HoldTester::info() const {
  return impl_->info;
}
const std::string& HoldTester::mjcf() const {
  return impl_->xml;
}
const HoldTestOptions& HoldTester::options() const {
  return impl_->options;
}

HoldResult HoldTester::Impl::run(const Pose& palm, const Eigen::VectorXd& joints,
                                 HoldTrace* trace) const {
  const Eigen::Index n = static_cast<Eigen::Index>(hand.jointNames().size());
  if (joints.size() != n)
    throw Error("hold test: " + std::to_string(joints.size()) + " joint values for hand '" +
                hand.name() + "' with " + std::to_string(n) + " actuated joints");
  const Eigen::VectorXd pre = hand.preshape();
  Eigen::VectorXd pregrasp = pre + options.pregrasp_fraction * (joints - pre);
  Eigen::VectorXd squeeze = pre + options.squeeze_fraction * (joints - pre);
  if (options.close_from_open) {  // a gripper's grasp command: from open, to the closed limit
    pregrasp = pre;
    for (const ClosingJoint& c : hand.closing()) squeeze[c.joint] = c.target;
  }
  DataPtr d = acquire(), closed = acquire();
  HoldResult r;
  place(d.get(), palm, pregrasp);
  r.initial_penetration = penetration(d.get());
  mjtNum start[7];
  std::memcpy(start, d->qpos + object_qpos, sizeof start);
  record(d.get(), start, "closing", 0, trace);
  if (r.initial_penetration > options.max_penetration) {
    r.status = HoldStatus::kPenetration;
  } else if (!close(d.get(), pregrasp, joints, &r.steps, start, "closing", trace) ||
             !close(d.get(), joints, squeeze, &r.steps, start, "squeeze", trace)) {
    r.status = HoldStatus::kUnstable;
  } else {
    copyState(model, closed.get(), d.get());
    r = push(d.get(), closed.get(), start, r, trace);
  }
  release(std::move(d));
  release(std::move(closed));
  return r;
}

HoldResult HoldTester::test(const Pose& palm, const Eigen::VectorXd& joints) const {
  return impl_->run(palm, joints, nullptr);
}

HoldTrace HoldTester::trace(const Pose& palm, const Eigen::VectorXd& joints) const {
  HoldTrace t;
  t.result = impl_->run(palm, joints, &t);
  return t;
}

}  // namespace taskmap
