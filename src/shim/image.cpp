// image.cpp — sensor_msgs/Image from the C mirror (af_msgs.h af_image).
#include <cstring>
#include <stdexcept>
#include <string>

#include <sensor_msgs/image_encodings.h>

#include "convert.hpp"

namespace af_shim
{

void to_ros(const af_image &c, sensor_msgs::Image &m)
{
  std::string encoding;
  assign_string(c.encoding, encoding);
  if (c.data == nullptr || c.width_px == 0 || c.height_px == 0)
    throw std::invalid_argument("image: no pixels (data NULL or a zero size)");
  int channels = 0, depth = 0;
  try {
    channels = sensor_msgs::image_encodings::numChannels(encoding);
    depth = sensor_msgs::image_encodings::bitDepth(encoding);
  } catch (const std::runtime_error &) {
    throw std::invalid_argument("image: unknown encoding '" + encoding + "'");
  }
  const uint64_t row = static_cast<uint64_t>(c.width_px) * channels * (depth / 8);
  if (c.step_bytes < row)
    throw std::invalid_argument("image: step " + std::to_string(c.step_bytes) +
                                " bytes is shorter than a row of " + std::to_string(row));
  to_ros(c.header, m.header);
  m.height = c.height_px;
  m.width = c.width_px;
  m.encoding = encoding;
  m.is_bigendian = 0;
  m.step = c.step_bytes;
  const std::size_t n = static_cast<std::size_t>(c.step_bytes) * c.height_px;
  m.data.resize(n); // keeps its capacity: no allocation after the first image of this size
  std::memcpy(m.data.data(), c.data, n);
}

} // namespace af_shim
