"""The regression suite must fail, with a readable table, when grasps change.

Runs `taskmap regress` on the paper's case (basket, three-finger hand) once as built and once
with the friction coefficient altered from 0.5 to 0.3, a change that alters which grasps are
force closure and their epsilon. The first run must pass, the second must fail and say where.
"""
import json
import os
import subprocess
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
CLI = os.environ["TASKMAP_CLI"]
CASES = os.path.join(HERE, "cases.json")
PAPER_CASE = "basket_barrett"


def regress(*extra):
    return subprocess.run([CLI, "regress", "--cases", CASES, "--only", PAPER_CASE, *extra],
                          capture_output=True, text=True, timeout=1200)


class RegressionDetectsDrift(unittest.TestCase):
    def test_golden_records_the_three_handle_clusters(self):
        with open(os.path.join(HERE, "golden", PAPER_CASE + ".json")) as f:
            golden = json.load(f)
        self.assertGreaterEqual(golden["clusters"], 3, "the paper's basket map has >= 3 clusters")
        self.assertEqual(len(golden["representatives"]), golden["clusters"])

    def test_altered_friction_fails_with_a_table(self):
        altered = regress("--friction", "0.3")
        self.assertEqual(altered.returncode, 1, altered.stdout + altered.stderr)
        out = altered.stdout
        self.assertIn("statistic", out)
        self.assertIn("golden", out)
        self.assertIn("verdict", out)
        failed = [line for line in out.splitlines() if line.rstrip().endswith("FAIL")]
        self.assertTrue(failed, out)
        # Lower friction: fewer force-closure grasps and a different epsilon distribution.
        self.assertTrue(any("epsilon" in line or "valid" in line for line in failed), out)
        self.assertRegex(out, r"regress: 1 case\(s\), [1-9][0-9]* statistic\(s\) failed")


if __name__ == "__main__":
    unittest.main()
