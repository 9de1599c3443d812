// SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) inside a mask, for the leave-one-out test.
//
// On luma Y = 0.299 R + 0.587 G + 0.114 B (BT.601 weights, full range 0..255), with the paper's
// constants: an 11 × 11 circular-symmetric Gaussian window of standard deviation 1.5,
// K1 = 0.01, K2 = 0.03, L = 255 (C1 = (K1 L)², C2 = (K2 L)²). The SSIM map is computed at
// every pixel inside the mask, and only pixels inside the mask enter a window: the Gaussian
// weights are multiplied by the mask and renormalised over the pixels that remain (and over
// those inside the image, at its borders). Pixels outside the mask therefore change nothing,
// so a rendered background or the scene behind the object does not count. The result is the
// mean of the SSIM map over the mask's pixels, kept as a sum and a count so that frames and
// cameras can be pooled.
#pragma once

#include <cstddef>

#include "common/views/image.h"

namespace tdvo {

struct SsimSum {
  double sum = 0;    // Σ SSIM over the counted pixels
  size_t count = 0;  // pixels counted
  SsimSum& operator+=(const SsimSum& o);
  double mean() const;  // NaN when nothing was counted
};

// `test` and `reference` have at least three channels (R, G, B first), `mask` at least one
// (non-zero: inside), all of one size.
SsimSum maskedSsim(const Image& test, const Image& reference, const Image& mask);

}  // namespace tdvo
