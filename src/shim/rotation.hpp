// rotation.hpp — a unit quaternion as a row-major 3x3 rotation matrix, shared
// by the URDF reader (joint origins) and the tf lookup (transforms).
#ifndef AF_SHIM_ROTATION_HPP
#define AF_SHIM_ROTATION_HPP

namespace af_shim
{

// r[9] = R(q), row-major, for the unit quaternion (x, y, z, w).
inline void rotation_from_quaternion(double x, double y, double z, double w, double r[9])
{
  r[0] = 1 - 2 * (y * y + z * z);
  r[1] = 2 * (x * y - z * w);
  r[2] = 2 * (x * z + y * w);
  r[3] = 2 * (x * y + z * w);
  r[4] = 1 - 2 * (x * x + z * z);
  r[5] = 2 * (y * z - x * w);
  r[6] = 2 * (x * z - y * w);
  r[7] = 2 * (y * z + x * w);
  r[8] = 1 - 2 * (x * x + y * y);
}

} // namespace af_shim

#endif
