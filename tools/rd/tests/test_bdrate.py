"""BD-rate and BD-quality on hand-made curves with known answers."""

import math
import unittest

from tdvo_rd import bdrate

# A made-up anchor: four rate points, quality rising with rate, not a straight line in log rate.
ANCHOR_RATE = [100.0, 180.0, 350.0, 700.0]
ANCHOR_QUALITY = [30.0, 33.5, 36.0, 39.5]


class BdRateTest(unittest.TestCase):
    def test_identical_curves_give_zero(self):
        for method in bdrate.METHODS:
            with self.subTest(method=method):
                self.assertAlmostEqual(bdrate.bd_rate(ANCHOR_RATE, ANCHOR_QUALITY, ANCHOR_RATE,
                                                      ANCHOR_QUALITY, method), 0.0, places=12)
                self.assertAlmostEqual(bdrate.bd_quality(ANCHOR_RATE, ANCHOR_QUALITY,
                                                         ANCHOR_RATE, ANCHOR_QUALITY, method),
                                       0.0, places=12)

    def test_ten_percent_less_rate_everywhere_gives_minus_ten_percent(self):
        test_rate = [0.9 * r for r in ANCHOR_RATE]
        for method in bdrate.METHODS:
            with self.subTest(method=method):
                self.assertAlmostEqual(bdrate.bd_rate(ANCHOR_RATE, ANCHOR_QUALITY, test_rate,
                                                      ANCHOR_QUALITY, method), -10.0, places=9)
                # And the anchor against the test: 1/0.9 - 1 = +11.1 %.
                self.assertAlmostEqual(bdrate.bd_rate(test_rate, ANCHOR_QUALITY, ANCHOR_RATE,
                                                      ANCHOR_QUALITY, method),
                                       (1 / 0.9 - 1) * 100, places=9)

    def test_one_db_better_everywhere_gives_plus_one_db(self):
        test_quality = [q + 1.0 for q in ANCHOR_QUALITY]
        for method in bdrate.METHODS:
            with self.subTest(method=method):
                self.assertAlmostEqual(bdrate.bd_quality(ANCHOR_RATE, ANCHOR_QUALITY, ANCHOR_RATE,
                                                         test_quality, method), 1.0, places=9)

    def test_linear_curves_have_the_closed_form_answer(self):
        # Quality linear in log10(rate) with slope 10 dB/decade for both curves and the test
        # 2 dB higher: at equal quality the test needs 10^(-2/10) of the rate.
        rates = [100.0, 200.0, 400.0, 800.0, 1600.0]
        anchor = [10 * math.log10(r) for r in rates]
        test = [q + 2.0 for q in anchor]
        for method in bdrate.METHODS:
            with self.subTest(method=method):
                self.assertAlmostEqual(bdrate.bd_rate(rates, anchor, rates, test, method),
                                       (10 ** -0.2 - 1) * 100, places=9)

    def test_point_order_does_not_matter(self):
        order = [2, 0, 3, 1]
        shuffled_rate = [ANCHOR_RATE[i] for i in order]
        shuffled_quality = [ANCHOR_QUALITY[i] for i in order]
        test_rate = [r * 0.8 for r in ANCHOR_RATE]
        self.assertAlmostEqual(
            bdrate.bd_rate(shuffled_rate, shuffled_quality, test_rate, ANCHOR_QUALITY),
            bdrate.bd_rate(ANCHOR_RATE, ANCHOR_QUALITY, test_rate, ANCHOR_QUALITY), places=12)

    def test_pchip_differs_from_the_polynomial_on_a_kinked_curve(self):
        # Both methods agree on smooth curves (above) but not in general: the test exercises
        # that the method argument is honoured.
        test_rate = [90.0, 200.0, 260.0, 800.0]
        a = bdrate.bd_rate(ANCHOR_RATE, ANCHOR_QUALITY, test_rate, ANCHOR_QUALITY, "pchip")
        b = bdrate.bd_rate(ANCHOR_RATE, ANCHOR_QUALITY, test_rate, ANCHOR_QUALITY, "cubic")
        self.assertGreater(abs(a - b), 1e-3)

    def test_curves_without_overlap_are_an_error(self):
        with self.assertRaisesRegex(bdrate.BdError, "do not overlap"):
            bdrate.bd_rate(ANCHOR_RATE, ANCHOR_QUALITY, ANCHOR_RATE, [q + 20 for q in
                                                                      ANCHOR_QUALITY])

    def test_too_few_points_are_an_error(self):
        with self.assertRaisesRegex(bdrate.BdError, "at least 4 points"):
            bdrate.bd_rate(ANCHOR_RATE[:3], ANCHOR_QUALITY[:3], ANCHOR_RATE[:3],
                           ANCHOR_QUALITY[:3], "cubic")
        with self.assertRaisesRegex(bdrate.BdError, "at least 2 points"):
            bdrate.bd_rate(ANCHOR_RATE[:1], ANCHOR_QUALITY[:1], ANCHOR_RATE[:1],
                           ANCHOR_QUALITY[:1], "pchip")

    def test_equal_qualities_are_an_error(self):
        with self.assertRaisesRegex(bdrate.BdError, "same value"):
            bdrate.bd_rate([1, 2, 3], [5, 5, 6], [1, 2, 3], [5, 6, 7])

    def test_quality_db(self):
        self.assertAlmostEqual(bdrate.quality_db(0.01, 1.0), 40.0)
        self.assertAlmostEqual(bdrate.quality_db(0.5, 5.0), 20.0)
        self.assertEqual(bdrate.quality_db(0.0, 1.0), math.inf)
        self.assertIsNone(bdrate.quality_db(None, 1.0))

    def test_report_quality_of_each_distortion(self):
        # Distances against the diagonal, the KG error against 100 %, STED against 1.
        from tdvo_rd import report
        row = {"D_A": "0.02", "kg_error": "1", "sted": "0.01", "sted_s": "0.1", "sted_t": "",
               "diagonal": "2"}
        self.assertAlmostEqual(report.quality(row, "D_A"), 40.0)
        self.assertAlmostEqual(report.quality(row, "kg_error"), 40.0)
        self.assertAlmostEqual(report.quality(row, "sted"), 40.0)
        self.assertAlmostEqual(report.quality(row, "sted_s"), 20.0)
        self.assertIsNone(report.quality(row, "sted_t"))  # a single frame: no temporal part
        self.assertEqual(report.GeometryKind.axis_label("sted"), "20·log10(1 / STED) [dB]")
        self.assertEqual(report.GeometryKind.axis_label("kg_error"),
                         "20·log10(100 % / KG error) [dB]")


if __name__ == "__main__":
    unittest.main()
