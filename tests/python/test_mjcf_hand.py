"""An MJCF hand from Python (issue 52): the real LEAP hand as MuJoCo Menagerie publishes it
(tests/data/real/hands/leap_hand_mjcf) through taskmap.hand_info, hand_init, build, validate and
view, giving what the command-line tool gives (the same JSON, draft and map bytes)."""
import json
import os
import shutil
import tempfile
import unittest

SRC = os.environ["TASKMAP_SOURCE_DIR"]
LEAP = os.path.join(SRC, "tests", "data", "real", "hands", "leap_hand_mjcf", "right_hand.xml")
BANANA = os.path.join(SRC, "tests", "data", "real", "objects", "ycb_011_banana.obj")

from cli_support import cli, read  # noqa: E402
import taskmap  # noqa: E402


class MjcfHandTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="taskmap_mjcf_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.tmp, name)

    def test_hand_info_is_what_the_cli_prints(self):
        code, out, err = cli("hand-info", "--json", LEAP)
        self.assertEqual(code, 0, err)
        info = taskmap.hand_info(LEAP)
        self.assertEqual(info, json.loads(out))
        self.assertEqual(info["format"], "MJCF")
        self.assertEqual(len(info["model_warnings"]), 8)

    def test_hand_init_drafts_what_the_cli_drafts(self):
        code, _, err = cli("hand-init", "-o", self.path("cli.hand.json"), LEAP)
        self.assertEqual(code, 0, err)
        draft = taskmap.hand_init(LEAP, output=self.path("py.hand.json"))
        self.assertEqual(read(self.path("py.hand.json")), read(self.path("cli.hand.json")))
        self.assertEqual(draft["sidecar"]["palm_link"], "palm")

    def test_build_and_validate_as_the_cli(self):
        code, _, err = cli("build", "--object", BANANA, "--hand", LEAP, "--valid", "6", "--seed",
                           "2", "--hold-test", "off", "-q", "-o", self.path("cli.h5"))
        self.assertEqual(code, 0, err)
        m = taskmap.build(object=BANANA, hand=LEAP, output=self.path("py.h5"), valid=6, seed=2,
                          hold_test="off")
        self.assertEqual(read(self.path("py.h5")), read(self.path("cli.h5")))
        self.assertEqual(len(m), 6)
        s = taskmap.validate(self.path("py.h5"), grasps=1, threads=1,
                             output=self.path("stated.h5"))
        self.assertEqual(s["tested"], 1)
        p = taskmap.validate(self.path("py.h5"), grasps=1, threads=1, stated_dynamics=False,
                             output=self.path("protocol.h5"))
        self.assertEqual(p["tested"], 1)
        page = taskmap.view(self.path("py.h5"), output=self.path("py.html"))
        self.assertTrue(os.path.getsize(self.path("py.html")) > 10000, page)


if __name__ == "__main__":
    unittest.main()
