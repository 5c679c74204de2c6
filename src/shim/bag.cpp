// bag.cpp — rosbag writing behind the C API of af_bag.h.
#include "af_bag.h"

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

#include <dirent.h>
#include <fcntl.h>
#include <unistd.h>

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>

#include "convert.hpp"
#include "errors.hpp"

extern "C" {
struct af_bag {
  rosbag::Bag rep;
  std::string path;     // as given, for the messages
  std::string resolved; // absolute, to find the file's descriptor (a later chdir)
  std::string last_error;
  bool failed = false; // a write or the close failed: the file is not a whole bag
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
// own exceptions (file errors) as AF_EIO and any other as AF_EROS. err: the
// errno saved first thing in the catch block; rosbag's messages give the
// byte counts but not the cause (ENOSPC, EFBIG), so it is appended to them.
af_status bag_status(af_bag *b, int err) noexcept
{
  auto record = [b](const std::string &msg) { set_bag_error(b, msg); };
  return af_shim::map_exception(record, [&](const std::exception &e) {
    if (dynamic_cast<const rosbag::BagException *>(&e) == nullptr) {
      record(e.what());
      return AF_EROS;
    }
    try {
      std::string msg(e.what());
      if (err != 0 && msg.find(std::strerror(err)) == std::string::npos)
        msg += std::string(": ") + std::strerror(err);
      record(msg);
    } catch (...) {
      record(e.what());
    }
    if (b != nullptr)
      b->failed = true;
    return AF_EIO;
  });
}

// rosbag::Bag::close() throws when its last writes fail, and ~Bag() calls
// close() again: a throw out of a destructor, std::terminate, exit 134. So a
// bag that failed is closed onto /dev/null: its descriptor (found by the
// file's path in /proc/self/fd) is replaced by one of /dev/null, where
// rosbag's remaining writes succeed and go nowhere, and the Bag can then be
// closed and destroyed. true when the close succeeded.
bool close_onto_null(af_bag *b) noexcept
{
  int null_fd = open("/dev/null", O_WRONLY | O_CLOEXEC);
  DIR *d = opendir("/proc/self/fd");
  if (null_fd >= 0 && d != nullptr) {
    const int own = dirfd(d);
    for (struct dirent *e = readdir(d); e != nullptr; e = readdir(d)) {
      char link[sizeof "/proc/self/fd/" + sizeof e->d_name], target[PATH_MAX];
      const int fd = std::atoi(e->d_name);
      if (e->d_name[0] == '.' || fd == own || fd == null_fd)
        continue;
      std::snprintf(link, sizeof link, "/proc/self/fd/%s", e->d_name);
      const ssize_t n = readlink(link, target, sizeof target - 1);
      if (n <= 0)
        continue;
      target[n] = '\0';
      if (b->resolved == target)
        (void)dup2(null_fd, fd);
    }
  }
  if (d != nullptr)
    closedir(d);
  if (null_fd >= 0)
    close(null_fd);
  try {
    b->rep.close();
    return true;
  } catch (...) {
    return false;
  }
}

// The end of a bag that failed: closed onto /dev/null, the partial file
// removed (a bag without its index, cut anywhere: no reader should take it
// for a recording), and freed. The message of the failure, already on b,
// goes to the thread's error with the path and what became of the file.
void abandon(af_bag *b) noexcept
{
  const bool closed = close_onto_null(b);
  const bool removed = std::remove(b->path.c_str()) == 0;
  try {
    set_bag_error(nullptr, b->path + ": " + b->last_error +
                               (removed ? "; the partial bag is removed"
                                        : "; the partial bag is left behind, not a readable bag"));
  } catch (...) {
    set_bag_error(nullptr, "out of memory");
  }
  // A Bag whose close still throws cannot be destroyed (see close_onto_null):
  // it is left allocated rather than abort the process.
  if (closed)
    delete b;
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
    errno = 0;
    b->rep.open(path, rosbag::bagmode::Write);
    char resolved[PATH_MAX];
    b->resolved = realpath(path, resolved) != nullptr ? resolved : path;
    *out = b;
    return AF_OK;
  } catch (...) {
    af_status s = bag_status(nullptr, errno);
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
  if (bag->failed) {
    set_bag_error(bag, bag->last_error.empty() ? "an earlier write failed" : bag->last_error);
    return AF_EIO;
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
    errno = 0; // rosbag's file errors: errno tells their cause
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
    return bag_status(bag, errno);
  }
}

af_status af_bag_close(af_bag *bag)
{
  if (bag == nullptr)
    return AF_OK;
  if (bag->failed) {
    abandon(bag);
    return AF_EIO;
  }
  try {
    errno = 0;
    bag->rep.close();
  } catch (...) {
    af_status s = bag_status(bag, errno);
    abandon(bag);
    return s;
  }
  delete bag;
  return AF_OK;
}

const char *af_bag_last_error(const af_bag *bag)
{
  return bag != nullptr ? bag->last_error.c_str() : g_bag_error.c_str();
}

} // extern "C"
