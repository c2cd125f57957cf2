// The hold test (docs/VALIDATION.md): MuJoCo runs DexGraspBench's force-closure protocol on
// one grasp. Steps: place (start state, penetration check), close (pregrasp -> grasp ->
// squeeze), push (six directions from the same closed state).
#include "taskmap/validate/hold_test.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <mutex>
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
  if (interpolation_stages < 1 || steps_per_stage < 1 || check_every < 1 || noslip_iterations < 0)
    throw Error("hold test: interpolation_stages, steps_per_stage and check_every must be >= 1");
  if (!(contact_patch >= 0.0)) throw Error("hold test option contact_patch must be >= 0 metres");
  if (object_max_pieces < 1 || object_max_pieces > 64)
    throw Error("hold test option object_max_pieces must be in [1, 64]");
}

std::string physicsEngine() {
  const int v = mj_version();
  return "MuJoCo " + std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." +
         std::to_string(v % 10);
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
  const int n = options.interpolation_stages;
  for (int k = 1; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    for (int a = 0; a < model->nu; ++a) d->ctrl[a] = from[a] + t * (to[a] - from[a]);
    for (int s = 0; s < options.steps_per_stage; ++s) mj_step(model, d);
    *steps += options.steps_per_stage;
    if (!finite(d)) return false;
    record(d, start, phase, *steps, trace);
  }
  return true;
}

HoldResult HoldTester::Impl::push(mjData* d, const mjData* closed, const mjtNum* start,
                                  HoldResult r, HoldTrace* trace) const {
  const Eigen::Quaterniond r0(start[3], start[4], start[5], start[6]);
  const double force = options.push_per_mass * options.object_mass;
  const auto lost = displacement(closed, start);
  const bool lost_in_closing =
      lost.first >= options.max_translation || lost.second >= options.max_rotation;
  const int total = static_cast<int>(std::lround(options.push_duration / options.timestep));
  for (int dir = 0; dir < 6; ++dir) {
    copyState(model, d, closed);
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    axis[dir / 2] = dir % 2 == 0 ? -1.0 : 1.0;
    const Eigen::Vector3d f = force * (r0.normalized() * axis);
    for (int k = 0; k < 3; ++k) d->xfrc_applied[6 * object_body + k] = f[k];
    for (int done = 0; done < total;) {
      const int n = std::min(options.check_every, total - done);
      for (int s = 0; s < n; ++s) mj_step(model, d);
      done += n;
      r.steps += n;
      if (!finite(d)) {
        r.status = HoldStatus::kUnstable;
        r.failed_direction = dir;
        return r;
      }
      record(d, start, pushDirectionNames()[static_cast<std::size_t>(dir)], r.steps, trace);
      const auto [dp, da] = displacement(d, start);
      r.max_translation = std::max(r.max_translation, dp);
      r.max_rotation = std::max(r.max_rotation, da);
      if (dp >= options.max_translation || da >= options.max_rotation) {
        r.status = lost_in_closing ? HoldStatus::kLostInClosing : HoldStatus::kSlipped;
        r.failed_direction = dir;
        return r;
      }
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
  const Eigen::VectorXd pregrasp = pre + options.pregrasp_fraction * (joints - pre);
  const Eigen::VectorXd squeeze = pre + options.squeeze_fraction * (joints - pre);
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
