"""quality_hull.py: the lower convex hull of (rate, distortion) points and its rate at a given
distortion, on hand-made points with known answers."""

import unittest

import quality_hull


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


if __name__ == "__main__":
    unittest.main()
