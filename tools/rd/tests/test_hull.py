"""quality_hull.py: the lower convex hull of (rate, distortion) points and its rate at a given
distortion, on hand-made points with known answers."""

import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import quality_hull
import quality_lambda_study


class HullTest(unittest.TestCase):
    def test_dominated_and_non_convex_points_are_dropped(self):
        points = [(100, 10.0), (150, 9.5),   # 150: barely better, above the segment 100 .. 200
                  (200, 5.0), (250, 6.0),    # 250: more rate and more distortion than 200
                  (400, 1.0), (1000, 0.9)]
        self.assertEqual(quality_hull.lower_hull(points),
                         [(100, 10.0), (200, 5.0), (400, 1.0), (1000, 0.9)])

    def test_rate_between_hull_vertices_is_linear(self):
        hull = [(100, 10.0), (200, 5.0), (400, 1.0)]
        self.assertAlmostEqual(quality_hull.hull_rate(hull, 7.5), 150.0)
        self.assertAlmostEqual(quality_hull.hull_rate(hull, 3.0), 300.0)
        self.assertAlmostEqual(quality_hull.hull_rate(hull, 10.0), 100.0)
        self.assertIsNone(quality_hull.hull_rate(hull, 0.5))   # finer than any point
        self.assertIsNone(quality_hull.hull_rate(hull, 20.0))  # coarser than any point


class LambdaStudyTest(unittest.TestCase):
    def test_candidates_reach_the_target_step(self):
        # An object of size 1023 at Quality 50: Δ = 1, grids of 10 .. 13 bits, steps 1 .. 8.
        cands, delta = quality_lambda_study.candidates(1023.0, 50)
        self.assertEqual(delta, 1023.0 / 1024)
        self.assertEqual(cands, [(10, 1), (11, 2), (12, 4), (13, 8)])

    def test_the_finer_slope_decides_where_the_model_is_too_small(self):
        # (bits, step) -> (R bits, D in units of Δ²). The model (λ = ln 2 / 6 = 0.1155) prefers
        # (10, 8): 200 + 0.1155 * 1000 = 315.5 against (9, 4): 260 + 0.1155 * 600 = 329.3.
        # Half (10, 8)'s step costs 400 bits for 160 less D: slope 0.4, and with it (9, 4) wins
        # (500 against 600). Twice the step saves 200 bits for 40 more D: slope 0.2, and (9, 4)
        # wins as well (380 against 400).
        points = {(9, 4): (600.0, 260.0), (10, 8): (1000.0, 200.0), (10, 4): (1400.0, 40.0),
                  (10, 16): (800.0, 240.0)}
        cands = [(9, 4), (10, 8)]
        self.assertEqual(quality_lambda_study.choose(points, cands, "model"), (10, 8))
        self.assertEqual(quality_lambda_study.choose(points, cands, "finer"), (9, 4))
        self.assertEqual(quality_lambda_study.choose(points, cands, "coarser"), (9, 4))
        # A finer coding that saves nothing keeps the model's choice.
        points[(10, 4)] = (1400.0, 210.0)
        self.assertEqual(quality_lambda_study.choose(points, cands, "finer"), (10, 8))


class PageTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="3dvo-hull-test-")
        self.addCleanup(shutil.rmtree, self.tmp, True)
        header = "sequence,mode,setting,kbit_s,kg_error\n"
        for name, rows in (("hull", "s,h,GridBits=10,100,1.0\ns,h,GridBits=12,400,0.1\n"),
                           ("quality", "s,quality,Quality=50,200,0.5\n")):
            os.makedirs(os.path.join(self.tmp, name))
            with open(os.path.join(self.tmp, name, "rd.csv"), "w") as f:
                f.write(header + rows)

    def run_hull(self, *extra):
        return subprocess.run([sys.executable, quality_hull.__file__,
                               os.path.join(self.tmp, "hull"), os.path.join(self.tmp, "quality"),
                               *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def test_writes_and_rewrites_its_own_page_only(self):
        page = os.path.join(self.tmp, "results-quality.md")
        # A file that bears the page's old temporary name is someone else's: it stays.
        bystander = os.path.join(self.tmp, ".tmp-results-quality.md")
        with open(bystander, "w") as f:
            f.write("someone's\n")
        self.assertEqual(self.run_hull("--out", page).returncode, 0)
        with open(bystander) as f:
            self.assertEqual(f.read(), "someone's\n")
        self.assertEqual(sorted(n for n in os.listdir(self.tmp) if n.startswith(".tmp-")),
                         [".tmp-results-quality.md"])  # no temporary file left
        with open(page) as f:
            first = f.read()
        self.assertIn("| Quality=50 | 200.0 | 0.5000 |", first)
        result = self.run_hull("--out", page)  # its own page: replaced
        self.assertEqual(result.returncode, 0, result.stderr)
        mine = os.path.join(self.tmp, "notes.md")
        with open(mine, "w") as f:
            f.write("# notes\n")
        result = self.run_hull("--out", mine)
        self.assertEqual(result.returncode, 1)
        self.assertIn("notes.md exists and is not a page this tool wrote", result.stderr)
        with open(mine) as f:
            self.assertEqual(f.read(), "# notes\n")
        result = subprocess.run([sys.executable, quality_hull.__file__, "/nonexistent", "x"],
                                stderr=subprocess.PIPE, text=True)
        self.assertEqual(result.returncode, 1)
        self.assertIn("quality_hull: error: /nonexistent/rd.csv: cannot read", result.stderr)


if __name__ == "__main__":
    unittest.main()
