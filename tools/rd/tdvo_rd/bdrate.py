"""Bjøntegaard delta rate (BD-rate) and delta distortion (BD-PSNR) between two RD curves.

Definitions (docs/rd.md, "BD-rate"): each curve is a set of (rate R, quality Q) points with Q a
PSNR-like value in dB (higher is better). With r = log10(R):

- BD-rate: interpolate r as a function of Q for both curves, integrate both over the Q interval
  the curves share, and take the mean difference Δr = (∫ r_test − ∫ r_anchor) / (Q_hi − Q_lo);
  BD-rate = (10^Δr − 1) · 100 %: the average rate change of the test curve at equal quality
  (negative = the test needs less rate).
- BD-PSNR (delta distortion): interpolate Q as a function of r, integrate over the shared r
  interval, mean difference test − anchor in dB (positive = the test is better).

Interpolation methods:
- "pchip" (default): piecewise cubic Hermite interpolation (scipy.interpolate.PchipInterpolator,
  monotone, no overshoot), the variant the JCT-VC / JVET common-test-condition spreadsheets use
  since HEVC (JCTVC-L1100) in place of the original polynomial; any number of points >= 2.
- "cubic": the original method of G. Bjøntegaard, "Calculation of average PSNR differences between
  RD-curves", ITU-T SG16/Q6 VCEG-M33, 2001: a least-squares cubic polynomial (numpy.polyfit,
  exact for 4 points) integrated analytically; needs >= 4 points.
"""

import math

import numpy as np
from scipy.interpolate import PchipInterpolator

METHODS = ("pchip", "cubic")


class BdError(ValueError):
    """The curves do not allow a BD figure (too few points, no overlap, not monotone)."""


def _prepare(x, y, what):
    """Points sorted by x with x strictly increasing."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.shape != y.shape or x.ndim != 1:
        raise BdError("%s: x and y differ in length" % what)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise BdError("%s: non-finite value (a zero distortion or rate?)" % what)
    order = np.argsort(x, kind="stable")
    x, y = x[order], y[order]
    if np.any(np.diff(x) <= 0):
        raise BdError("%s: two points have the same value" % what)
    return x, y


_MINIMUM_POINTS = {"pchip": 2, "cubic": 4}


def _integral(x, y, lo, hi, method):
    if method == "pchip":
        return float(PchipInterpolator(x, y).integrate(lo, hi))
    poly = np.polyint(np.polyfit(x, y, 3))
    return float(np.polyval(poly, hi) - np.polyval(poly, lo))


def _average_difference(anchor_x, anchor_y, test_x, test_y, method, what):
    if method not in _MINIMUM_POINTS:
        raise BdError("unknown BD method '%s' (pchip or cubic)" % method)
    ax, ay = _prepare(anchor_x, anchor_y, "anchor curve, " + what)
    tx, ty = _prepare(test_x, test_y, "test curve, " + what)
    if min(len(ax), len(tx)) < _MINIMUM_POINTS[method]:
        raise BdError("the %s method needs at least %d points per curve"
                      % (method, _MINIMUM_POINTS[method]))
    lo = max(ax[0], tx[0])
    hi = min(ax[-1], tx[-1])
    if not hi > lo:
        raise BdError("the curves do not overlap in %s" % what)
    return (_integral(tx, ty, lo, hi, method) - _integral(ax, ay, lo, hi, method)) / (hi - lo)


def _log_rates(rates):
    rates = np.asarray(rates, dtype=float)
    if np.any(rates <= 0):
        raise BdError("rates must be positive")
    return np.log10(rates)


def bd_rate(anchor_rate, anchor_quality, test_rate, test_quality, method="pchip"):
    """BD-rate of the test curve against the anchor, in percent."""
    delta = _average_difference(anchor_quality, _log_rates(anchor_rate), test_quality,
                                _log_rates(test_rate), method, "quality")
    return (math.pow(10.0, delta) - 1.0) * 100.0


def bd_quality(anchor_rate, anchor_quality, test_rate, test_quality, method="pchip"):
    """BD-PSNR of the test curve against the anchor, in the quality's unit (dB)."""
    return _average_difference(_log_rates(anchor_rate), anchor_quality, _log_rates(test_rate),
                               test_quality, method, "log rate")


def quality_db(distortion, diagonal):
    """The PSNR-like quality of a distance-type distortion D (D_A, RMSE, Hausdorff) relative to the
    reference bounding-box diagonal: 20·log10(diagonal / D) = 10·log10(diagonal² / D²) dB, i.e. a
    PSNR whose peak is the diagonal and whose error amplitude is D. Infinite for D = 0."""
    if distortion is None or diagonal is None or diagonal <= 0:
        return None
    if distortion <= 0:
        return math.inf
    return 20.0 * math.log10(diagonal / distortion)
