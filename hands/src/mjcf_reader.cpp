// readMjcfModel (mjcf_model.hpp): a short driver over MjcfReader's steps (mjcf_reader.hpp), and
// the steps of the model-wide sections: <compiler>, mesh assets, joint couplings (<equality>),
// contact exclusions.
#include <algorithm>
#include <filesystem>

#include "mjcf_reader.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace detail {
namespace {

namespace fs = std::filesystem;

/// Top-level sections of MJCF: those taskmap reads, and those it may skip (they do not change
/// the hand's kinematics, geometry or dynamics as the validator models them).
const std::set<std::string> kSections = {
    "compiler",  "option",   "size",   "visual",    "statistic",  "default",
    "extension", "custom",   "asset",  "contact",   "deformable", "equality",
    "tendon",    "actuator", "sensor", "worldbody", "keyframe"};

}  // namespace

MjcfReader::MjcfReader(const std::string& xml, const std::string& path)
    : doc_(xml, path), defaults_(doc_), body_count_{0, 0} {}

MjcfModel MjcfReader::read() {
  for (const TiXmlElement* s : doc_.children(doc_.root()))
    if (kSections.count(s->Value()) == 0)
      doc_.fail(s, std::string("<") + s->Value() + "> is not an MJCF section taskmap knows");
  const char* model = doc_.root()->Attribute("model");
  out_.tree.name = model ? model : "MuJoCo Model";
  out_.dynamics.source = "MJCF";
  readCompiler();
  readMeshes();
  readWorld();
  readEqualities();
  readTendons();
  readActuators();
  readContact();
  out_.files = doc_.files();
  return std::move(out_);
}

void MjcfReader::readCompiler() {
  bool meshdir_set = false;
  for (const TiXmlElement* c : doc_.children(doc_.root(), "compiler")) {
    if (const char* a = c->Attribute("angle")) {
      const std::string v = a;
      if (v != "degree" && v != "radian") doc_.fail(c, "angle must be degree or radian");
      compiler_.degrees = v == "degree";
    }
    if (const char* s = c->Attribute("eulerseq")) {
      const std::string v = s;
      if (v.size() != 3 || v.find_first_not_of("xyzXYZ") != std::string::npos)
        doc_.fail(c, "eulerseq='" + v + "' must be three of x, y, z, X, Y, Z");
      compiler_.eulerseq = v;
    }
    if (const char* d = c->Attribute("meshdir")) {
      compiler_.meshdir = d;
      meshdir_set = true;
    }
    if (const char* d = c->Attribute("assetdir"); d && !meshdir_set) compiler_.meshdir = d;
    if (const char* a = c->Attribute("autolimits"))
      compiler_.autolimits = mjcfBool(doc_, {a, c}, "autolimits", false) == 1;
    if (const char* i = c->Attribute("inertiafromgeom"))
      compiler_.inertia_from_geom = std::string(i) == "true";
    if (const char* g = c->Attribute("coordinate"); g && std::string(g) == "global")
      doc_.fail(c, "coordinate='global' is not supported (MuJoCo dropped it too): use local");
  }
}

void MjcfReader::readMeshes() {
  for (const TiXmlElement* section : doc_.children(doc_.root(), "asset"))
    for (const TiXmlElement* m : doc_.children(section, "mesh")) {
      const int cls = defaults_.classOf(m, defaults_.main());
      MjcfMesh mesh;
      mesh.at = m;
      const char* file = m->Attribute("file");
      const char* name = m->Attribute("name");
      if (file) {
        const fs::path f(file);
        mesh.file =
            (f.is_absolute() ? f : fs::path(compiler_.meshdir) / f).lexically_normal().string();
      } else if (auto v = m->Attribute("vertex")) {
        const auto xyz = mjcfNumbers(doc_, {v, m}, "vertex", 12, 3 * 100000);
        if (xyz.size() % 3 != 0) doc_.fail(m, "vertex needs x y z triples");
        for (std::size_t i = 0; i < xyz.size(); i += 3)
          mesh.vertices.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
      } else {
        doc_.fail(m, "a mesh needs a file or vertex attribute (taskmap reads no other source)");
      }
      if (auto s = find(m, "mesh", cls, "scale")) {
        const auto v = mjcfNumbers(doc_, *s, "scale", 3, 3);
        mesh.scale = Eigen::Vector3d(v[0], v[1], v[2]);
      }
      for (const char* moved : {"refpos", "refquat"})
        if (m->Attribute(moved)) doc_.fail(m, std::string(moved) + " is not supported");
      const std::string key = name ? name : fs::path(file ? file : "").stem().string();
      if (key.empty()) doc_.fail(m, "an inline mesh needs a name");
      if (!meshes_.emplace(key, std::move(mesh)).second)
        doc_.fail(m, "mesh '" + key + "' is defined twice");
    }
}

int MjcfReader::jointNamed(const TiXmlElement* e, const char* attr) const {
  const char* name = e->Attribute(attr);
  if (!name) doc_.fail(e, std::string("needs a ") + attr + " attribute");
  const auto it = joints_.find(name);
  if (it == joints_.end())
    doc_.fail(e, std::string(attr) + "='" + name + "' names no hinge or slide joint of the model");
  return it->second;
}

double MjcfReader::number(const TiXmlElement* e, const char* tag, int cls, const char* name,
                          double fallback) const {
  const auto a = find(e, tag, cls, name);
  return a ? mjcfNumbers(doc_, *a, name, 1, 1)[0] : fallback;
}

std::vector<std::optional<double>> MjcfReader::components(const TiXmlElement* e, const char* tag,
                                                          int cls, const char* name,
                                                          std::size_t n) const {
  std::vector<std::optional<double>> out(n);
  for (const MjcfAttr& a : defaults_.findAll(e, {tag}, cls, name)) {
    const auto v = mjcfNumbers(doc_, a, name, 1, n);
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!out[k]) out[k] = v[k];
  }
  return out;
}

void MjcfReader::readEqualities() {
  for (const TiXmlElement* section : doc_.children(doc_.root(), "equality"))
    for (const TiXmlElement* q : doc_.children(section)) {
      const std::string type = q->Value();
      const int cls = defaults_.classOf(q, defaults_.main());
      if (auto a = find(q, "equality", cls, "active");
          a && mjcfBool(doc_, *a, "active", false) == 0)
        continue;  // an inactive constraint couples nothing
      if (type != "joint")
        doc_.fail(q, "<" + type +
                         "> constraints close kinematic loops or couple tendons, which taskmap "
                         "cannot model: a hand's couplings must be <joint> equalities (mimic)");
      const int j1 = jointNamed(q, "joint1");
      if (!q->Attribute("joint2"))
        doc_.fail(q,
                  "a joint equality without joint2 locks joint1 at a constant, which taskmap "
                  "cannot model: make that joint part of the body (no joint)");
      const int j2 = jointNamed(q, "joint2");
      if (j1 == j2) doc_.fail(q, "couples a joint to itself");
      UrdfJoint& joint = out_.tree.joints[static_cast<std::size_t>(j1)];
      if (joint.mimic) doc_.fail(q, "joint '" + joint.name + "' is coupled twice");
      std::vector<double> c = {0, 1, 0, 0, 0};
      if (auto p = find(q, "equality", cls, "polycoef")) {
        const auto v = mjcfNumbers(doc_, *p, "polycoef", 1, 5);
        std::copy(v.begin(), v.end(), c.begin());
      }
      if (c[2] != 0.0 || c[3] != 0.0 || c[4] != 0.0)
        doc_.fail(q,
                  "polycoef has non-linear terms; taskmap couples joints linearly (q1 = a0 + "
                  "a1 q2)");
      joint.mimic = UrdfMimic{out_.tree.joints[static_cast<std::size_t>(j2)].name, c[1], c[0]};
      JointDynamics& d = out_.dynamics.joints[static_cast<std::size_t>(j1)];
      if (auto r = find(q, "equality", cls, "solref")) {
        const auto v = mjcfNumbers(doc_, *r, "solref", 2, 2);
        d.coupling_solref = std::array<double, 2>{v[0], v[1]};
      }
      if (auto i = find(q, "equality", cls, "solimp")) {
        const auto v = mjcfNumbers(doc_, *i, "solimp", 3, 5);
        d.coupling_solimp = std::array<double, 5>{v[0], v[1], v[2], v.size() > 3 ? v[3] : 0.5,
                                                  v.size() > 4 ? v[4] : 2.0};
      }
    }
}

void MjcfReader::readContact() {
  for (const TiXmlElement* section : doc_.children(doc_.root(), "contact"))
    for (const TiXmlElement* x : doc_.children(section, "exclude")) {
      std::array<int, 2> pair{};
      for (int k = 0; k < 2; ++k) {
        const char* attr = k == 0 ? "body1" : "body2";
        const char* name = x->Attribute(attr);
        if (!name) doc_.fail(x, std::string("needs ") + attr);
        const auto it = bodies_.find(name);
        if (it == bodies_.end())
          doc_.fail(x, std::string(attr) + "='" + name + "' names no body of the hand");
        pair[static_cast<std::size_t>(k)] = it->second;
      }
      if (pair[0] > pair[1]) std::swap(pair[0], pair[1]);
      auto& pairs = out_.dynamics.excluded_pairs;
      if (std::find(pairs.begin(), pairs.end(), pair) == pairs.end()) pairs.push_back(pair);
    }
}

}  // namespace detail

MjcfModel readMjcfModel(const std::string& xml, const std::string& path) {
  return detail::MjcfReader(xml, path).read();
}

bool isMjcfText(const std::string& xml) {
  // The first start tag that is not a declaration, comment or processing instruction.
  std::size_t i = 0;
  while ((i = xml.find('<', i)) != std::string::npos) {
    if (xml.compare(i, 4, "<!--") == 0) {
      const std::size_t end = xml.find("-->", i + 4);
      if (end == std::string::npos) return false;
      i = end + 3;
    } else if (xml.compare(i, 2, "<?") == 0 || xml.compare(i, 2, "<!") == 0) {
      ++i;
    } else {
      return xml.compare(i, 7, "<mujoco") == 0 &&
             (i + 7 == xml.size() ||
              std::string(" \t\r\n>/").find(xml[i + 7]) != std::string::npos);
    }
  }
  return false;
}

}  // namespace taskmap
