"""taskmap.TaskMap's stored data as numpy arrays (python/src/map_arrays.cpp) against h5py, an
independent reader of the same file (mapstore/SCHEMA.md), on the checked-in reference map
(meshes/maps/basket_humanoid.h5: humanoid hand, basket, grasps validated in physics)."""
import os
import unittest

import h5py
import numpy as np

import taskmap

MAP = os.path.join(os.environ.get("TASKMAP_SOURCE_DIR", ""), "meshes", "maps",
                   "basket_humanoid.h5")


def names(dataset):
    return [n.decode() if isinstance(n, bytes) else str(n) for n in dataset[:]]


class MapArraysTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.map = taskmap.load(MAP)
        cls.f = h5py.File(MAP, "r")

    @classmethod
    def tearDownClass(cls):
        cls.f.close()

    def test_grasp_arrays_match_the_file(self):
        g = self.f["grasps"]
        n = len(self.map)
        for attr, key in [("poses", "pose"), ("joints", "joints"), ("epsilon", "epsilon"),
                          ("volume", "volume"), ("contact_offsets", "contact_offsets"),
                          ("contact_points", "contact_points"),
                          ("contact_normals", "contact_normals"),
                          ("contact_depths", "contact_depths"), ("contact_links", "contact_links"),
                          ("labels", "cluster")]:
            value = getattr(self.map, attr)
            self.assertIsInstance(value, np.ndarray, attr)
            np.testing.assert_array_equal(value, g[key][:], err_msg=attr)
        self.assertEqual(self.map.joints.shape, (n, len(self.map.joint_names)))
        np.testing.assert_array_equal(self.map.force_closure, g["force_closure"][:] != 0)
        self.assertEqual(self.map.force_closure.dtype, np.bool_)
        self.assertEqual(self.map.joint_names, names(self.f["hand/joint_names"]))
        self.assertEqual(self.map.link_names, names(self.f["hand/link_names"]))

    def test_contacts_of_one_grasp_name_their_links(self):
        offsets = self.f["grasps/contact_offsets"][:]
        link_names = names(self.f["hand/link_names"])
        for i in (0, len(self.map) // 2, len(self.map) - 1):
            c = self.map.contacts(i)
            rows = slice(offsets[i], offsets[i + 1])
            np.testing.assert_array_equal(c["points"], self.f["grasps/contact_points"][rows])
            np.testing.assert_array_equal(c["normals"], self.f["grasps/contact_normals"][rows])
            np.testing.assert_array_equal(c["depths"], self.f["grasps/contact_depths"][rows])
            links = self.f["grasps/contact_links"][rows]
            np.testing.assert_array_equal(c["links"], links)
            self.assertEqual(c["link_names"], [link_names[l] for l in links])
            self.assertGreater(len(c["link_names"]), 0)
        with self.assertRaises(IndexError):
            self.map.contacts(len(self.map))

    def test_hold_labels_match_the_file(self):
        g = self.f["grasps"]
        np.testing.assert_array_equal(self.map.hold, g["hold"][:])
        np.testing.assert_array_equal(self.map.hold_translation, g["hold_translation"][:])
        np.testing.assert_array_equal(self.map.hold_rotation, g["hold_rotation"][:])
        np.testing.assert_array_equal(self.map.hold_direction, g["hold_direction"][:])
        self.assertTrue((self.map.hold == 1).all())  # the reference map keeps holding grasps

    def test_a_map_without_labels_has_none(self):
        m = taskmap.TaskMap.from_arrays(self.map.poses[:5], self.map.epsilon[:5])
        self.assertIsNone(m.hold)
        self.assertIsNone(m.hold_translation)
        self.assertEqual(m.joints.size, 0)  # no hand joints stored


if __name__ == "__main__":
    unittest.main()
