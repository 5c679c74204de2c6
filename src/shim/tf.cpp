// tf.cpp — the rig's frames through tf2_ros (see af_tf.h).
#include "af_tf.h"

#include <cstdio>
#include <memory>
#include <string>

#include <tf2/exceptions.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "ros_handle.hpp"
#include "rotation.hpp"

extern "C" {

struct af_tf {
  af_ros *owner;
  // The listener subscribes to /tf and /tf_static through the node's
  // NodeHandle, whose callbacks run in af_ros_spin_once on the caller's
  // thread: no thread of its own, which woke every 10 ms to poll its queue
  // (~0.25 % of a core, idle or not). It goes before the buffer it fills.
  tf2_ros::Buffer buffer{ros::Duration(10.0)};
  std::unique_ptr<tf2_ros::TransformListener> listener;
};

} // extern "C"

namespace
{

void say(char *why, size_t len, const std::string &text)
{
  if (why != nullptr && len > 0)
    std::snprintf(why, len, "%s", text.c_str());
}

void fill(const geometry_msgs::TransformStamped &m, af_transform &out)
{
  const geometry_msgs::Quaternion &q = m.transform.rotation;
  af_shim::rotation_from_quaternion(q.x, q.y, q.z, q.w, out.rotation);
  out.translation_m[0] = m.transform.translation.x;
  out.translation_m[1] = m.transform.translation.y;
  out.translation_m[2] = m.transform.translation.z;
}

} // namespace

extern "C" {

af_status af_tf_create(af_ros *r, af_tf **out)
{
  try {
    if (out == nullptr)
      return af_shim::invalid(r, "af_tf_create: out is NULL");
    *out = nullptr;
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_tf_create: r is NULL");
    std::unique_ptr<af_tf> t(new af_tf);
    t->owner = r;
    t->listener.reset(new tf2_ros::TransformListener(t->buffer, *r->nh, false));
    *out = t.release();
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

void af_tf_destroy(af_tf *t)
{
  try {
    delete t;
  } catch (...) {
    // Shutting down: nothing to report to.
  }
}

af_status af_tf_lookup(af_tf *t, const char *target, const char *source, af_transform *out,
                       char *why, size_t len)
{
  if (t == nullptr || out == nullptr || target == nullptr || source == nullptr ||
      target[0] == '\0' || source[0] == '\0') {
    say(why, len, "no frame name given");
    return AF_EINVAL;
  }
  try {
    fill(t->buffer.lookupTransform(target, source, ros::Time(0)), *out);
    return AF_OK;
  } catch (const tf2::LookupException &) {
    const bool has_target = t->buffer._frameExists(target);
    const std::string missing = has_target ? source : target;
    say(why, len, "frame '" + missing + "' does not exist in TF");
    return AF_ENODATA;
  } catch (const tf2::ConnectivityException &) {
    say(why, len, std::string("'") + target + "' and '" + source + "' are not connected in TF");
    return AF_ENODATA;
  } catch (const tf2::ExtrapolationException &) {
    say(why, len, std::string("no TF data for '") + target + "' at a common time");
    return AF_ENODATA;
  } catch (const tf2::InvalidArgumentException &e) {
    say(why, len, std::string("TF refused the frame names: ") + e.what());
    return AF_EINVAL;
  } catch (const std::exception &e) {
    say(why, len, std::string("TF: ") + e.what());
    return AF_ENODATA;
  } catch (...) {
    say(why, len, "TF: unknown C++ exception");
    return AF_EROS;
  }
}

bool af_tf_frame_known(af_tf *t, const char *frame)
{
  try {
    return t != nullptr && frame != nullptr && frame[0] != '\0' && t->buffer._frameExists(frame);
  } catch (...) {
    return false;
  }
}

} // extern "C"
