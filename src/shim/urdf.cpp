// urdf.cpp — the rig's URDF through urdfdom: the hammer's mass, tip and
// strike axis, and link frames composed down to the root.
#include "af_urdf.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include "rotation.hpp"

extern "C" {

struct af_urdf {
  urdf::ModelInterfaceSharedPtr model;
  // Joints that carry an <axis> element. urdfdom silently gives a joint
  // without one the axis (1, 0, 0), which for the hammer would be a
  // sideways strike; the XML is the only place the absence shows.
  std::set<std::string> joints_with_axis;
};

} // extern "C"

namespace
{

af_status fail(char *err, size_t err_len, af_status s, const std::string &msg)
{
  if (err != nullptr && err_len > 0)
    std::snprintf(err, err_len, "%s", msg.c_str());
  return s;
}

void clear_err(char *err, size_t err_len)
{
  if (err != nullptr && err_len > 0)
    err[0] = '\0';
}

// urdfdom reports why a parse failed only through console_bridge; while it
// parses, this handler keeps the first error for the caller's err instead of
// printing it (the shim never prints).
class FirstError : public console_bridge::OutputHandler
{
public:
  FirstError()
  {
    console_bridge::useOutputHandler(this);
  }
  ~FirstError() override
  {
    console_bridge::restorePreviousOutputHandler();
  }
  FirstError(const FirstError &) = delete;
  FirstError &operator=(const FirstError &) = delete;

  void log(const std::string &text, console_bridge::LogLevel level, const char *, int) override
  {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && first_.empty())
      first_ = text;
  }
  const std::string &first() const
  {
    return first_;
  }

private:
  std::string first_;
};

af_status parse(const std::string &xml, af_urdf **out, char *err, size_t err_len)
{
  TiXmlDocument doc;
  doc.Parse(xml.c_str());
  if (doc.Error()) {
    std::ostringstream msg;
    msg << "URDF is not well-formed XML: " << doc.ErrorDesc() << " (line " << doc.ErrorRow()
        << ", column " << doc.ErrorCol() << ")";
    return fail(err, err_len, AF_EINVAL, msg.str());
  }
  const TiXmlElement *robot = doc.FirstChildElement("robot");
  if (robot == nullptr)
    return fail(err, err_len, AF_EINVAL, "URDF has no <robot> element");

  std::unique_ptr<af_urdf> u(new af_urdf);
  for (const TiXmlElement *j = robot->FirstChildElement("joint"); j != nullptr;
       j = j->NextSiblingElement("joint")) {
    const char *name = j->Attribute("name");
    if (name != nullptr && j->FirstChildElement("axis") != nullptr)
      u->joints_with_axis.insert(name);
  }

  {
    FirstError errors;
    u->model = urdf::parseURDF(xml);
    if (!u->model) {
      const std::string why = errors.first().empty() ? "unknown reason" : errors.first();
      return fail(err, err_len, AF_EINVAL, "URDF rejected by urdfdom: " + why);
    }
  }
  *out = u.release();
  return AF_OK;
}

// A rigid transform: p_root = R p_link + t.
struct Transform {
  double r[9];
  double t[3];
};

void rotation_matrix(const urdf::Rotation &q, double r[9])
{
  af_shim::rotation_from_quaternion(q.x, q.y, q.z, q.w, r);
}

// f := joint * f, with joint the transform from the parent link to the
// joint's (= the child link's) frame at joint position zero.
void premultiply(const urdf::Pose &joint, Transform &f)
{
  double a[9];
  rotation_matrix(joint.rotation, a);
  const double jt[3] = {joint.position.x, joint.position.y, joint.position.z};
  Transform g;
  for (size_t i = 0; i < 3; i++) {
    for (size_t k = 0; k < 3; k++)
      g.r[3 * i + k] = a[3 * i] * f.r[k] + a[3 * i + 1] * f.r[3 + k] + a[3 * i + 2] * f.r[6 + k];
    g.t[i] = jt[i] + a[3 * i] * f.t[0] + a[3 * i + 1] * f.t[1] + a[3 * i + 2] * f.t[2];
  }
  f = g;
}

// The transform from link to the root, every movable joint at zero (only
// the joints' origins count). false when link is absent.
bool to_root(const urdf::ModelInterface &m, const std::string &link, Transform &f)
{
  urdf::LinkConstSharedPtr l = m.getLink(link);
  if (!l)
    return false;
  f = Transform{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
  // urdfdom has already refused cycles; the bound only guards the loop.
  for (size_t depth = 0; l->parent_joint && depth <= m.links_.size(); depth++) {
    premultiply(l->parent_joint->parent_to_joint_origin_transform, f);
    l = m.getLink(l->parent_joint->parent_link_name);
    if (!l)
      throw std::runtime_error("URDF joint refers to a missing parent link");
  }
  return true;
}

const char *joint_type_name(int type)
{
  switch (type) {
  case urdf::Joint::REVOLUTE: return "revolute";
  case urdf::Joint::CONTINUOUS: return "continuous";
  case urdf::Joint::PRISMATIC: return "prismatic";
  case urdf::Joint::FLOATING: return "floating";
  case urdf::Joint::PLANAR: return "planar";
  case urdf::Joint::FIXED: return "fixed";
  default: return "of unknown type";
  }
}

af_status hammer(const af_urdf &u, const std::string &name, af_hammer_geometry &out, char *err,
                 size_t err_len)
{
  const urdf::ModelInterface &m = *u.model;
  const std::string quoted = "URDF link '" + name + "'";
  urdf::LinkConstSharedPtr link = m.getLink(name);
  if (!link)
    return fail(err, err_len, AF_ENODATA, "URDF has no link '" + name + "' (the hammer)");

  if (!link->inertial)
    return fail(err, err_len, AF_ENODATA,
                quoted + " has no <inertial> (needed for the hammer mass)");
  const double mass = link->inertial->mass;
  if (!(mass > 0.0) || !std::isfinite(mass))
    return fail(err, err_len, AF_EINVAL,
                quoted + " has inertial mass " + std::to_string(mass) + " kg; it must be > 0");

  if (!link->collision || !link->collision->geometry)
    return fail(err, err_len, AF_ENODATA,
                quoted + " has no <collision> geometry (needed for the tip: a sphere for a "
                         "round tip, a box or cylinder for a flat face)");
  double tip_radius = 0.0;
  const urdf::Geometry &g = *link->collision->geometry;
  switch (g.type) {
  case urdf::Geometry::SPHERE:
    tip_radius = static_cast<const urdf::Sphere &>(g).radius;
    if (!(tip_radius > 0.0) || !std::isfinite(tip_radius))
      return fail(err, err_len, AF_EINVAL,
                  quoted + " has a collision sphere of radius " + std::to_string(tip_radius) +
                      " m; it must be > 0");
    break;
  case urdf::Geometry::BOX:
  case urdf::Geometry::CYLINDER: tip_radius = 0.0; break;
  case urdf::Geometry::MESH:
  default:
    return fail(err, err_len, AF_EINVAL,
                quoted + " has a mesh as collision geometry: unsupported geometry (use a sphere "
                         "for a round tip, a box or cylinder for a flat face)");
  }

  const urdf::JointConstSharedPtr joint = link->parent_joint;
  if (!joint)
    return fail(err, err_len, AF_ENODATA,
                quoted + " has no parent joint (its axis is the strike direction)");
  const std::string jquoted = "URDF joint '" + joint->name + "' (parent of link '" + name + "')";
  if (joint->type == urdf::Joint::FIXED || joint->type == urdf::Joint::FLOATING)
    return fail(err, err_len, AF_ENODATA,
                jquoted + " is " + joint_type_name(joint->type) +
                    " and has no axis (a prismatic joint's axis is the strike direction)");
  // A revolute joint's axis is the axis the hammer swings about, not the
  // direction it strikes in; taking it would aim the model sideways.
  if (joint->type != urdf::Joint::PRISMATIC)
    return fail(err, err_len, AF_EINVAL,
                jquoted + " is " + joint_type_name(joint->type) +
                    "; the strike direction needs a prismatic joint");
  if (u.joints_with_axis.count(joint->name) == 0)
    return fail(err, err_len, AF_ENODATA,
                jquoted + " has no <axis> (needed for the strike direction)");
  const double a[3] = {joint->axis.x, joint->axis.y, joint->axis.z};
  const double norm = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (!(norm > 0.0) || !std::isfinite(norm))
    return fail(err, err_len, AF_EINVAL, jquoted + " has a zero <axis>");

  // The axis is given in the joint frame, which is the hammer's own frame.
  Transform f;
  to_root(m, name, f);
  double axis[3];
  for (size_t i = 0; i < 3; i++)
    axis[i] = (f.r[3 * i] * a[0] + f.r[3 * i + 1] * a[1] + f.r[3 * i + 2] * a[2]) / norm;

  out.mass_kg = mass;
  out.tip_radius_m = tip_radius;
  out.strike_axis.x = axis[0];
  out.strike_axis.y = axis[1];
  out.strike_axis.z = axis[2];
  // The mount: the joint's own origin and axis in its parent link.
  double jr[9];
  rotation_matrix(joint->parent_to_joint_origin_transform.rotation, jr);
  out.mount_axis.x = (jr[0] * a[0] + jr[1] * a[1] + jr[2] * a[2]) / norm;
  out.mount_axis.y = (jr[3] * a[0] + jr[4] * a[1] + jr[5] * a[2]) / norm;
  out.mount_axis.z = (jr[6] * a[0] + jr[7] * a[1] + jr[8] * a[2]) / norm;
  const urdf::Vector3 &jp = joint->parent_to_joint_origin_transform.position;
  out.mount_origin_m.x = jp.x;
  out.mount_origin_m.y = jp.y;
  out.mount_origin_m.z = jp.z;
  const std::string &mount = joint->parent_link_name;
  const size_t nm = mount.size() < AF_FRAME_ID_MAX - 1 ? mount.size() : AF_FRAME_ID_MAX - 1;
  mount.copy(out.mount_frame, nm);
  out.mount_frame[nm] = '\0';
  const std::string &root = m.getRoot()->name;
  const size_t n = root.size() < AF_FRAME_ID_MAX - 1 ? root.size() : AF_FRAME_ID_MAX - 1;
  root.copy(out.root_frame, n);
  out.root_frame[n] = '\0';
  return AF_OK;
}

} // namespace

extern "C" {

af_status af_urdf_parse(const char *xml, af_urdf **out, char *err, size_t err_len)
{
  try {
    clear_err(err, err_len);
    if (out == nullptr)
      return fail(err, err_len, AF_EINVAL, "af_urdf_parse: out is NULL");
    *out = nullptr;
    if (xml == nullptr)
      return fail(err, err_len, AF_EINVAL, "af_urdf_parse: xml is NULL");
    return parse(xml, out, err, err_len);
  } catch (const std::bad_alloc &) {
    return fail(err, err_len, AF_ENOMEM, "out of memory while parsing the URDF");
  } catch (const std::exception &e) {
    return fail(err, err_len, AF_EINVAL, std::string("URDF: ") + e.what());
  } catch (...) {
    return fail(err, err_len, AF_EINVAL, "URDF: unknown C++ exception");
  }
}

af_status af_urdf_load(const char *path, af_urdf **out, char *err, size_t err_len)
{
  try {
    clear_err(err, err_len);
    if (out == nullptr)
      return fail(err, err_len, AF_EINVAL, "af_urdf_load: out is NULL");
    *out = nullptr;
    if (path == nullptr)
      return fail(err, err_len, AF_EINVAL, "af_urdf_load: path is NULL");
    // Read here rather than by urdf::parseURDFFile, so that a missing file
    // is AF_EIO with its name, distinct from a bad URDF.
    std::ifstream in(path, std::ios::binary);
    if (!in)
      return fail(err, err_len, AF_EIO, std::string("cannot read URDF file '") + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    const af_status s = parse(text.str(), out, err, err_len);
    if (s != AF_OK && err != nullptr && err_len > 0) {
      const std::string why = err;
      fail(err, err_len, s, std::string(path) + ": " + why);
    }
    return s;
  } catch (const std::bad_alloc &) {
    return fail(err, err_len, AF_ENOMEM, "out of memory while reading the URDF");
  } catch (const std::exception &e) {
    return fail(err, err_len, AF_EIO, std::string("URDF file: ") + e.what());
  } catch (...) {
    return fail(err, err_len, AF_EIO, "URDF file: unknown C++ exception");
  }
}

void af_urdf_destroy(af_urdf *u)
{
  delete u;
}

af_status af_urdf_hammer(const af_urdf *u, const char *hammer_link, af_hammer_geometry *out,
                         char *err, size_t err_len)
{
  try {
    clear_err(err, err_len);
    if (u == nullptr || hammer_link == nullptr || out == nullptr)
      return fail(err, err_len, AF_EINVAL, "af_urdf_hammer: u, hammer_link or out is NULL");
    return hammer(*u, hammer_link, *out, err, err_len);
  } catch (const std::bad_alloc &) {
    return fail(err, err_len, AF_ENOMEM, "out of memory while reading the hammer");
  } catch (const std::exception &e) {
    return fail(err, err_len, AF_EINVAL, std::string("URDF hammer: ") + e.what());
  } catch (...) {
    return fail(err, err_len, AF_EINVAL, "URDF hammer: unknown C++ exception");
  }
}

af_status af_urdf_rotation_to_root(const af_urdf *u, const char *link, double r[9])
{
  try {
    if (u == nullptr || link == nullptr || r == nullptr)
      return AF_EINVAL;
    Transform f;
    if (!to_root(*u->model, link, f))
      return AF_ENODATA;
    for (int i = 0; i < 9; i++)
      r[i] = f.r[i];
    return AF_OK;
  } catch (const std::bad_alloc &) {
    return AF_ENOMEM;
  } catch (...) {
    return AF_EINVAL;
  }
}

af_status af_urdf_position_in_root(const af_urdf *u, const char *link, af_vec3 *p)
{
  try {
    if (u == nullptr || link == nullptr || p == nullptr)
      return AF_EINVAL;
    Transform f;
    if (!to_root(*u->model, link, f))
      return AF_ENODATA;
    p->x = f.t[0];
    p->y = f.t[1];
    p->z = f.t[2];
    return AF_OK;
  } catch (const std::bad_alloc &) {
    return AF_ENOMEM;
  } catch (...) {
    return AF_EINVAL;
  }
}

} // extern "C"
