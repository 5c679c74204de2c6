// diagnostics.cpp — diagnostic_updater for C tasks.
#include "ros_handle.hpp"

#include <cstdarg>
#include <cstdio>

extern "C" {

void af_diag_summary(af_diag_status *st, af_diag_level level, const char *message)
{
  try {
    if (st == nullptr || st->rep == nullptr)
      return;
    st->rep->summary(static_cast<unsigned char>(level), message != nullptr ? message : "");
  } catch (...) {
    af_shim::status_from_exception(nullptr);
  }
}

void af_diag_add(af_diag_status *st, const char *key, const char *fmt, ...)
{
  if (st == nullptr || st->rep == nullptr || key == nullptr || fmt == nullptr)
    return;
  // Formatted before the try block, so that va_end cannot be skipped.
  char value[256];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(value, sizeof value, fmt, ap);
  va_end(ap);
  try {
    st->rep->add(key, std::string(value));
  } catch (...) {
    af_shim::status_from_exception(nullptr);
  }
}

af_status af_ros_diag_create(af_ros *r, const char *hardware_id, af_ros_diag **out)
{
  try {
    if (out == nullptr)
      return af_shim::invalid(r, "af_ros_diag_create: out is NULL");
    *out = nullptr;
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_diag_create: r is NULL");
    if (hardware_id == nullptr || hardware_id[0] == '\0')
      return af_shim::invalid(r, "af_ros_diag_create: hardware_id is NULL or empty");
    if (r->diag)
      return af_shim::invalid(r, "af_ros_diag_create: this node already has its updater");
    std::unique_ptr<af_ros_diag> d(new af_ros_diag);
    d->owner = r;
    // The node's own handles: /diagnostics in the node's namespace and
    // ~diagnostic_period read from the private one, as any ROS driver does.
    d->updater.reset(new diagnostic_updater::Updater(*r->nh, *r->pnh, r->name));
    d->updater->setHardwareID(hardware_id);
    r->diag = std::move(d);
    *out = r->diag.get();
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

af_status af_ros_diag_add_task(af_ros_diag *d, const char *name, af_diag_fn fn, void *user)
{
  af_ros *r = d != nullptr ? d->owner : nullptr;
  try {
    if (d == nullptr)
      return af_shim::invalid(nullptr, "af_ros_diag_add_task: d is NULL");
    if (name == nullptr || name[0] == '\0')
      return af_shim::invalid(r, "af_ros_diag_add_task: name is NULL or empty");
    if (fn == nullptr)
      return af_shim::invalid(r, std::string("af_ros_diag_add_task: fn is NULL for ") + name);
    d->updater->add(name, [fn, user](diagnostic_updater::DiagnosticStatusWrapper &w) {
      af_diag_status st = {&w};
      fn(&st, user);
    });
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

void af_ros_diag_update(af_ros_diag *d)
{
  try {
    if (d != nullptr)
      d->updater->update();
  } catch (...) {
    af_shim::status_from_exception(d != nullptr ? d->owner : nullptr);
  }
}

void af_ros_diag_force_update(af_ros_diag *d)
{
  try {
    if (d != nullptr)
      d->updater->force_update();
  } catch (...) {
    af_shim::status_from_exception(d != nullptr ? d->owner : nullptr);
  }
}

} // extern "C"
