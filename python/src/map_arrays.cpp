// taskmap.TaskMap's stored data as numpy arrays (copies; the map is read-only): what the map
// file holds per grasp (mapstore/SCHEMA.md), in its units (metres, radians, object frame).
#include "map_arrays.hpp"

#include "core_docs.hpp"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>
#include <vector>

#include "taskmap/core/error.hpp"

namespace py = pybind11;

namespace taskmap {
namespace {

template <class T>
py::array_t<T> array(const std::vector<T>& v) {
  return py::array_t<T>(static_cast<py::ssize_t>(v.size()), v.data());
}

py::array_t<bool> boolArray(const std::vector<std::uint8_t>& v) {
  py::array_t<bool> a(static_cast<py::ssize_t>(v.size()));
  auto m = a.mutable_unchecked<1>();
  for (std::size_t i = 0; i < v.size(); ++i) m(static_cast<py::ssize_t>(i)) = v[i] != 0;
  return a;
}

const MapValidation* labels(const TaskMap& t) {
  return t.data().validation ? &*t.data().validation : nullptr;
}

/// Contacts of grasp i as a dict of arrays (points, normals, depths, links, link_names).
py::dict contactsOf(const TaskMap& t, std::size_t i) {
  const MapGrasps& g = t.data().grasps;
  if (i >= g.size())
    throw py::index_error("contacts: grasp " + std::to_string(i) + " out of range (the map has " +
                          std::to_string(g.size()) + ")");
  if (!g.contacts_available) throw Error("contacts: this map stores no contacts (an imported map)");
  const auto b = static_cast<Eigen::Index>(g.contact_offsets[i]);
  const auto n = static_cast<Eigen::Index>(g.contact_offsets[i + 1]) - b;
  py::dict d;
  d["points"] = RowMatrixXd(g.contact_points.middleRows(b, n));
  d["normals"] = RowMatrixXd(g.contact_normals.middleRows(b, n));
  const auto first = g.contact_depths.begin() + b;
  d["depths"] = array(std::vector<double>(first, first + n));
  const auto lf = g.contact_links.begin() + b;
  const std::vector<std::int32_t> links(lf, lf + n);
  d["links"] = array(links);
  py::list names;
  for (const std::int32_t l : links) {
    const auto& all = t.data().hand.link_names;
    names.append(l >= 0 && static_cast<std::size_t>(l) < all.size()
                     ? py::object(py::str(all[static_cast<std::size_t>(l)]))
                     : py::object(py::none()));
  }
  d["link_names"] = names;
  return d;
}

/// The robust hold labels (the default build's, `taskmap validate --robust`), None without them.
void bindRobustLabels(py::class_<TaskMap>& cls) {
  cls.def_property_readonly(
         "robust",
         [](const TaskMap& t) -> py::object {
           const MapValidation* v = labels(t);
           if (!v || v->robust_json.empty()) return py::none();
           return array(v->robust);
         },
         "N robust hold labels (built maps, taskmap.validate(robust=True)): 1 the grasp holds "
         "under every variant within the margin, 0 not, 255 not tested; None without them.")
      .def_property_readonly(
          "robust_share",
          [](const TaskMap& t) -> py::object {
            const MapValidation* v = labels(t);
            if (!v || v->robust_json.empty()) return py::none();
            return array(v->robust_share);
          },
          "N shares of the robust label's variants held (-1 not tested), or None.")
      .def_property_readonly(
          "hold_margin",
          [](const TaskMap& t) -> py::object {
            const MapValidation* v = labels(t);
            if (!v || v->robust_json.empty()) return py::none();
            py::array_t<double> a({static_cast<py::ssize_t>(v->robust.size()), py::ssize_t{2}});
            auto m = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < v->robust.size(); ++i) {
              m(static_cast<py::ssize_t>(i), 0) = v->push_translation[i];
              m(static_cast<py::ssize_t>(i), 1) = v->push_rotation[i];
            }
            return std::move(a);
          },
          "N x 2: the object's largest displacement (metres) and rotation (radians) from its "
          "closed state under the pushes, over the robust label's variants (-1 not tested); "
          "or None.")
      .def_property_readonly(
          "robust_variants",
          [](const TaskMap& t) -> py::object {
            const MapValidation* v = labels(t);
            if (!v || v->robust_json.empty()) return py::none();
            const auto k = static_cast<py::ssize_t>(v->variantCount());
            py::array_t<std::uint8_t> a({static_cast<py::ssize_t>(v->robust.size()), k});
            std::copy(v->variant_held.begin(), v->variant_held.end(), a.mutable_data());
            return std::move(a);
          },
          "N x V: per grasp and robust variant (names: robust_params['variants']), 1 held, 0 "
          "failed, 255 not tested; or None.")
      .def_property_readonly(
          "robust_params",
          [](const TaskMap& t) -> py::object {
            const MapValidation* v = labels(t);
            if (!v || v->robust_json.empty()) return py::none();
            return py::module_::import("json").attr("loads")(v->robust_json);
          },
          "The robust label's variants (names, test order) and thresholds as a dict "
          "(/validation robust_json), or None.");
  ;
}

}  // namespace

void bindTaskMapArrays(py::class_<TaskMap>& cls) {
  cls.def_property_readonly(
         "joints", [](const TaskMap& t) { return t.data().grasps.joints; },
         "N x J joint values (radians; metres for prismatic joints), order of joint_names.")
      .def_property_readonly(
          "joint_names", [](const TaskMap& t) { return t.data().hand.joint_names; },
          "The hand's actuated joints, columns of joints.")
      .def_property_readonly(
          "link_names", [](const TaskMap& t) { return t.data().hand.link_names; },
          "The hand's links; contact_links index it (empty for imported maps).")
      .def_property_readonly(
          "force_closure",
          [](const TaskMap& t) { return boolArray(t.data().grasps.force_closure); },
          "N booleans: the grasp's recorded contacts are force closure.")
      .def_property_readonly(
          "volume", [](const TaskMap& t) { return array(t.data().grasps.volume); },
          "N wrench-space volumes (0 when not computed; params 'volume').")
      .def_property_readonly(
          "contact_offsets",
          [](const TaskMap& t) { return array(t.data().grasps.contact_offsets); },
          "N + 1 offsets: grasp i's contacts are rows contact_offsets[i]:contact_offsets[i+1].")
      .def_property_readonly(
          "contact_points", [](const TaskMap& t) { return t.data().grasps.contact_points; },
          "M x 3 contact points, metres, object frame.")
      .def_property_readonly(
          "contact_normals", [](const TaskMap& t) { return t.data().grasps.contact_normals; },
          "M x 3 outward unit surface normals, object frame.")
      .def_property_readonly(
          "contact_depths", [](const TaskMap& t) { return array(t.data().grasps.contact_depths); },
          "M penetration depths, metres.")
      .def_property_readonly(
          "contact_links", [](const TaskMap& t) { return array(t.data().grasps.contact_links); },
          "M hand link indices (into link_names).")
      .def("contacts", &contactsOf, py::arg("i"), pydoc::kContacts)
      .def_property_readonly(
          "hold",
          [](const TaskMap& t) -> py::object {
            const MapValidation* v = labels(t);
            if (!v) return py::none();
            return array(v->hold);
          },
          "N physics hold labels (taskmap.validate): 1 holds, 0 does not, 255 not tested; "
          "None when the map was not validated.")
      .def_property_readonly(
          "hold_translation",
          [](const TaskMap& t) -> py::object {
            const MapValidation* v = labels(t);
            return v ? py::object(array(v->translation)) : py::object(py::none());
          },
          "N largest object displacements in the hold test, metres (-1 not tested), or None.")
      .def_property_readonly(
          "hold_rotation",
          [](const TaskMap& t) -> py::object {
            const MapValidation* v = labels(t);
            return v ? py::object(array(v->rotation)) : py::object(py::none());
          },
          "N largest object rotations in the hold test, radians (-1 not tested), or None.")
      .def_property_readonly(
          "hold_direction",
          [](const TaskMap& t) -> py::object {
            const MapValidation* v = labels(t);
            return v ? py::object(array(v->direction)) : py::object(py::none());
          },
          "N first failing pushes 0..5 (-x +x -y +y -z +z of the object frame), -1 none; or "
          "None.");
  bindRobustLabels(cls);
}

}  // namespace taskmap
