// errors.hpp — the shim's one mapping from a C++ exception to an af_status
// and its message, used by every extern "C" body (errors.cpp for the node
// handle, bag.cpp and bag_read.cpp for the bag handles).
#ifndef AF_SHIM_ERRORS_HPP
#define AF_SHIM_ERRORS_HPP

#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "status.h"

namespace af_shim
{

// Stores msg in slot; out of memory while saving it is swallowed (the
// status still tells).
inline void save_error(std::string &slot, const std::string &msg) noexcept
{
  try {
    slot = msg;
  } catch (...) {
    // Out of memory while saving the message: the status still tells.
  }
}

// Called inside a catch (...) block: classifies the exception in flight.
// std::invalid_argument gives AF_EINVAL, std::bad_alloc AF_ENOMEM ("out of
// memory"), a non-standard exception AF_EROS ("unknown C++ exception"); any
// other std::exception goes to other(e), which records its message and
// returns its status (a handle's own exceptions: rosbag's file errors are
// AF_EIO, a bad name AF_EINVAL). record(msg) keeps the message on the handle.
template <class Record, class Other> af_status map_exception(Record record, Other other) noexcept
{
  try {
    throw;
  } catch (const std::invalid_argument &e) {
    record(e.what());
    return AF_EINVAL;
  } catch (const std::bad_alloc &) {
    record("out of memory");
    return AF_ENOMEM;
  } catch (const std::exception &e) {
    return other(e);
  } catch (...) {
    record("unknown C++ exception");
    return AF_EROS;
  }
}

} // namespace af_shim

#endif
