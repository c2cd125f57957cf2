#pragma once
// Private to hands: the steps of readMjcfModel (mjcf_model.hpp). The driver (mjcf_reader.cpp)
// reads the compiler settings and mesh assets, then the body tree (mjcf_bodies.cpp: links,
// joints, collision geoms, inertials), the joint couplings (equalities), the actuators and
// fixed tendons (mjcf_actuators.cpp) and the contact exclusions.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mjcf_document.hpp"
#include "taskmap/hands/mjcf_model.hpp"

namespace taskmap::detail {

/// The <compiler> settings taskmap uses (every <compiler> element, later ones overriding).
struct MjcfCompiler {
  bool degrees = true;             ///< angle="degree" (MuJoCo's default) or "radian"
  std::string eulerseq = "xyz";    ///< euler sequence: lower case moving axes, upper case fixed
  std::string meshdir;             ///< mesh folder relative to the model's folder
  bool autolimits = true;          ///< a range without `limited` limits (MuJoCo >= 2.3's default)
  bool inertia_from_geom = false;  ///< inertiafromgeom="true": <inertial>s are ignored
};

/// A mesh asset.
struct MjcfMesh {
  std::string file;  ///< relative to the model's folder ("" for inline vertices)
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  std::vector<Eigen::Vector3d> vertices;  ///< inline <mesh vertex>
  const TiXmlElement* at = nullptr;
};

/// Orientation of an element from the one of quat, axisangle, euler, xyaxes, zaxis it has (else
/// its default class's when `tags` is not empty; else identity). Throws Error on two forms.
Eigen::Quaterniond mjcfOrientation(const MjcfDocument& doc, const MjcfDefaults& defaults,
                                   const MjcfCompiler& compiler, const TiXmlElement* e,
                                   const std::vector<const char*>& tags, int cls);
/// The rotation that takes +z to the direction d (MuJoCo's rule: a half turn about x for -z).
Eigen::Quaterniond mjcfZToDirection(const Eigen::Vector3d& d);

/// Reads one MJCF hand: a step per section, each filling out_.
class MjcfReader {
 public:
  MjcfReader(const std::string& xml, const std::string& path);
  /// Runs every step and returns the model.
  MjcfModel read();

 private:
  // ---- mjcf_reader.cpp ----
  void readCompiler();
  void readMeshes();
  void readEqualities();
  void readContact();
  /// Joint index of the joint named by attribute `attr` of e (which must exist).
  int jointNamed(const TiXmlElement* e, const char* attr) const;
  std::optional<MjcfAttr> find(const TiXmlElement* e, const char* tag, int cls,
                               const char* name) const {
    return defaults_.find(e, {tag}, cls, name);
  }
  double number(const TiXmlElement* e, const char* tag, int cls, const char* name,
                double fallback) const;
  /// The first n numbers of attribute `name`, each from the nearest definition that has it
  /// (MuJoCo reads such attributes in part: the missing trailing numbers keep the class's).
  std::vector<std::optional<double>> components(const TiXmlElement* e, const char* tag, int cls,
                                                const char* name, std::size_t n) const;

  // ---- mjcf_bodies.cpp ----
  /// Where a body's contents attach: its last link, and the body frame in that link's frame.
  struct Scope {
    int link = -1;
    Eigen::Isometry3d in_link = Eigen::Isometry3d::Identity();
  };
  void readWorld();
  void collectTopBodies(const TiXmlElement* e, std::vector<const TiXmlElement*>* bodies, int depth);
  void addBody(const TiXmlElement* b, const Scope& parent, const Eigen::Isometry3d& pose, int cls,
               int depth);
  int addLinks(const TiXmlElement* b, const std::string& name, const Scope& parent,
               const Eigen::Isometry3d& pose, int cls, Scope* scope);
  void readJoint(const TiXmlElement* j, int cls, UrdfJoint* joint, JointDynamics* dyn);
  void addInertial(const TiXmlElement* i, const Scope& scope);
  void addContents(const TiXmlElement* container, const Scope& scope,
                   const Eigen::Isometry3d& frame, int cls, int depth);
  void addGeom(const TiXmlElement* g, const Scope& scope, const Eigen::Isometry3d& frame, int cls);
  void geomShape(const TiXmlElement* g, int cls, const std::string& type, UrdfShape* shape);
  ShapeContact geomContact(const TiXmlElement* g, int cls) const;
  const MjcfMesh& meshOf(const TiXmlElement* g, int cls) const;

  // ---- mjcf_actuators.cpp ----
  struct TendonJoint {
    int joint;
    double coef;
  };
  void readTendons();
  void readActuators();
  void addActuator(const TiXmlElement* a);
  int coupleTendon(const TiXmlElement* a, const std::string& tendon, double* gear);
  ActuatorDynamics servoOf(const TiXmlElement* a, int cls, double gear, int joint) const;

  MjcfDocument doc_;
  MjcfDefaults defaults_;
  MjcfCompiler compiler_;
  std::map<std::string, MjcfMesh> meshes_;
  std::map<std::string, int> joints_;  // joint name -> index into tree.joints
  std::map<std::string, int> bodies_;  // body name -> its last link
  std::map<std::string, std::vector<TendonJoint>> fixed_tendons_;
  std::set<std::string> spatial_tendons_;
  std::set<std::string> coupled_tendons_;
  std::set<int> followers_;               // joints a fixed tendon couples to its driver
  std::set<std::string> missing_visual_;  // visual mesh files already warned about
  std::vector<int> body_count_;           // [0]: bodies, [1]: joints (MuJoCo ids of unnamed)
  MjcfModel out_;
};

}  // namespace taskmap::detail
