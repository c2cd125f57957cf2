#pragma once
// Private to grasp_sim: one grasp trial as named steps over a SimModel (semantics in
// grasp_simulator.hpp). GraspSimulator::simulate is the driver:
//   retract -> placePalm -> close -> squeeze -> collectContacts -> judge.
// A step that ends the trial early sets the status and returns false.

#include <array>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sim_model.hpp"
#include "squeeze.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"

namespace taskmap {

/// State of one trial: palm pose, joint values, link poses and the closing bookkeeping.
class Trial {
 public:
  /// Starts a trial at `initial` (palm pose, object frame) with the open preshape. With
  /// `status_only` a failing trial may end once its status is certain (FailureDetail::kStatus).
  Trial(const SimModel& model, const Pose& initial, bool status_only = false);

  /// Moves the hand along -approach out of the object (or along +approach onto it) to the
  /// first touching pose. False (status set) when not retractable or nothing is touched.
  bool retract();
  /// Palm grasps: checks that the palm touches and presses it by the squeeze distance along
  /// +approach; false (kNoPalmContact) when a finger touches first and the palm is required.
  /// Fingertip grasps: backs the hand off until the palm is the standoff from the object.
  bool placePalm();
  /// autoGrasp: closes every closing joint until contact or limit.
  void close();
  /// Presses each contact-stopped joint's contact point the squeeze distance deeper.
  void squeeze();
  /// Extracts the pressed contacts (per link, merged, manifold-reduced) and the fingers.
  void collectContacts();
  /// Sets the final status (step limit, self-collision, no finger contact or ok).
  void judge();
  /// The result (valid after a step returned false or after judge()).
  GraspResult takeResult() { return std::move(res_); }

  /// Minimum cosine between a triangle's normal and the separation direction for a contact.
  static constexpr double kMinNormalAgreement = 0.5;

 private:
  using Clock = std::chrono::steady_clock;

  // Retraction parts.
  double evalAll(const Eigen::Isometry3d& pm, double threshold, bool inside_check);
  double evalNearest(const Eigen::Isometry3d& pm, double far);
  Eigen::Isometry3d at(double s) const;
  bool leaveObject(double m, double s_max, double* s);
  bool palmStaysClear(double s, const Eigen::Vector3d& dir) const;
  double palmClearFrom(double s, const Eigen::Vector3d& dir) const;
  bool palmClearAt(double lo, double* retry) const;
  bool endClear(double s);
  bool approachObject(double s_max, double* s);
  double palmGap(const Eigen::Isometry3d& pm, double threshold);
  void placeFingertips();
  // Closing parts.
  bool moving(int link) const;
  Eigen::VectorXd advance(const Eigen::VectorXd& from, double dt) const;
  double evalMoving(const Eigen::VectorXd& qq, double dt = 0.0);
  double pairSelfDistance(int link, std::size_t k);
  void stopTouching(const std::vector<int>& touching);
  void refreshMoving();
  void closingStep();
  void bisectStep(double dt, double rate, std::vector<int>* touching);
  // Coupled closing parts (trial_coupling.cpp).
  bool heldLink(int link) const;
  double exactDistance(int link, const Eigen::Isometry3d& t, bool facing_shift);
  double evalStill();
  void coupledTouch(const std::vector<int>& touching);
  void shiftFirstTouch(const std::vector<int>& touching);
  void startShift(int group, int link);
  Eigen::Vector3d shiftVelocity() const;
  void completeGroup(int group, const std::vector<int>& links);
  void stopGroup(int group, int link);
  void endShift();
  void settleStopped(const std::vector<int>& touching);
  // Squeeze parts.
  std::vector<SqueezeContact> pressingContacts();
  double deepestSqueezed(const std::vector<int>& squeezed, const Eigen::VectorXd& qq);
  bool squeezedTooDeep(const std::vector<int>& squeezed, const Eigen::VectorXd& qq, double limit);
  void limitSqueeze(const Eigen::VectorXd& q_contact);
  // Contacts parts.
  void linkContacts(int link, std::vector<char>* finger_touch);
  bool selfPenetrating() const;
  // Ends the trial with `status`.
  void finish(GraspStatus status, const std::string& msg);
  double lap();

  const SimModel& m_;
  const double tol_;
  // FailureDetail::kStatus: no_palm_contact may be decided during the retraction (palm grasps
  // that require the palm, automatic retraction limit); the judge's status before contacts.
  const bool status_only_;
  const bool early_no_palm_;
  GraspResult res_;
  GraspStats& st_;
  Clock::time_point t0_;

  Eigen::Isometry3d palm_;
  /// Metres along a_ the reported pose lies behind palm_: the palm's squeeze, once placePalm
  /// pressed it (the pose is reported with the palm touching, not pressed into the object).
  double pressed_ = 0.0;
  Eigen::Vector3d p0_, a_;
  Eigen::VectorXd q_;
  std::vector<Eigen::Isometry3d> lp_;  // link poses in the palm frame at q_ (or last evaluated)
  std::vector<double> dist_;           // last signed distance per link
  std::size_t first_ = 0;              // evalAll: the shaped link tried first
  std::size_t near_ = 0;               // evalNearest: the shaped link tried first

  // Closing bookkeeping, per closing joint and per link.
  std::vector<char> active_;
  std::vector<int> stop_link_;
  std::vector<double> dir_;
  std::vector<int> mov_;   // links moved by an active closing joint
  std::vector<int> eval_;  // links evaluated per step: mov_, or every shaped link while shifting
  std::vector<Eigen::Isometry3d> world_;
  std::vector<Eigen::Vector3d> centre_;  // evalMoving: each link's bounding sphere's centre
  // evalMoving: per link and self-collision partner (m_.partners' layout), the last separating
  // axis of the pair in the link's frame (CollisionScene::linkLinkDistance; zero: none yet).
  std::vector<std::vector<Eigen::Vector3d>> pair_axis_;
  // evalMoving: per link and partner, the last evaluation that asked the pair from this link
  // and whether that call proved the pair apart without GJK (pairSelfDistance).
  std::vector<std::vector<char>> pair_apart_;
  std::vector<std::vector<long>> pair_eval_;
  long eval_id_ = 0;
  // Lean queries: per link, what its last kSeen closing evaluations saw (a ring; the squeeze's
  // contacts read the one at the pose where the link stopped) and the next slot.
  static constexpr std::size_t kSeen = 8;
  std::vector<std::array<SeenTriangles, kSeen>>* seen_ = nullptr;
  std::vector<std::size_t> seen_next_;
  const SeenTriangles* seenAt(int link, const Eigen::Isometry3d& pose) const;
  std::vector<std::vector<int>> press_extra_;  // per closing joint: more links to squeeze
  // Coupled closing: the group shifting the hand (-1: none), the touching link it holds in place
  // (and its finger), the contact point in that link's frame, the palm velocity per unit
  // closing time, and per link the signed distance below which a link blocks the shift.
  int shift_group_ = -1;
  int held_link_ = -1;
  int held_finger_ = -1;
  Eigen::Vector3d held_point_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d shift_vel_ = Eigen::Vector3d::Zero();
  std::vector<double> floor_;
  bool step_limit_ = false;
  bool self_ = false;
};

}  // namespace taskmap
