// bag.cpp — rosbag writing behind the C API of af_bag.h.
#include "af_bag.h"

#include <new>
#include <stdexcept>
#include <string>

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>

#include "convert.hpp"
#include "errors.hpp"

extern "C" {
struct af_bag {
  rosbag::Bag rep;
  std::string path;
  std::string last_error;
};
} // extern "C"

namespace
{

// The error of the last call that had no bag to keep it (open, close), one
// per thread.
thread_local std::string g_bag_error;

void set_bag_error(af_bag *b, const std::string &msg)
{
  af_shim::save_error(b != nullptr ? b->last_error : g_bag_error, msg);
}

// Called inside a catch (...) block: af_shim::map_exception, with rosbag's
// own exceptions (file errors) as AF_EIO and any other as AF_EROS.
af_status bag_status(af_bag *b) noexcept
{
  auto record = [b](const std::string &msg) { set_bag_error(b, msg); };
  return af_shim::map_exception(record, [&](const std::exception &e) {
    record(e.what());
    return dynamic_cast<const rosbag::BagException *>(&e) != nullptr ? AF_EIO : AF_EROS;
  });
}

template <class C, class M>
void write_as(rosbag::Bag &bag, const std::string &topic, const ros::Time &t, const void *c)
{
  M m;
  af_shim::to_ros(*static_cast<const C *>(c), m);
  bag.write(topic, t, m);
}

} // namespace

extern "C" {

af_status af_bag_open_write(const char *path, af_bag **out)
{
  if (out == nullptr) {
    set_bag_error(nullptr, "af_bag_open_write: out is NULL");
    return AF_EINVAL;
  }
  *out = nullptr;
  if (path == nullptr || path[0] == '\0') {
    set_bag_error(nullptr, "af_bag_open_write: path is NULL or empty");
    return AF_EINVAL;
  }
  af_bag *b = nullptr;
  try {
    b = new af_bag;
    b->path = path;
    b->rep.open(path, rosbag::bagmode::Write);
    *out = b;
    return AF_OK;
  } catch (...) {
    af_status s = bag_status(nullptr);
    delete b;
    return s;
  }
}

af_status af_bag_write(af_bag *bag, const char *topic, af_msg_type type, const void *msg,
                       af_time stamp)
{
  if (bag == nullptr) {
    set_bag_error(nullptr, "af_bag_write: bag is NULL");
    return AF_EINVAL;
  }
  try {
    if (topic == nullptr || topic[0] == '\0')
      throw std::invalid_argument("af_bag_write: topic is NULL or empty");
    if (msg == nullptr)
      throw std::invalid_argument(std::string("af_bag_write: msg is NULL on ") + topic);
    if (stamp.sec == 0 && stamp.nsec == 0)
      throw std::invalid_argument(std::string("af_bag_write: zero stamp on ") + topic);
    const std::string t(topic);
    const ros::Time when(stamp.sec, stamp.nsec);
    using namespace acoustic_firmness;
    switch (type) {
    case AF_MSG_SIGNAL_CHUNK: write_as<af_signal_chunk, SignalChunk>(bag->rep, t, when, msg); break;
    case AF_MSG_APPLE_ESTIMATE:
      write_as<af_apple_estimate, AppleEstimate>(bag->rep, t, when, msg);
      break;
    case AF_MSG_EXCITATION_BAND:
      write_as<af_excitation_band, ExcitationBand>(bag->rep, t, when, msg);
      break;
    case AF_MSG_STRIKE_ADVICE:
      write_as<af_strike_advice, StrikeAdvice>(bag->rep, t, when, msg);
      break;
    case AF_MSG_RELIABILITY: write_as<af_reliability, Reliability>(bag->rep, t, when, msg); break;
    case AF_MSG_MARKER_ARRAY:
      write_as<af_marker_array, visualization_msgs::MarkerArray>(bag->rep, t, when, msg);
      break;
    case AF_MSG_STRIKE_REPORT:
      write_as<af_strike_report, StrikeReport>(bag->rep, t, when, msg);
      break;
    default:
      throw std::invalid_argument("af_bag_write: unknown message type " +
                                  std::to_string(static_cast<int>(type)) + " for " + t);
    }
    return AF_OK;
  } catch (...) {
    return bag_status(bag);
  }
}

af_status af_bag_close(af_bag *bag)
{
  if (bag == nullptr)
    return AF_OK;
  af_status s = AF_OK;
  try {
    bag->rep.close();
  } catch (...) {
    s = bag_status(bag);
    set_bag_error(nullptr, bag->path + ": " + bag->last_error);
  }
  delete bag;
  return s;
}

const char *af_bag_last_error(const af_bag *bag)
{
  return bag != nullptr ? bag->last_error.c_str() : g_bag_error.c_str();
}

} // extern "C"
