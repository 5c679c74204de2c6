// ros.cpp — the node: ros::init, its handles and private callback queue,
// spinning, shutdown and the node's name.
#include "ros_handle.hpp"

#include <cmath>

namespace
{
// roscpp holds one node per process; a second af_ros would share (and on
// destroy, shut down) the first one's.
bool g_node_exists = false;
} // namespace

extern "C" {

af_status af_ros_create(int *argc, char **argv, const char *node_name, af_ros **out)
{
  try {
    if (out == nullptr)
      return af_shim::invalid(nullptr, "af_ros_create: out is NULL");
    *out = nullptr;
    if (argc == nullptr || *argc < 0 || (*argc > 0 && argv == nullptr))
      return af_shim::invalid(nullptr, "af_ros_create: argc/argv missing");
    if (node_name == nullptr || node_name[0] == '\0')
      return af_shim::invalid(nullptr, "af_ros_create: node_name is NULL or empty");
    if (g_node_exists)
      return af_shim::invalid(nullptr, "af_ros_create: this process already has a node");

    // Default init options on purpose: roscpp's SIGINT handler stays, so
    // Ctrl-C requests shutdown and af_ros_ok() turns false.
    ros::init(*argc, argv, node_name);
    std::unique_ptr<af_ros> r(new af_ros);
    r->nh.reset(new ros::NodeHandle());
    r->pnh.reset(new ros::NodeHandle("~"));
    // Callbacks run only inside af_ros_spin_once, on its caller's thread:
    // nothing of ours goes to the global queue that other threads may serve.
    r->nh->setCallbackQueue(&r->queue);
    r->pnh->setCallbackQueue(&r->queue);
    r->name = ros::this_node::getName();
    std::string base = r->name.substr(r->name.find_last_of('/') + 1);
    r->logger = std::string("ros.acoustic_firmness.") + base;
    g_node_exists = true;
    *out = r.release();
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(nullptr);
  }
}

void af_ros_destroy(af_ros *r)
{
  if (r == nullptr)
    return;
  try {
    // Subscribers first, so that no callback into freed user data is queued.
    r->subs.clear();
    r->extras.clear();
    r->pubs.clear();
    r->diag.reset();
    r->queue.clear();
    r->pnh.reset();
    r->nh.reset();
    ros::shutdown();
  } catch (...) {
    af_shim::status_from_exception(nullptr);
  }
  delete r;
  g_node_exists = false;
}

const char *af_ros_last_error(const af_ros *r)
{
  // Without a handle: why the last af_ros_create (or other handle-less
  // call) failed.
  return r != nullptr ? r->last_error.c_str() : af_shim::orphan_error();
}

bool af_ros_ok(const af_ros *r)
{
  try {
    return r != nullptr && !r->shutdown_requested && ros::ok();
  } catch (...) {
    af_shim::status_from_exception(r);
    return false;
  }
}

void af_ros_request_shutdown(af_ros *r)
{
  try {
    if (r != nullptr)
      r->shutdown_requested = true;
    // What roscpp's SIGINT handler does: its poll thread shuts down soon after.
    ros::requestShutdown();
  } catch (...) {
    af_shim::status_from_exception(r);
  }
}

af_status af_ros_spin_once(af_ros *r, double timeout_s)
{
  try {
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_spin_once: r is NULL");
    if (!(timeout_s >= 0.0) || !std::isfinite(timeout_s))
      return af_shim::invalid(r, "af_ros_spin_once: timeout_s must be finite and >= 0, got " +
                                     std::to_string(timeout_s));
    r->queue.callAvailable(ros::WallDuration(timeout_s));
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

const char *af_ros_node_name(const af_ros *r)
{
  return r != nullptr ? r->name.c_str() : "";
}

} // extern "C"
