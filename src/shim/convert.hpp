// convert.hpp — conversions between the C mirrors (af_msgs.h) and the ROS
// messages, C++ only; used by the publishers and subscribers of the shim and
// by its unit tests.
//
// ROS -> C never allocates: strings are copied into the fixed arrays of the C
// struct (cut at their size - 1, always NUL-terminated) and float32[] data is
// borrowed, so the C struct lives on the callback's stack and is valid only
// while the ROS message it came from is.
//
// C -> ROS reuses the message it is given, so a publisher that keeps one
// message per topic stops allocating once its vectors have grown. A C struct
// that cannot be represented (data NULL with n > 0, too many points, an
// unknown marker type) throws std::invalid_argument, which the C API reports
// as AF_EINVAL.
#ifndef AF_SHIM_CONVERT_HPP
#define AF_SHIM_CONVERT_HPP

#include <cstddef>
#include <cstring>
#include <string>

#include <acoustic_firmness/AppleEstimate.h>
#include <acoustic_firmness/ExcitationBand.h>
#include <acoustic_firmness/Reliability.h>
#include <acoustic_firmness/SignalChunk.h>
#include <acoustic_firmness/StrikeAdvice.h>
#include <acoustic_firmness/StrikeReport.h>
#include <geometry_msgs/Vector3.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

#include "af_msgs.h"

namespace af_shim
{

// Copies src into dst, cut at N - 1 bytes; dst is always NUL-terminated. A
// NUL byte inside src would end the C string in silence (a unit "N\0x" read
// as "N"): it is copied as '?', so that the field shows it and
// matches no accepted value.
template <std::size_t N> void copy_string(const std::string &src, char (&dst)[N])
{
  const std::size_t n = src.size() < N - 1 ? src.size() : N - 1;
  for (std::size_t i = 0; i < n; ++i)
    dst[i] = src[i] == '\0' ? '?' : src[i];
  dst[n] = '\0';
}

// A fixed C array may come without its NUL (a caller filling it with
// strncpy); strnlen keeps the read inside the array.
template <std::size_t N> void assign_string(const char (&src)[N], std::string &dst)
{
  dst.assign(src, strnlen(src, N));
}

void to_ros(const af_time &c, ros::Time &m);
void from_ros(const ros::Time &m, af_time &c);
void to_ros(const af_header &c, std_msgs::Header &m);
void from_ros(const std_msgs::Header &m, af_header &c);
void to_ros(const af_vec3 &c, geometry_msgs::Vector3 &m);
void from_ros(const geometry_msgs::Vector3 &m, af_vec3 &c);

void to_ros(const af_signal_chunk &c, acoustic_firmness::SignalChunk &m);
// c.data borrows m.data: valid while m is.
void from_ros(const acoustic_firmness::SignalChunk &m, af_signal_chunk &c);

void to_ros(const af_apple_estimate &c, acoustic_firmness::AppleEstimate &m);
void from_ros(const acoustic_firmness::AppleEstimate &m, af_apple_estimate &c);

void to_ros(const af_excitation_band &c, acoustic_firmness::ExcitationBand &m);
void from_ros(const acoustic_firmness::ExcitationBand &m, af_excitation_band &c);

void to_ros(const af_strike_advice &c, acoustic_firmness::StrikeAdvice &m);
void from_ros(const acoustic_firmness::StrikeAdvice &m, af_strike_advice &c);

void to_ros(const af_reliability &c, acoustic_firmness::Reliability &m);
void from_ros(const acoustic_firmness::Reliability &m, af_reliability &c);

void to_ros(const af_strike_report &c, acoustic_firmness::StrikeReport &m);
void from_ros(const acoustic_firmness::StrikeReport &m, af_strike_report &c);

// Markers are publish-only: there is no ROS -> C direction.
void to_ros(const af_marker &c, visualization_msgs::Marker &m);
void to_ros(const af_marker_array &c, visualization_msgs::MarkerArray &m);

// Images are publish-only too (image.cpp): the pixels are copied into m.data,
// whose capacity is kept between publishes. Throws std::invalid_argument for
// data NULL, a zero size, a step shorter than a row of the encoding, or an
// encoding the shim does not know.
void to_ros(const af_image &c, sensor_msgs::Image &m);

void to_ros(const af_text_msg &c, std_msgs::String &m);

} // namespace af_shim

#endif
