// errors.cpp — C++ exceptions to af_status, and the error text behind
// af_ros_last_error.
#include "ros_handle.hpp"

#include <new>
#include <stdexcept>

namespace af_shim
{

namespace
{
// Where errors go when there is no handle yet, e.g. a failed af_ros_create.
std::string g_orphan_error;
} // namespace

void set_error(const af_ros *r, const std::string &msg)
{
  try {
    if (r != nullptr)
      r->last_error = msg;
    else
      g_orphan_error = msg;
  } catch (...) {
    // Out of memory while saving the message: the status still tells.
  }
}

af_status status_from_exception(const af_ros *r) noexcept
{
  try {
    throw;
  } catch (const ros::InvalidNameException &e) {
    set_error(r, e.what());
    return AF_EINVAL;
  } catch (const std::invalid_argument &e) {
    set_error(r, e.what());
    return AF_EINVAL;
  } catch (const std::bad_alloc &) {
    set_error(r, "out of memory");
    return AF_ENOMEM;
  } catch (const std::exception &e) {
    set_error(r, e.what());
    return AF_EROS;
  } catch (...) {
    set_error(r, "unknown C++ exception");
    return AF_EROS;
  }
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
