#include "common/views/image.h"

#include "common/core/error.h"

namespace tdvo {

Image::Image(int w, int h, int c, uint8_t fill) : width(w), height(h), channels(c) {
  check(w >= 0 && h >= 0 && c >= 1 && c <= 4, "image: invalid size " + std::to_string(w) + "x" +
                                                  std::to_string(h) + "x" + std::to_string(c));
  pixels.assign(static_cast<size_t>(w) * static_cast<size_t>(h) * static_cast<size_t>(c), fill);
}

Image convertChannels(const Image& image, int channels) {
  check(channels >= 1 && channels <= 4, "convertChannels: invalid channel count");
  if (image.channels == channels) return image;
  Image out(image.width, image.height, channels);
  const bool inColour = image.channels >= 3, inAlpha = image.channels % 2 == 0;
  const bool outColour = channels >= 3, outAlpha = channels % 2 == 0;
  const size_t n = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* p = &image.pixels[i * static_cast<size_t>(image.channels)];
    uint8_t* q = &out.pixels[i * static_cast<size_t>(channels)];
    uint8_t rgb[3] = {p[0], p[0], p[0]};
    if (inColour) rgb[1] = p[1], rgb[2] = p[2];
    const uint8_t alpha = inAlpha ? p[image.channels - 1] : 255;
    if (outColour) {
      q[0] = rgb[0], q[1] = rgb[1], q[2] = rgb[2];
    } else {
      q[0] = inColour ? static_cast<uint8_t>((77 * rgb[0] + 150 * rgb[1] + 29 * rgb[2] + 128) >> 8)
                      : rgb[0];
    }
    if (outAlpha) q[channels - 1] = alpha;
  }
  return out;
}

void checkMaskedComparison(const Image& test, const Image& reference, const Image& mask,
                           const std::string& metric) {
  check(test.width == reference.width && test.height == reference.height &&
            mask.width == test.width && mask.height == test.height,
        metric + ": image sizes differ");
  check(test.channels >= 3 && reference.channels >= 3 && mask.channels >= 1,
        metric + ": colour images and a mask are needed");
}

}  // namespace tdvo
