#include "tools/render/masked_ssim.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace tdvo {

namespace {

constexpr int kRadius = 5;  // 11 × 11 window
constexpr double kSigma = 1.5;
constexpr double kC1 = (0.01 * 255) * (0.01 * 255);
constexpr double kC2 = (0.03 * 255) * (0.03 * 255);

std::array<double, 2 * kRadius + 1> gaussian() {
  std::array<double, 2 * kRadius + 1> g{};
  double total = 0;
  for (int i = -kRadius; i <= kRadius; ++i)
    total += g[size_t(i + kRadius)] = std::exp(-0.5 * i * i / (kSigma * kSigma));
  for (double& v : g)
    v /= total;
  return g;
}

std::vector<double> luma(const Image& image) {
  std::vector<double> y(size_t(image.width) * size_t(image.height));
  for (int r = 0; r < image.height; ++r)
    for (int c = 0; c < image.width; ++c)
      y[size_t(r) * size_t(image.width) + size_t(c)] =
          0.299 * image.at(c, r, 0) + 0.587 * image.at(c, r, 1) + 0.114 * image.at(c, r, 2);
  return y;
}

// One pass of the Gaussian along a line: `lines` lines of `length` samples, sample k of line l
// at l·lineStep + k·step, from `in` to `out`, clipped at the line's ends.
void filterLines(const std::vector<double>& in, std::vector<double>& out, int lines, int length,
                 size_t lineStep, size_t step) {
  const auto g = gaussian();
  for (int l = 0; l < lines; ++l)
    for (int k = 0; k < length; ++k) {
      double s = 0;
      for (int d = std::max(-kRadius, -k); d <= std::min(kRadius, length - 1 - k); ++d)
        s += g[size_t(d + kRadius)] * in[size_t(l) * lineStep + size_t(k + d) * step];
      out[size_t(l) * lineStep + size_t(k) * step] = s;
    }
}

// Separable Gaussian filtering of `planes` (each width × height, row-major).
void blur(std::vector<std::vector<double>>& planes, int width, int height) {
  std::vector<double> rows(size_t(width) * size_t(height));
  for (std::vector<double>& p : planes) {
    filterLines(p, rows, height, width, size_t(width), 1);
    filterLines(rows, p, width, height, 1, size_t(width));
  }
}

}  // namespace

SsimSum& SsimSum::operator+=(const SsimSum& o) {
  sum += o.sum;
  count += o.count;
  return *this;
}

double SsimSum::mean() const {
  return count ? sum / double(count) : std::numeric_limits<double>::quiet_NaN();
}

SsimSum maskedSsim(const Image& test, const Image& reference, const Image& mask) {
  checkMaskedComparison(test, reference, mask, "SSIM");
  const int w = test.width, h = test.height;
  const size_t n = size_t(w) * size_t(h);
  const std::vector<double> a = luma(test), b = luma(reference);
  // Weighted sums of m, m·a, m·b, m·a², m·b², m·a·b (m the 0/1 mask) over each window.
  std::vector<std::vector<double>> s(6, std::vector<double>(n, 0.0));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (mask.at(x, y) == 0) continue;
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      s[0][i] = 1;
      s[1][i] = a[i];
      s[2][i] = b[i];
      s[3][i] = a[i] * a[i];
      s[4][i] = b[i] * b[i];
      s[5][i] = a[i] * b[i];
    }
  blur(s, w, h);
  SsimSum result;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (mask.at(x, y) == 0) continue;
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const double m = s[0][i];  // > 0: the centre pixel is inside
      const double ma = s[1][i] / m, mb = s[2][i] / m;
      const double va = std::max(0.0, s[3][i] / m - ma * ma);
      const double vb = std::max(0.0, s[4][i] / m - mb * mb);
      const double cab = s[5][i] / m - ma * mb;
      result.sum +=
          (2 * ma * mb + kC1) * (2 * cab + kC2) / ((ma * ma + mb * mb + kC1) * (va + vb + kC2));
      ++result.count;
    }
  return result;
}

}  // namespace tdvo
