// ros_handle.hpp — the C++ side of the opaque handles of af_ros.h, shared by
// the shim's sources (ros.cpp, params.cpp, pubsub.cpp, diagnostics.cpp),
// and the one place where C++ exceptions become af_status values.
#ifndef AF_SHIM_ROS_HANDLE_HPP
#define AF_SHIM_ROS_HANDLE_HPP

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include "af_ros.h"

extern "C" {

struct af_ros_pub {
  af_ros *owner;
  af_msg_type type;
  ros::Publisher pub;
  // Converts the C struct into a message kept by the closure and publishes
  // it; keeping the message lets its vectors keep their capacity.
  std::function<void(const void *)> send;
};

struct af_ros_sub {
  af_ros *owner;
  af_msg_type type;
  af_ros_callback cb;
  void *user;
  ros::Subscriber sub;
  // Messages dropped before deserializing: a length prefix claiming more
  // bytes than the message has (wire.hpp). Written in the spinning thread.
  std::atomic<unsigned long long> malformed{0};
  // SignalChunks longer than max_samples (0: no cap), refused before
  // deserializing (af_ros_sub_limit); refused (may be null) is told of each
  // refusal, malformed or oversized, with its line.
  std::atomic<std::size_t> max_samples{0};
  std::atomic<unsigned long long> oversized{0};
  af_ros_refused_fn refused = nullptr;
};

struct af_diag_status {
  diagnostic_updater::DiagnosticStatusWrapper *rep;
};

struct af_ros_diag {
  af_ros *owner;
  std::unique_ptr<diagnostic_updater::Updater> updater;
};

// Member order is destruction order reversed: the publishers, subscribers
// and updater go before the node handles, and those before the queue their
// callbacks are in.
struct af_ros {
  ros::CallbackQueue queue;
  std::unique_ptr<ros::NodeHandle> nh;
  std::unique_ptr<ros::NodeHandle> pnh;
  std::string name;   // fully resolved node name
  std::string logger; // rosconsole logger of af_ros_log
  bool shutdown_requested = false;
  // Functions taking a const handle (parameters, logging) still report.
  mutable std::string last_error;
  std::vector<std::unique_ptr<af_ros_pub>> pubs;
  std::vector<std::unique_ptr<af_ros_sub>> subs;
  std::unique_ptr<af_ros_diag> diag;
  // Services and dynamic_reconfigure servers (service.cpp, reconfigure.cpp):
  // owned here, released before the node handles.
  std::vector<std::shared_ptr<void>> extras;
};

} // extern "C"

namespace af_shim
{

// Records msg as r's last error (r may be NULL: the message then goes to the
// process-wide slot that af_ros_last_error(NULL) returns).
void set_error(const af_ros *r, const std::string &msg);

// Called inside a catch (...) block: classifies the exception in flight,
// records its message on r and returns its status — std::invalid_argument
// and ros::InvalidNameException give AF_EINVAL, std::bad_alloc AF_ENOMEM,
// anything else AF_EROS. One function, so that every extern "C" body maps
// exceptions the same way.
af_status status_from_exception(const af_ros *r) noexcept;

// The last error recorded without a handle ("" when none).
const char *orphan_error() noexcept;

// Records a C API misuse (a NULL pointer, a value out of range) and returns
// AF_EINVAL.
af_status invalid(const af_ros *r, const std::string &msg);

} // namespace af_shim

#endif
