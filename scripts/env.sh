# Sourced by the other scripts: where the package and its build live, and the
# ROS environment of the build's devel space.
AF_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
AF_BUILD=${AF_BUILD_DIR:-$AF_ROOT/build}
# A pyenv python3 first in PATH breaks catkin and rostest: Debian's ROS is
# built for /usr/bin/python3.
export PATH=/usr/bin:$PATH
af_source_devel() {
  # shellcheck disable=SC1091
  set +u
  source "$AF_BUILD/devel/setup.bash"
  set -u
}
