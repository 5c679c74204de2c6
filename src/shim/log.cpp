// log.cpp — rosconsole logging for C callers.
#include "ros_handle.hpp"

#include <cstdarg>
#include <cstdio>

namespace
{

// Each ROS_LOG call site caches its logger and level at first use: each level
// gets its own call site, and the logger name of the first call sticks (the
// node's, since there is one node per process and it logs after create).
void log_line(const char *logger, af_log_level level, const char *line)
{
  switch (level) {
  case AF_LOG_DEBUG: ROS_LOG(::ros::console::levels::Debug, logger, "%s", line); break;
  case AF_LOG_INFO: ROS_LOG(::ros::console::levels::Info, logger, "%s", line); break;
  case AF_LOG_WARN: ROS_LOG(::ros::console::levels::Warn, logger, "%s", line); break;
  case AF_LOG_ERROR: ROS_LOG(::ros::console::levels::Error, logger, "%s", line); break;
  case AF_LOG_FATAL:
  default: ROS_LOG(::ros::console::levels::Fatal, logger, "%s", line); break;
  }
}

} // namespace

extern "C" {

void af_ros_log(const af_ros *r, af_log_level level, const char *fmt, ...)
{
  if (fmt == nullptr)
    return;
  // A fixed buffer: logging must not allocate while spinning. Longer lines
  // are cut. Formatted before the try block, so that va_end cannot be
  // skipped.
  char line[1024];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  try {
    // Before af_ros_create the package's logger stands in for the node's.
    log_line(r != nullptr ? r->logger.c_str() : "ros.acoustic_firmness", level, line);
  } catch (...) {
    af_shim::status_from_exception(r);
  }
}

} // extern "C"
