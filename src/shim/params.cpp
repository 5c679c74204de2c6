// params.cpp — parameters: private (~name) for the node's settings, global or
// relative for shared ones such as robot_description.
#include "ros_handle.hpp"

#include <cstring>

namespace
{

const char *type_name(XmlRpc::XmlRpcValue::Type t)
{
  switch (t) {
  case XmlRpc::XmlRpcValue::TypeBoolean: return "a bool";
  case XmlRpc::XmlRpcValue::TypeInt: return "an int";
  case XmlRpc::XmlRpcValue::TypeDouble: return "a double";
  case XmlRpc::XmlRpcValue::TypeString: return "a string";
  case XmlRpc::XmlRpcValue::TypeDateTime: return "a date";
  case XmlRpc::XmlRpcValue::TypeBase64: return "binary data";
  case XmlRpc::XmlRpcValue::TypeArray: return "a list";
  case XmlRpc::XmlRpcValue::TypeStruct: return "a dictionary";
  case XmlRpc::XmlRpcValue::TypeInvalid: break;
  }
  return "of no valid type";
}

// Fetches name from nh into v. AF_ENODATA when unset, AF_EINVAL on a NULL
// argument; full receives the resolved name for messages.
af_status fetch(const af_ros *r, bool private_ns, const char *fn, const char *name,
                XmlRpc::XmlRpcValue &v, std::string &full)
{
  if (r == nullptr)
    return af_shim::invalid(nullptr, std::string(fn) + ": r is NULL");
  if (name == nullptr || name[0] == '\0')
    return af_shim::invalid(r, std::string(fn) + ": name is NULL or empty");
  const ros::NodeHandle &nh = private_ns ? *r->pnh : *r->nh;
  full = nh.resolveName(name);
  if (!nh.getParam(name, v)) {
    af_shim::set_error(r, "parameter '" + full + "' is not set");
    return AF_ENODATA;
  }
  return AF_OK;
}

af_status mismatch(const af_ros *r, const std::string &full, const XmlRpc::XmlRpcValue &v,
                   const char *expected)
{
  return af_shim::invalid(r, "parameter '" + full + "' is " + type_name(v.getType()) +
                                 ", expected " + expected);
}

af_status string_param(const af_ros *r, bool private_ns, const char *fn, const char *name,
                       char *buf, size_t len)
{
  if (buf == nullptr || len == 0)
    return af_shim::invalid(r, std::string(fn) + ": buf is NULL or len is 0");
  buf[0] = '\0';
  XmlRpc::XmlRpcValue v;
  std::string full;
  const af_status s = fetch(r, private_ns, fn, name, v, full);
  if (s != AF_OK)
    return s;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString)
    return mismatch(r, full, v, "a string");
  const std::string &value = static_cast<std::string &>(v);
  const size_t n = value.size() < len - 1 ? value.size() : len - 1;
  std::memcpy(buf, value.data(), n);
  buf[n] = '\0';
  if (value.size() > len - 1) {
    af_shim::set_error(r, "parameter '" + full + "' is " + std::to_string(value.size()) +
                              " bytes long, the buffer holds " + std::to_string(len - 1));
    return AF_ESIZE;
  }
  return AF_OK;
}

} // namespace

extern "C" {

af_status af_ros_param_double(const af_ros *r, const char *name, double *out)
{
  try {
    if (out == nullptr)
      return af_shim::invalid(r, "af_ros_param_double: out is NULL");
    XmlRpc::XmlRpcValue v;
    std::string full;
    const af_status s = fetch(r, true, "af_ros_param_double", name, v, full);
    if (s != AF_OK)
      return s;
    // YAML reads "1" as an int; a double parameter written without a decimal
    // point is still what the user meant.
    if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
      *out = static_cast<double &>(v);
    else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
      *out = static_cast<double>(static_cast<int &>(v));
    else
      return mismatch(r, full, v, "a double");
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

af_status af_ros_param_int(const af_ros *r, const char *name, int *out)
{
  try {
    if (out == nullptr)
      return af_shim::invalid(r, "af_ros_param_int: out is NULL");
    XmlRpc::XmlRpcValue v;
    std::string full;
    const af_status s = fetch(r, true, "af_ros_param_int", name, v, full);
    if (s != AF_OK)
      return s;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeInt)
      return mismatch(r, full, v, "an int");
    *out = static_cast<int &>(v);
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

af_status af_ros_param_set_int(af_ros *r, const char *name, int value)
{
  try {
    if (r == nullptr)
      return af_shim::invalid(nullptr, "af_ros_param_set_int: r is NULL");
    if (name == nullptr || name[0] == '\0')
      return af_shim::invalid(r, "af_ros_param_set_int: name is NULL or empty");
    r->pnh->setParam(name, value);
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

af_status af_ros_param_bool(const af_ros *r, const char *name, bool *out)
{
  try {
    if (out == nullptr)
      return af_shim::invalid(r, "af_ros_param_bool: out is NULL");
    XmlRpc::XmlRpcValue v;
    std::string full;
    const af_status s = fetch(r, true, "af_ros_param_bool", name, v, full);
    if (s != AF_OK)
      return s;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean)
      return mismatch(r, full, v, "a bool");
    *out = static_cast<bool &>(v);
    return AF_OK;
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

af_status af_ros_param_string(const af_ros *r, const char *name, char *buf, size_t len)
{
  try {
    return string_param(r, true, "af_ros_param_string", name, buf, len);
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

af_status af_ros_param_string_global(const af_ros *r, const char *name, char *buf, size_t len)
{
  try {
    return string_param(r, false, "af_ros_param_string_global", name, buf, len);
  } catch (...) {
    return af_shim::status_from_exception(r);
  }
}

size_t af_ros_param_string_bytes(const af_ros *r, const char *name, bool private_ns)
{
  try {
    XmlRpc::XmlRpcValue v;
    std::string full;
    if (fetch(r, private_ns, "af_ros_param_string_bytes", name, v, full) != AF_OK)
      return 0;
    if (v.getType() != XmlRpc::XmlRpcValue::TypeString) {
      mismatch(r, full, v, "a string");
      return 0;
    }
    return static_cast<std::string &>(v).size() + 1;
  } catch (...) {
    af_shim::status_from_exception(r);
    return 0;
  }
}

} // extern "C"
