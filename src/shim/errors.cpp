// errors.cpp — C++ exceptions to af_status, and the error text behind
// af_ros_last_error.
#include "ros_handle.hpp"

#include "errors.hpp"

namespace af_shim
{

namespace
{
// Where errors go when there is no handle yet, e.g. a failed af_ros_create.
std::string g_orphan_error;
} // namespace

void set_error(const af_ros *r, const std::string &msg)
{
  save_error(r != nullptr ? r->last_error : g_orphan_error, msg);
}

af_status status_from_exception(const af_ros *r) noexcept
{
  auto record = [r](const std::string &msg) { set_error(r, msg); };
  return map_exception(record, [&](const std::exception &e) {
    record(e.what());
    return dynamic_cast<const ros::InvalidNameException *>(&e) != nullptr ? AF_EINVAL : AF_EROS;
  });
}

af_status invalid(const af_ros *r, const std::string &msg)
{
  set_error(r, msg);
  return AF_EINVAL;
}

const char *orphan_error() noexcept
{
  return g_orphan_error.c_str();
}

} // namespace af_shim
